// The structure coupling component: the primary structure's state (StructureState) and how the
// cavity rides on it and loads it: where it is held while the contents settle, whether it feels
// the contents, the cavity's axis and direction on it, the load moments of this step. Its stage:
// structure (structure.cpp).
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "bagdem/step/samples.hpp"
#include "bagdem/vec3.hpp"

namespace bagdem {

struct StructureCoupling : StructureState {
  Eigen::VectorXd q_hold;                   // where the structure is held while the contents settle
  struct {
    Eigen::VectorXd load, damping, total;   // scratch of structure_forces (Q_contents, C v, Q)
  } scratch;
  bool couple = false;                      // a primary structure feels the contents' load
  bool tilt = false;                        // the cavity follows the beam's slope too (motion_at)
  double tilt_extent = 0;                   // half the cavity's axial extent (unit: m)
  Vec3 load_axis = Vec3::Zero(), load_dir = Vec3::Zero();  // its axis and transverse direction
  std::vector<Vec3> cavity_load;            // per ball: load moments on the cavity this step
  Vec3 film_load_moments = Vec3::Zero();    // the film's (walls and strings) this step
  std::uint64_t release_step = 0;           // the step at which settling ends
  // Its checkpoint fields (step/checkpoint.cpp): one list for writing and reading, so the two
  // cannot disagree. IO: pod(x) and vec(v).
  // Empty vectors without a structure.
  template <class IO>
  void checkpoint(IO& io) {
    io.vec(q), io.vec(v), io.vec(v_pred), io.vec(a), io.vec(damping_prev), io.vec(load_prev);
    auto& c = scalars;  // field by field: the struct's padding bytes would make images differ
    io.pod(c.phase), io.pod(c.omega), io.pod(c.force), io.pod(c.released), io.pod(c.work_external);
    io.pod(c.work_contents), io.pod(c.dissipated);
    io.pod(load_now);
    io.vec(cavity_load), io.pod(film_load_moments);
  }
};

}  // namespace bagdem
