// The cavity track component: the cavity's state now and at the last step, its sums over the
// current sample, and where it was at the last neighbour build. Its stage: move_cavity
// (cavity_track.cpp; on the structure, StructureCoupling::cavity).
#pragma once
#include <cstdint>

#include "bagdem/motion/motion.hpp"
#include "bagdem/vec3.hpp"

namespace bagdem {

struct Neighbours;
struct Scene;
struct StructureCoupling;

struct CavityTrack {
  CavityState now, prev;
  // Sums over the steps of the current cavity sample (Stepper::take_cavity_sample).
  struct Sums {
    std::uint64_t steps = 0;
    double time = 0;                 // sum of step times (unit: s)
    Vec3 position = Vec3::Zero();    // (unit: m)
    Vec3 velocity = Vec3::Zero();    // (unit: m/s)
  } sums;
  Vec3 pos_at_build = Vec3::Zero();  // position and shear at the last neighbour build
  Vec3 shear_at_build = Vec3::Zero();
  // The cavity at time t is c: the last state becomes prev, and the sample's sums take c.
  void move_to(double t, const CavityState& c) {
    prev = now;
    now = c;
    ++sums.steps;
    sums.time += t;
    sums.position += now.position;
    sums.velocity += now.velocity;
  }
  // How far a point of the cavity moved since the last build, at most (a slope moves a point at
  // most |d shear| `extent` further; extent: half the cavity's axial extent, 0 without a slope).
  double moved_since_build(double extent) const {
    return (now.position - pos_at_build).norm() + (extent > 0 ? (now.shear - shear_at_build).norm() * extent : 0.0);
  }
  // Its checkpoint fields (step/checkpoint.cpp): one list for writing and reading, so the two
  // cannot disagree. IO: pod(x) and vec(v).
  template <class IO>
  void checkpoint(IO& io) {
    io.pod(now), io.pod(prev), io.pod(sums), io.pod(pos_at_build), io.pod(shear_at_build);
  }
};

// The cavity's state at time t: on the structure when one carries it, else the scene's prescribed
// motion (held where it starts while the contents settle).
CavityState cavity_at(const Scene& scene, const StructureCoupling& structure, double t);

// What the move_cavity stage works on: the scene, the steps done before this one, the cavity, the
// structure that carries it, and the neighbours (whose walls' lists it may end).
struct CavityStage {
  const Scene& scene;
  std::uint64_t steps_done;
  CavityTrack& cavity;
  const StructureCoupling& structure;
  Neighbours& nb;
};
// The move_cavity stage (stage.hpp): the cavity at this step's end.
void move_cavity_stage(const CavityStage& s);

}  // namespace bagdem
