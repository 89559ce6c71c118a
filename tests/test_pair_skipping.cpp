// The pair stage looks only at the candidate pairs that may touch (PairState::wake): a pair found
// apart by a gap g sleeps until the balls have travelled g/2 between them. Skipping must never
// miss a contact: after every step, each candidate pair is marked touching exactly when its
// spheres overlap (spheres_apart, the one test of contact). A gas of fast balls colliding head on
// (where g/2, not g, is the bound) on one thread and on two (the cross pairs' own stage).
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "bagdem/parallel.hpp"
#include "bagdem/contact/geometry.hpp"
#include "bagdem/error.hpp"
#include "bagdem/step/simulation.hpp"
#include "step/stepper.hpp"
#include "rng.hpp"
#include "scene_builder.hpp"

using namespace bagdem;
using bagdem::testing::Rng;
using bagdem::testing::SceneBuilder;

namespace {

// n steel balls of radius r (a third of them 1.5 r) on a jittered lattice of spacing 2.6 r in a
// closed box, no gravity, speeds of about `speed` in random directions.
Scene gas(int per_side, double r, double speed, std::uint64_t seed) {
  Rng rng(seed);
  SceneBuilder b;
  b.material("steel", 7800, 2e11, 0.3).interaction(0.9, 0.3);
  const double a = 3.2 * r, side = per_side * a;
  b.box(Vec3::Zero(), Vec3::Constant(side));
  int count = 0;
  for (int i = 0; i < per_side; ++i)
    for (int j = 0; j < per_side; ++j)
      for (int k = 0; k < per_side; ++k, ++count) {
        const Vec3 x = (Vec3(i, j, k) + Vec3::Constant(0.5)) * a + 0.1 * r * draw_vec3([&] { return rng.uniform(-1, 1); });
        b.particle(x, speed * rng.uniform(0.2, 1.0) * rng.unit(), count % 3 == 0 ? 1.5 * r : r);
      }
  return b.dt(1e-7).duration(1500 * 1e-7).build();
}

struct Tally {
  std::size_t steps = 0, contacts = 0, missed = 0, phantom = 0;
};

// Runs s on `threads` threads and compares, after each step, every candidate pair's touching flag
// with the overlap of its spheres now.
Tally run_and_check(const Scene& s, int threads) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  Stepper sim(s);  // the stepper itself: the test reads its pair list
  sim.set_parallel_balls(kParallelMin);  // the parallel ball stages on this small scene
  Tally t;
  while (sim.steps_done() < s.total_steps()) {
    sim.step();
    ++t.steps;
    const PairState& ps = sim.pair_state();
    const Particles& p = sim.particles();
    for (std::size_t k = 0; k < ps.pairs.size(); ++k) {
      const std::uint32_t i = ps.first[k], j = ps.pairs.partner[k];
      const bool overlap = !spheres_apart(p.x[i], p.x[j], p.radius[i] + p.radius[j]);
      t.contacts += overlap;
      t.missed += overlap && ps.touching[k] == 0;
      t.phantom += !overlap && ps.touching[k] != 0;
    }
  }
  omp_set_num_threads(before);
  return t;
}

}  // namespace

// 729 balls (11 664 candidate-pair checks a step at the start), 1500 steps at 1e-7 s; at 3 m/s
// a head-on pair closes 6e-7 m a step. Tolerance: no missed and no phantom contact in any step.
TEST(PairSkipping, NoContactMissedOnOneOrTwoThreads) {
  const Scene s = gas(9, 1e-3, 3.0, 7);
  for (int threads : {1, 2}) {
    const Tally t = run_and_check(s, threads);
    EXPECT_EQ(t.steps, s.total_steps());
    EXPECT_GT(t.contacts, 5000u) << "the gas must collide for the test to mean anything";
    EXPECT_EQ(t.missed, 0u) << threads << " threads: overlapping pairs the pair stage did not see";
    EXPECT_EQ(t.phantom, 0u) << threads << " threads";
  }
}

// The neighbour list is renewed one step ahead (Simulation::kSkinStep): before a step's pairs
// exactly when a ball ended the step before more than skin/2 - kSkinStep x skin from where it was
// at the last build; so at no step's pairs is a ball more than skin/2 from there. The stepper does
// not measure that distance at every step (Stepper::near_skin_edge: only once travel could
// have taken a ball that far); this test does, after every step, from the positions at the last
// build it saw. The gas at 3 m/s with a skin of 20 um rebuilds every few dozen steps; tolerance:
// the same decision at every one of the 1500 steps, and no ball ever beyond skin/2.
TEST(PairSkipping, RebuildsExactlyWhenABallNearedTheSkinsEdge) {
  Scene s = gas(9, 1e-3, 3.0, 11);
  s.skin = 2e-5;
  const double edge = (0.5 - Simulation::kSkinStep) * s.skin;
  for (int threads : {1, 2}) {
    const int before = omp_get_max_threads();
    omp_set_num_threads(threads);
    Simulation sim(s);
    sim.set_parallel_balls(kParallelMin);
    std::vector<Vec3> at_build = sim.particles().x;
    std::uint64_t builds = sim.neighbour_builds(), rebuilds = 0, wrong = 0, beyond = 0;
    double last_d2 = 0, farthest = 0;
    while (sim.steps_done() < s.total_steps()) {
      sim.step();  // its pairs at the positions it ends with
      const std::vector<Vec3>& x = sim.particles().x;
      const bool expected = last_d2 > edge * edge, rebuilt = sim.neighbour_builds() != builds;
      wrong += expected != rebuilt;
      if (rebuilt) at_build = x, builds = sim.neighbour_builds(), ++rebuilds;
      double d2 = 0;
      for (std::size_t i = 0; i < x.size(); ++i) d2 = std::max(d2, (x[i] - at_build[i]).squaredNorm());
      beyond += d2 > 0.25 * s.skin * s.skin;
      farthest = std::max(farthest, std::sqrt(d2));
      last_d2 = d2;
    }
    omp_set_num_threads(before);
    std::printf("[rebuilds] %d threads: %llu rebuilds in %llu steps; farthest from the build %.3g of the skin\n", threads,
                static_cast<unsigned long long>(rebuilds), static_cast<unsigned long long>(s.total_steps()), farthest / s.skin);
    EXPECT_GT(rebuilds, 10u) << "the gas must outrun the skin often for the test to mean anything";
    EXPECT_EQ(wrong, 0u) << threads << " threads: steps whose rebuild decision differs from the distance test";
    EXPECT_EQ(beyond, 0u) << threads << " threads: steps whose pairs had a ball beyond skin/2";
  }
}

// A ball that moves more than kSkinStep x skin in one step would outrun the list renewed a step
// ahead: the run stops and says so. The same gas with the skin at 1 um: at up to 3 m/s a ball
// moves up to 0.3 um a step, more than 0.25 um.
TEST(PairSkipping, BallTooFastForTheSkinStopsTheRun) {
  Scene s = gas(5, 1e-3, 3.0, 11);
  s.skin = 1e-6;
  Simulation sim(s);
  try {
    sim.advance(s.total_steps());
    FAIL() << "the run must stop";
  } catch (const RunError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("in one step, more than 0.25 of the neighbour skin"), std::string::npos) << what;
    EXPECT_NE(what.find("raise simulation.skin"), std::string::npos) << what;
  }
}
