// Balls at rest under gravity: the Hertz overlap where the elastic force carries the weight.
//
// References and tolerances:
//   ball on a plane:  delta = hertz::static_overlap(m g, R, E*_wall)          within 0.1 % relative
//   column of two:    wall - lower ball: static_overlap(2 m g, R, E*_wall)     within 0.1 % relative
//                     lower - upper ball: static_overlap(m g, R/2, E*_pair)    within 0.1 % relative
// E* from effective_youngs (the same as make_pair_laws uses; the wall has the balls' material).
// The balls start touching at rest (zero overlap) with e = 0.3; the damped oscillation about the
// static overlap (linearised frequency w0 = sqrt(1.5 g / delta_static)) is followed for 40 periods,
// 60 steps each, and the overlap is checked over the whole last period (not only at one instant).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "bagdem/contact/hertz_theory.hpp"
#include "bagdem/step/simulation.hpp"
#include "scene_builder.hpp"

using namespace bagdem;
using bagdem::testing::SceneBuilder;
using bagdem::testing::sphere_mass;

namespace {

constexpr double kRho = 7800, kE = 200e9, kNu = 0.3, kR = 5e-3, kG = 9.81;
constexpr int kPeriods = 40, kStepsPerPeriod = 60;

double wall_E_star() {
  const Material steel{"steel", kRho, kE, kNu};
  return effective_youngs(steel, steel);
}

}  // namespace

TEST(StaticOverlap, BallOnPlaneSettlesToHertzOverlap) {
  const double m = sphere_mass(kRho, kR);
  const double delta_s = hertz::static_overlap(m * kG, kR, wall_E_star());
  const double period = 2 * std::numbers::pi / std::sqrt(1.5 * kG / delta_s);
  const double dt = period / kStepsPerPeriod;
  Scene scene = SceneBuilder()
                    .material("steel", kRho, kE, kNu)
                    .interaction(0.3, 0.0, 0.0)
                    .plane(Vec3(0, 0, 0), Vec3(0, 0, 1))
                    .particle(Vec3(0, 0, kR), Vec3::Zero(), kR)
                    .gravity(Vec3(0, 0, -kG))
                    .dt(dt)
                    .build();
  Simulation sim(scene);
  const auto& p = sim.particles();
  double worst_last = 0, peak = 0;
  for (int s = 0; s < kPeriods * kStepsPerPeriod; ++s) {
    sim.step();
    const double delta = kR - p.x[0].z();
    peak = std::max(peak, delta);
    if (s >= (kPeriods - 1) * kStepsPerPeriod) worst_last = std::max(worst_last, std::abs(delta / delta_s - 1));
  }
  std::printf("  ball on plane: delta_static %.4e m, first peak %.3f delta_static, last-period |err| %.2e\n",
              delta_s, peak / delta_s, worst_last);
  EXPECT_GT(peak, 1.1 * delta_s);  // it did oscillate: the check is on the settled state, not the start
  EXPECT_LT(worst_last, 1e-3);
}

TEST(StaticOverlap, TwoBallColumnSettlesToHertzOverlaps) {
  const double m = sphere_mass(kRho, kR);
  const double E_star = wall_E_star();  // the pair and the wall have the same E* (one material)
  const double d_wall = hertz::static_overlap(2 * m * kG, kR, E_star);
  const double d_pair = hertz::static_overlap(m * kG, 0.5 * kR, E_star);
  // The faster mode of the pair of contacts sets the step; the slower one the settling time.
  const double w_fast = std::sqrt(1.5 * kG / std::min(d_wall, d_pair) * 4);
  const double dt = 2 * std::numbers::pi / w_fast / kStepsPerPeriod;
  const int steps = static_cast<int>(4 * kPeriods * kStepsPerPeriod);
  Scene scene = SceneBuilder()
                    .material("steel", kRho, kE, kNu)
                    .interaction(0.3, 0.0, 0.0)
                    .plane(Vec3(0, 0, 0), Vec3(0, 0, 1))
                    .particle(Vec3(0, 0, kR), Vec3::Zero(), kR)
                    .particle(Vec3(0, 0, 3 * kR), Vec3::Zero(), kR)
                    .gravity(Vec3(0, 0, -kG))
                    .dt(dt)
                    .build();
  Simulation sim(scene);
  const auto& p = sim.particles();
  double worst_wall = 0, worst_pair = 0;
  for (int s = 0; s < steps; ++s) {
    sim.step();
    if (s < steps - 4 * kStepsPerPeriod) continue;
    worst_wall = std::max(worst_wall, std::abs((kR - p.x[0].z()) / d_wall - 1));
    worst_pair = std::max(worst_pair, std::abs((2 * kR - (p.x[1] - p.x[0]).norm()) / d_pair - 1));
  }
  std::printf("  column: wall overlap %.4e m |err| %.2e, pair overlap %.4e m |err| %.2e\n", d_wall, worst_wall,
              d_pair, worst_pair);
  EXPECT_LT(worst_wall, 1e-3);
  EXPECT_LT(worst_pair, 1e-3);
}
