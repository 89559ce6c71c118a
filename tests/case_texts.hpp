// Test support: case texts several suites share.
#pragma once
#include <string>

namespace bagdem::testing {

// 30 soft rubber balls (6 mm) with friction in a 40 x 40 x 50 mm box shaken at 2 mm, 25 Hz along
// (1, 0, 1), gravity, a settle of 0.02 s, for `duration`; frames every 5 ms, and checkpoints every
// `checkpoint_interval` when one is given (~1.3e-5 s steps).
inline std::string shaken_box(const std::string& duration, const std::string& checkpoint_interval = "") {
  return R"([simulation]
duration = ")" + duration + R"("
settle = "0.02 s"
gravity = [0, 0, "-9.81 m/s^2"]

[materials.rubber]
density = "1200 kg/m^3"
youngs_modulus = "5 MPa"
poisson_ratio = 0.45

[interactions.default]
restitution = 0.6
friction = 0.4

[cavity]
kind = "box"
material = "rubber"
min = [0, 0, 0]
max = ["40 mm", "40 mm", "50 mm"]

[cavity.motion]
kind = "harmonic"
amplitude = "2 mm"
frequency = "25 Hz"
direction = [1, 0, 1]

[particles.balls]
material = "rubber"
diameter = "6 mm"
count = 30
fill = "random"
seed = 7

[output]
frame_interval = "5 ms"
)" + (checkpoint_interval.empty() ? std::string() : "checkpoint_interval = \"" + checkpoint_interval + "\"\n");
}

}  // namespace bagdem::testing
