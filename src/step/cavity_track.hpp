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
  // Its checkpoint fields (step/checkpoint.cpp): one list for writing and reading, so the two
  // cannot disagree. IO: pod(x) and vec(v).
  template <class IO>
  void checkpoint(IO& io) {
    io.pod(now), io.pod(prev), io.pod(sums), io.pod(pos_at_build), io.pod(shear_at_build);
  }
};

}  // namespace bagdem
