// The move_cavity stage (stage.hpp): the cavity's position and velocity at the end of the step.
#include "cavity_track.hpp"

#include "bagdem/scene.hpp"
#include "neighbours.hpp"
#include "structure_coupling.hpp"

namespace bagdem {

CavityState cavity_at(const Scene& scene, const StructureCoupling& structure, double t) {
  if (structure.couple) return structure.cavity(*scene.primary);
  if (t < scene.settle) return {scene.motion->at(0.0).position, Vec3::Zero()};
  return scene.motion->at(t - scene.settle);
}

void move_cavity_stage(const CavityStage& s) {
  const double t = static_cast<double>(s.steps_done + 1) * s.scene.dt;
  s.cavity.move_to(t, cavity_at(s.scene, s.structure, t));
  // The walls' candidates (WallContacts::near) hold while the cavity moved at most skin/2 since
  // the last build.
  if (s.cavity.moved_since_build(s.structure.tilt ? s.structure.tilt_extent : 0.0) > 0.5 * s.scene.skin) s.nb.needs_rebuild = true;
}

}  // namespace bagdem
