// The balls component: their state (Particles: positions, velocities, forces, ...) in the
// stepper's order, that order, and their tallies. Its stages: kick_drift and kick (balls.cpp).
#pragma once
#include <cstdint>
#include <vector>

#include "bagdem/particles.hpp"

namespace bagdem {

struct Balls : Particles {
  std::vector<std::uint32_t> order;  // per ball: its index in scene.particles (Stepper::input_index)
  ParticleTallies tally;             // per ball: this step's dissipation and the running totals
  bool uniform = false;              // all balls of one radius and one material
  // Its checkpoint fields (step/checkpoint.cpp): one list for writing and reading, so the two
  // cannot disagree. IO: pod(x) and vec(v).
  template <class IO>
  void checkpoint(IO& io) {
    io.vec(x), io.vec(v), io.vec(w), io.vec(v_pred), io.vec(w_pred), io.vec(f), io.vec(t);
    io.vec(tally.wall_force_prev), io.vec(tally.wall_impulse), io.vec(tally.wall_ang_impulse), io.vec(tally.work_cavity);
    io.vec(tally.diss_normal), io.vec(tally.diss_tangential), io.vec(tally.diss_rolling);
  }
};

}  // namespace bagdem
