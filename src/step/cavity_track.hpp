// The cavity track component: the cavity's state now and at the last step, its sums over the
// current sample, and where it was at the last neighbour build. Its stage: move_cavity
// (stepper.cpp; from the structure: structure.cpp).
#pragma once
#include <cstdint>

#include "bagdem/motion/motion.hpp"
#include "bagdem/vec3.hpp"

namespace bagdem {

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

}  // namespace bagdem
