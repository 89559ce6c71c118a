// The force the contents exert on the cavity (docs/reference-study.md, section 5): every wall contact force,
// no gravity, recorded as the mean over each sample interval (impulse / interval).
#include <gtest/gtest.h>

#include <cmath>

#include "bagdem/step/simulation.hpp"
#include "scene_builder.hpp"

using namespace bagdem;
using namespace bagdem::testing;

TEST(CavityLoad, RestingBallWeighsOnTheFloor) {
  // A ball settled on the floor of a fixed box pushes down with its weight m g (reference: statics),
  // to 1e-9 once the bounce has died out.
  const double r = 2e-3, rho = 7800;
  SceneBuilder b;
  b.material("steel", rho, 200e9, 0.3).interaction(0.1, 0.3).box(Vec3(-0.01, -0.01, 0), Vec3(0.01, 0.01, 0.02));
  b.particle(Vec3(0, 0, r), Vec3::Zero(), r).gravity(Vec3(0, 0, -9.81)).dt(2e-7);
  const Scene s = b.build();
  Simulation sim(s);
  for (int k = 0; k < 200000; ++k) sim.step();
  sim.take_cavity_sample();  // discard the transient
  for (int k = 0; k < 10000; ++k) sim.step();
  const Vec3 F = sim.take_cavity_sample().force;
  const double weight = sphere_mass(rho, r) * 9.81;
  EXPECT_NEAR(F.z(), -weight, 1e-9 * weight);
  EXPECT_NEAR(F.x(), 0.0, 1e-12 * weight);
}

TEST(CavityLoad, SampleKinematicsAreIntervalMeans) {
  // A box shaken as X sin(w t): the sample's position is the mean of the step-end positions over
  // the interval, and its time their mean time, so force and kinematics share one time base.
  // Reference: the same means computed here from the motion (to rounding).
  SceneBuilder b;
  b.material("steel", 7800, 200e9, 0.3).interaction(0.5).box(Vec3(0, 0, 0), Vec3(0.02, 0.02, 0.02));
  b.particle(Vec3(0.01, 0.01, 0.01), Vec3::Zero(), 2e-3).dt(1e-6);
  const std::shared_ptr<const Motion> motion = make_harmonic_motion(1e-3, 30, Vec3::UnitX(), 0);
  b.motion(motion);
  const Scene s = b.build();
  Simulation sim(s);
  double t_sum = 0, x_sum = 0;
  for (int k = 1; k <= 1000; ++k) {
    sim.step();
    t_sum += sim.time();
    x_sum += motion->at(sim.time()).position.x();
  }
  const CavitySample c = sim.take_cavity_sample();
  EXPECT_NEAR(c.time, t_sum / 1000, 1e-15);
  EXPECT_NEAR(c.position.x(), x_sum / 1000, 1e-15);
  EXPECT_NEAR(c.time, 500.5e-6, 1e-12);  // mean of 1..1000 us
}

TEST(CavityLoad, ImpulseMatchesTheMomentumTheContentsGained) {
  // Balls rattling in a box shaken at Gamma = 3.6: over the run, the impulse the cavity received
  // (sum of mean force x interval) equals minus the contents' momentum change net of gravity,
  // -(P_end - P_0 - M g T), up to velocity Verlet's end terms dt/2 (F_0 - F_end), i.e. ~1e-6 of the
  // impulse scale M g T. An instantaneous sample of the force would miss the impacts entirely.
  SceneBuilder b;
  b.material("steel", 7800, 200e9, 0.3).interaction(0.5, 0.3).box(Vec3(0, 0, 0), Vec3(0.021, 0.021, 0.048));
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 2; ++k)
        b.particle(Vec3(0.003 + 0.005 * i, 0.003 + 0.005 * j, 0.003 + 0.005 * k), Vec3::Zero(), 2e-3);
  b.gravity(Vec3(0, 0, -9.81)).dt(2e-7).motion(make_harmonic_motion(1e-3, 30, Vec3::UnitX(), 0));
  const Scene s = b.build();
  Simulation sim(s);
  auto momentum = [&] {
    Vec3 P(0, 0, 0);
    for (std::size_t i = 0; i < sim.particles().size(); ++i) P += sim.particles().mass[i] * sim.particles().v[i];
    return P;
  };
  double M = 0;
  for (double m : sim.particles().mass) M += m;
  const Vec3 P0 = momentum();
  Vec3 J(0, 0, 0);
  double peak = 0;
  const int steps = 150000, every = 500;  // 30 ms = 0.9 period, samples of 0.1 ms
  for (int k = 1; k <= steps; ++k) {
    sim.step();
    if (k % every == 0) {
      const Vec3 F = sim.take_cavity_sample().force;
      J += F * (every * s.dt);
      peak = std::max(peak, F.norm());
    }
  }
  const Vec3 expected = -(momentum() - P0 - M * s.gravity * sim.time());
  const double scale = M * 9.81 * sim.time();
  EXPECT_LT((J - expected).norm(), 1e-6 * scale) << "J = " << J.transpose() << ", expected " << expected.transpose();
  EXPECT_GT(peak, 2 * M * 9.81);  // the balls really hit the walls harder than their weight
}
