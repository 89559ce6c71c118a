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
};

}  // namespace bagdem
