// The cavity's frame over the step in progress, as a stage sees it: a view of the cavity track
// (where the cavity is, now and at the last step) and of the structure coupling (its slope, its
// axis), with the step's context. What it answers: how the walls move at a lab point over the step
// (WallMotion, stage.hpp), and the moments of a load the contents put on the cavity.
#pragma once
#include "bagdem/scene.hpp"
#include "cavity_track.hpp"
#include "stage.hpp"
#include "structure_coupling.hpp"

namespace bagdem {

struct CavityFrame {
  const Scene& scene;
  const StepContext& ctx;
  const CavityTrack& cavity;
  const StructureCoupling& structure;

  // The rigid motion from `prev` to `now`: the same for every point.
  WallMotion rigid(const CavityState& prev, const CavityState& now) const {
    const Vec3 step = now.position - prev.position;
    return {now.position, now.velocity, ctx.stepping() ? Vec3(step / ctx.dt) : now.velocity, step};
  }
  WallMotion rigid() const { return rigid(cavity.prev, cavity.now); }
  // At a lab point x: without a slope the rigid motion; with one, each adds shear * s (s: the
  // point's axial coordinate from the cavity reference).
  WallMotion at(const Vec3& x) const {
    WallMotion m = rigid();
    if (!structure.tilt) return m;
    const double s = (x - cavity.now.position - scene.cavity_reference).dot(structure.load_axis);
    m.pos += s * cavity.now.shear;
    m.vel += s * cavity.now.shear_rate;
    m.step += s * (cavity.now.shear - cavity.prev.shear);
    if (ctx.stepping()) m.half = m.step / ctx.dt;
    return m;
  }
  // Moments (f, f s, f s^2) of the transverse force f = F . e the contents put on the cavity at
  // `local` (cavity frame), s its axial distance from the cavity reference (structure/primary.hpp).
  Vec3 load_moments(const Vec3& local, const Vec3& force_on_cavity) const {
    const double s = (local - scene.cavity_reference).dot(structure.load_axis), f = force_on_cavity.dot(structure.load_dir);
    return {f, f * s, f * s * s};
  }
};

}  // namespace bagdem
