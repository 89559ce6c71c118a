// The balls component: their state (Particles: positions, velocities, forces, ...) in the
// stepper's order, that order, and their tallies. Its stages: kick_drift and kick (balls.cpp), free
// functions of the views below.
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

#include "bagdem/contact/geometry.hpp"
#include "bagdem/particles.hpp"

namespace bagdem {

class SpanBalance;
struct Film;
struct GuardValues;
struct Neighbours;
struct Scene;
struct StageFold;
struct StepContext;
struct StructureCoupling;
struct SurfaceContacts;

struct Balls : Particles {
  std::vector<std::uint32_t> order;  // per ball: its index in scene.particles (Stepper::input_index)
  ParticleTallies tally;             // per ball: this step's dissipation and the running totals
  bool uniform = false;              // all balls of one radius and one material
  // The kick for ball i, with its force F and torque T: v += h F/m, w += h T/I (h = dt/2). Returns
  // whether the new velocity is finite.
  BAGDEM_INLINE bool kick(std::size_t i, const Vec3& F, const Vec3& T, double h, bool rotation) {
    const Vec3 vi = v[i] + h * inv_mass[i] * F;
    v[i] = vi;
    if (rotation) w[i] += h * inv_inertia[i] * T;
    return std::isfinite(vi.squaredNorm());
  }
  // Ball p's motion relative to a point of a surface (a wall, an STL wall, the film) that moves at
  // v_end at the end of the step and at v_half over it: g.v_rel, g.v_half and g.w_half, from g.n,
  // g.arm_i and g.arm_j. Spin: the tangential or rolling role is modelled (else the centre's alone).
  template <bool Spin>
  BAGDEM_INLINE void motion_against_surface(std::size_t p, const Vec3& v_end, const Vec3& v_half, ContactGeometry& g) const {
    if constexpr (Spin) {
      g.v_rel = contact_velocity(v_pred[p], v_end, w_pred[p], Vec3::Zero(), g);
      g.v_half = contact_velocity(v[p], v_half, w[p], Vec3::Zero(), g);
      g.w_half = w[p];
    } else {
      g.v_rel = v_pred[p] - v_end;
      g.v_half = v[p] - v_half;
      g.w_half.setZero();
    }
  }
  // Its checkpoint fields (step/checkpoint.cpp): one list for writing and reading, so the two
  // cannot disagree. IO: pod(x) and vec(v).
  template <class IO>
  void checkpoint(IO& io) {
    io.vec(x), io.vec(v), io.vec(w), io.vec(v_pred), io.vec(w_pred), io.vec(f), io.vec(t);
    io.vec(tally.wall_force_prev), io.vec(tally.wall_impulse), io.vec(tally.wall_ang_impulse), io.vec(tally.work_cavity);
    io.vec(tally.diss_normal), io.vec(tally.diss_tangential), io.vec(tally.diss_rolling);
  }
};

// What the kick_drift stage works on: the step (its kick state moves on), the scene, the balls on
// the threads' spans (balance), the film's nodes and the structure (their drift), the neighbours'
// travel and the surfaces' (the balls' and the nodes' largest steps), the guards' values.
struct DriftStage {
  StepContext& ctx;
  const Scene& scene;
  Balls& balls;
  SpanBalance& balance;
  Neighbours& nb;
  Film& film;
  SurfaceContacts& surfaces;
  StructureCoupling& structure;
  GuardValues& guard;
};
// The kick_drift stage (stage.hpp): velocity Verlet's first half-kick and drift (and, pending, the
// last step's second half-kick first).
void kick_drift_stage(const DriftStage& s);
// A drift's folds over the balls into the guards' values and the neighbours' travel.
void end_drift(const StageFold& fold, const Balls& balls, double skin, Neighbours& nb, GuardValues& guard);

// What the kick stage works on: as the drift's, and whether the wall stage already kicked the balls
// (no triangulated surface adds to their forces after it).
struct KickStage {
  StepContext& ctx;
  const Scene& scene;
  Balls& balls;
  SpanBalance& balance;
  Film& film;
  StructureCoupling& structure;
  GuardValues& guard;
  bool kicked_in_walls;
};
// The kick stage (stage.hpp): velocity Verlet's second half-kick, and whether every velocity is finite.
void kick_stage(const KickStage& s);

}  // namespace bagdem
