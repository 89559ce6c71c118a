// The structure coupling component: the primary structure's state (StructureState) and how the
// cavity rides on it and loads it: where it is held while the contents settle, whether it feels
// the contents, the cavity's axis and direction on it, the load moments of this step. Its part of
// each stage is a member here taking the primary and the step's context; its stage, structure_stage
// (structure.cpp), is a free function of them.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "bagdem/step/samples.hpp"
#include "bagdem/structure/primary.hpp"
#include "stage.hpp"
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
  // Several dampers on the structure (step/dampers.hpp): the generalized load of them all this step,
  // which the structure feels instead of this damper's alone (null: one damper); and this damper's.
  const Eigen::VectorXd* all_load = nullptr;
  Eigen::VectorXd own_load;

  // Sizes the state for P (`balls` load slots), held where it is released from.
  void set_up(const Primary& P, std::size_t balls);
  // Settling is over: the structure starts moving (structure.cpp).
  void release(const Primary& P);
  // kick_drift's part: v += dt/2 a, q += dt v, v_pred = v + dt/2 a. kick's: v += dt/2 a.
  void drift(double dt);
  void kick(double dt);
  // This damper's generalized load G m of the load moments of this step, into own_load.
  const Eigen::VectorXd& damper_load(const Primary& P);
  // The cavity's state on the structure (move_cavity).
  CavityState cavity(const Primary& P) const;
  // The structure stage's work: the contents' load of this step (the balls' and the film's), the
  // external force at `t` (since release), the acceleration; tallied when ctx is a step.
  void forces(const Primary& P, const StepContext& ctx, double t);
  // a from the present state, the contents' load of the last step and the force at t (set-up mode:
  // nothing is tallied and the previous-step values restart from here).
  void restart_acceleration(const Primary& P, double t);
  // A harmonic drive's new frequency from the next step on; t as restart_acceleration's.
  void set_drive_frequency(const Primary& P, double hz, double t);
  double energy(const Primary& P) const;  // kinetic + elastic (unit: J)
  StructureResponse response(const Primary& P) const;
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

// The structure stage (stage.hpp): the structure's forces and acceleration of this step, t the
// time since release at the step's end (StructureCoupling::forces).
void structure_stage(const StepContext& ctx, const Primary& P, double t, StructureCoupling& structure);

}  // namespace bagdem
