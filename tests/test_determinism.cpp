// Thread-count independence (src/step/stage.hpp, "Determinism"): every per-particle sum runs in a fixed
// order and totals are summed in index order, so a run must be bitwise identical for any number of
// OpenMP threads. The parallel loops engage above 512 items (the ball stages from kParallelBalls =
// 2048 balls, lowered to 512 here with set_parallel_balls) and the broad phase above 2000 particles,
// so the scenes here are above those sizes.
#include <gtest/gtest.h>
#include <omp.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bagdem/parallel.hpp"
#include "bagdem/error.hpp"
#include "bagdem/motion/motion.hpp"
#include "bagdem/step/simulation.hpp"
#include "rng.hpp"
#include "scene_builder.hpp"

using namespace bagdem;
using bagdem::testing::Rng;
using bagdem::testing::SceneBuilder;

namespace {


std::uint64_t fnv1a64(const std::vector<char>& bytes) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

// Polydisperse frictional balls (r 1.5-2.5 mm, E = 5e7 Pa, e = 0.5, mu = 0.4, mu_r = 0.05) on a
// jittered nx x ny x nz lattice in a box shaken obliquely (X = 1 mm, 30 Hz) under gravity, with
// random initial velocities so that contacts form at once.
Scene shaken_box(int nx, int ny, int nz, double duration, bool energy = true) {
  SceneBuilder b;
  b.energy(energy);
  b.material("glass", 2500, 5e7, 0.3).interaction(0.5, 0.4, 0.05);
  const double a = 0.0051, m = 0.003;
  const Vec3 lo(0, 0, 0), hi(2 * m + a * (nx - 1), 2 * m + a * (ny - 1), 2 * m + a * (nz - 1) + 0.01);
  b.box(lo, hi).gravity(Vec3(0, 0, -9.81)).dt(1e-5).duration(duration);
  b.motion(make_harmonic_motion(0.001, 30.0, Vec3(0.3, 0.2, 1.0), 0.0));
  Rng rng(2024);
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k) {
        const double r = rng.uniform(0.0015, 0.0025);
        const Vec3 x = Vec3(m + a * i, m + a * j, m + a * k) +
                       draw_vec3([&] { return rng.uniform(-1, 1); }) * 4e-5;
        const Vec3 v = draw_vec3([&] { return rng.uniform(-1, 1); });
        const Vec3 w = draw_vec3([&] { return rng.uniform(-50, 50); });
        b.particle(x, v, r, 0, w);
      }
  return b.build();
}

struct RunResult {
  std::vector<char> state;
  EnergySample energy;
  std::size_t pairs = 0, contacts = 0, max_contacts = 0;
  std::uint64_t builds = 0;
  std::uint64_t moves = 0;  // times the threads' spans moved (SpanBalance)
};

RunResult run(const Scene& s, int threads) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  RunResult r;
  {
    Simulation sim(s);
    sim.set_parallel_balls(kParallelMin);  // the parallel ball stages on this small scene
    sim.set_balance_window(1, 0.0);        // the threads' spans move at every step
    for (std::uint64_t k = 0; k < s.total_steps(); ++k) {
      sim.step();
      if (k % 25 == 0) r.max_contacts = std::max(r.max_contacts, sim.contact_count());
    }
    r.state = sim.save_state();
    r.energy = sim.energy();
    r.pairs = sim.pair_list().pairs;
    r.contacts = sim.contact_count();
    r.builds = sim.neighbour_builds();
    r.moves = sim.balance().moves();
  }
  omp_set_num_threads(before);
  return r;
}

bool bitwise_equal(const EnergySample& a, const EnergySample& b) {
  return std::memcmp(&a, &b, sizeof(EnergySample)) == 0;
}

void compare_thread_counts(const Scene& s, const char* label) {
  const RunResult one = run(s, 1);
  std::printf("[determinism] %s: %zu particles, %zu candidate pairs, %zu contacts at the end (max %zu), "
              "%llu neighbour builds; K = %.6e J, D_t = %.6e J; state hash %016llx (1 thread)\n",
              label, s.particles.size(), one.pairs, one.contacts, one.max_contacts,
              static_cast<unsigned long long>(one.builds), one.energy.kinetic,
              one.energy.dissipated_tangential, static_cast<unsigned long long>(fnv1a64(one.state)));
  // The scene must exercise the parallel paths (> 512 particles and > 512 candidate pairs) and the
  // contact laws (many closed contacts), else equality proves nothing.
  EXPECT_GT(s.particles.size(), 512u);
  EXPECT_GT(one.pairs, 512u);
  EXPECT_GT(one.max_contacts, 60u);
  EXPECT_GT(one.energy.dissipated_tangential, 0.0);
  EXPECT_GT(one.energy.dissipated_rolling, 0.0);
  for (int threads : {2, 3}) {
    const RunResult other = run(s, threads);
    EXPECT_GT(other.moves, other.builds) << label << ": the threads' spans must move during the run";
    const std::uint64_t h1 = fnv1a64(one.state), hk = fnv1a64(other.state);
    std::printf("[determinism] %s: state hash %016llx (%d threads)\n", label,
                static_cast<unsigned long long>(hk), threads);
    EXPECT_EQ(one.state.size(), other.state.size()) << label << ", " << threads << " threads";
    EXPECT_EQ(h1, hk) << label << ": checkpoint image differs between 1 and " << threads << " threads";
    EXPECT_TRUE(one.state == other.state) << label << ", " << threads << " threads";
    EXPECT_TRUE(bitwise_equal(one.energy, other.energy))
        << label << ": energy sample differs between 1 and " << threads << " threads (K "
        << one.energy.kinetic << " vs " << other.energy.kinetic << ")";
  }
}

}  // namespace

// Reference: the 1-thread run. Tolerance: bitwise equality (FNV-1a 64 of the checkpoint image, the
// image itself, and the EnergySample bytes) with 2 and 3 threads (3: uneven static partitions),
// whose spans of balls move by the clock at every step (SpanBalance).
// 8 x 8 x 12 = 768 particles, 150 steps (few steps: on a loaded 2-core machine every OpenMP
// region can cost a scheduler time slice).
TEST(Determinism, ShakenFrictionalBoxSameForAnyThreadCount) {
  const Scene s = shaken_box(8, 8, 12, 1.5e-3);
  compare_thread_counts(s, "768-particle shaken box");
}

// Above 2000 particles the broad phase itself runs in parallel (build_candidates): 13 x 13 x 13 =
// 2197 particles, 60 steps.
TEST(Determinism, ParallelBroadPhaseSameForAnyThreadCount) {
  const Scene s = shaken_box(13, 13, 13, 6e-4);
  compare_thread_counts(s, "2197-particle shaken box");
}

// Reference: a run that is checkpointed and restored into a fresh Simulation mid-way, and continued
// with 2 threads, ends bitwise identical to an uninterrupted 1-thread run (FNV-1a 64 of the image,
// EnergySample bytes). 640 particles, 100 + 100 steps.
TEST(Determinism, RestoredCheckpointContinuesBitwise) {
  const Scene s = shaken_box(8, 8, 10, 2e-3);
  const RunResult whole = run(s, 1);
  const int before = omp_get_max_threads();
  std::vector<char> mid;
  {
    omp_set_num_threads(1);
    Simulation a(s);
    a.set_parallel_balls(kParallelMin);  // the parallel ball stages on this small scene
    for (std::uint64_t k = 0; k < s.total_steps() / 2; ++k) a.step();
    mid = a.save_state();
  }
  omp_set_num_threads(2);
  Simulation b(s);
  b.set_parallel_balls(kParallelMin);  // the parallel ball stages on this small scene
  b.set_balance_window(1, 0.0);        // and the threads' spans moving at every step
  b.load_state(mid);
  EXPECT_EQ(b.steps_done(), s.total_steps() / 2);
  while (b.steps_done() < s.total_steps()) b.step();
  omp_set_num_threads(before);
  EXPECT_EQ(fnv1a64(whole.state), fnv1a64(b.save_state()));
  EXPECT_TRUE(bitwise_equal(whole.energy, b.energy()));
}

// One Simulation whose thread count changes between steps (2 threads for 5 steps, 1 for 3, again
// and again: gathered, scattered, gathered, with contacts opening in the scattered stretches) ends
// bitwise identical to an uninterrupted 1-thread run: the pair records kept for gathering are not
// stale after a stretch of scattering. 640 particles, 200 steps.
TEST(Determinism, ThreadCountChangedMidRun) {
  const Scene s = shaken_box(8, 8, 10, 2e-3);
  const RunResult whole = run(s, 1);
  const int before = omp_get_max_threads();
  std::vector<char> end;
  EnergySample energy;
  {
    Simulation sim(s);
    sim.set_parallel_balls(kParallelMin);  // the parallel ball stages on this small scene
    sim.set_balance_window(1, 0.0);        // and the threads' spans moving at every step
    while (sim.steps_done() < s.total_steps()) {
      omp_set_num_threads(sim.steps_done() % 8 < 5 ? 2 : 1);
      sim.step();
    }
    end = sim.save_state();
    energy = sim.energy();
  }
  omp_set_num_threads(before);
  EXPECT_EQ(fnv1a64(whole.state), fnv1a64(end));
  EXPECT_TRUE(bitwise_equal(whole.energy, energy));
}

// Simulation::advance(n) fuses each step's second half-kick into the next step's first and skips, in
// the wall stage, the balls with no wall or bound near: it must end bitwise where n calls of step()
// end. Energy tallies off (the skipping's condition) and on, 1 and 2 threads, advanced in uneven
// chunks (1, 2, 37 and 60 steps) through neighbour builds and wall contacts. 640 particles, 200 steps.
TEST(Determinism, AdvanceEqualsStepByStep) {
  for (bool energy : {false, true}) {
    const Scene s = shaken_box(8, 8, 10, 2e-3, energy);
    for (int threads : {1, 2}) {
      const RunResult whole = run(s, threads);
      const int before = omp_get_max_threads();
      omp_set_num_threads(threads);
      Simulation sim(s);
      sim.set_parallel_balls(kParallelMin);  // the parallel ball stages on this small scene
      const std::uint64_t chunks[] = {1, 37, 2, 60};
      for (std::size_t c = 0; sim.steps_done() < s.total_steps(); ++c)
        sim.advance(std::min(chunks[c % 4], s.total_steps() - sim.steps_done()));
      omp_set_num_threads(before);
      EXPECT_GT(whole.builds, 1u) << "the run must cross a neighbour build";
      EXPECT_EQ(fnv1a64(whole.state), fnv1a64(sim.save_state())) << "energy " << energy << ", " << threads << " threads";
      EXPECT_TRUE(bitwise_equal(whole.energy, sim.energy())) << "energy " << energy << ", " << threads << " threads";
    }
  }
}

// advance() runs the pairs, the walls and the next step's drift in one parallel region, each thread
// on its own range (Stepper::fused_contacts): it must end bitwise where the staged step (the same
// advance() with set_fusion(false), one region per stage) ends. Energy tallies off (the wall stage
// then visits only the balls near a wall) and on, frictional and frictionless, 1, 2 and 3 threads
// (the threads' spans moved at every step), in uneven chunks of advance() through neighbour builds.
// 640 particles, 200 steps.
TEST(Determinism, FusedStepEqualsStaged) {
  for (bool energy : {false, true}) {
    for (bool friction : {true, false}) {
      Scene s = shaken_box(8, 8, 10, 2e-3, energy);
      if (!friction) {
        s.models.tangential = s.models.rolling = false;
      }
      auto advanced = [&s](int threads, bool fuse, std::uint64_t* fused, std::uint64_t* builds) {
        const int before = omp_get_max_threads();
        omp_set_num_threads(threads);
        Simulation sim(s);
        sim.set_parallel_balls(kParallelMin);
        sim.set_balance_window(1, 0.0);
        sim.set_fusion(fuse);
        const std::uint64_t chunks[] = {60, 1, 37, 2};
        for (std::size_t c = 0; sim.steps_done() < s.total_steps(); ++c)
          sim.advance(std::min(chunks[c % 4], s.total_steps() - sim.steps_done()));
        omp_set_num_threads(before);
        *fused = sim.fused_steps();
        *builds = sim.neighbour_builds();
        return std::make_pair(sim.save_state(), sim.energy());
      };
      std::uint64_t fused = 0, builds = 0;
      const auto staged = advanced(1, false, &fused, &builds);
      EXPECT_EQ(fused, 0u);
      for (int threads : {1, 2, 3}) {
        const auto f = advanced(threads, true, &fused, &builds);
        const std::string what = "energy " + std::to_string(energy) + ", friction " + std::to_string(friction) + ", " +
                                 std::to_string(threads) + " threads";
        // Every step fused but the last of each advance() (its kick is not deferred).
        EXPECT_GT(fused, s.total_steps() * 9 / 10) << what;
        EXPECT_GT(builds, 1u) << what << ": the run must cross a neighbour build";
        EXPECT_TRUE(f.first == staged.first) << what;
        EXPECT_TRUE(bitwise_equal(f.second, staged.second)) << what;
      }
    }
  }
}

// advance() on several threads runs its steps pipelined (Stepper::pipelined_region, a column of the stage table): the threads
// stay in one region for up to a balance window of steps (64) and wait only for the ranges next
// to theirs. It must end bitwise where the fused steps end (the 1-thread run, and 2 threads with
// pipelining off). Energy tallies off and on, frictional and frictionless, 2 and 3 threads (3: more
// threads than cores, and ranges whose cross pairs may reach two ranges down), in uneven chunks of
// advance() through neighbour builds. 640 particles, 400 steps.
TEST(Determinism, PipelinedStepsEqualFused) {
  for (bool energy : {false, true}) {
    for (bool friction : {true, false}) {
      Scene s = shaken_box(8, 8, 10, 4e-3, energy);
      if (!friction) s.models.tangential = s.models.rolling = false;
      struct Out {
        std::vector<char> state;
        EnergySample energy;
        std::uint64_t pipelined = 0, builds = 0;
      };
      auto advanced = [&s](int threads, bool pipelining) {
        const int before = omp_get_max_threads();
        omp_set_num_threads(threads);
        Simulation sim(s);
        sim.set_parallel_balls(kParallelMin);
        sim.set_pipelining(pipelining);
        const std::uint64_t chunks[] = {150, 1, 37, 2, 90};
        for (std::size_t c = 0; sim.steps_done() < s.total_steps(); ++c)
          sim.advance(std::min(chunks[c % 5], s.total_steps() - sim.steps_done()));
        omp_set_num_threads(before);
        return Out{sim.save_state(), sim.energy(), sim.pipelined_steps(), sim.neighbour_builds()};
      };
      const Out fused = advanced(1, true), fused2 = advanced(2, false);
      EXPECT_EQ(fused.pipelined, 0u);
      EXPECT_EQ(fused2.pipelined, 0u);
      EXPECT_GT(fused.builds, 2u) << "the run must cross neighbour builds";
      EXPECT_TRUE(fused2.state == fused.state);
      for (int threads : {2, 3}) {
        const Out p = advanced(threads, true);
        const std::string what = "energy " + std::to_string(energy) + ", friction " + std::to_string(friction) + ", " +
                                 std::to_string(threads) + " threads";
        std::printf("[pipelined] %s: %llu of %llu steps pipelined, %llu neighbour builds\n", what.c_str(),
                    static_cast<unsigned long long>(p.pipelined), static_cast<unsigned long long>(s.total_steps()),
                    static_cast<unsigned long long>(p.builds));
        // All but the first and the last step of each advance(), and the steps that rebuild.
        EXPECT_GT(p.pipelined, s.total_steps() * 3 / 4) << what;
        EXPECT_EQ(p.builds, fused.builds) << what;
        EXPECT_TRUE(p.state == fused.state) << what;
        EXPECT_TRUE(bitwise_equal(p.energy, fused.energy)) << what;
      }
    }
  }
}

// Three ranges, the middle one two balls thin, so that cross pairs reach from the first range
// into the third: the cross pairs' scale is half the sum of three ranges' travels and can outgrow
// each of them. At the end of pipelined steps travel_ must cover it at the final positions, or a
// cross pair sleeps through its contact in the steps after (a bug of session 19, found when the
// balance made a middle range that thin under load). The cuts stay (no balance moves); advance()
// in calls of 6 steps, so that many regions of pipelined steps end (without the fix: fails).
TEST(Determinism, PipelinedStepsWithCrossPairsOverAThinRange) {
  Scene s = shaken_box(8, 8, 10, 4e-3, true);
  s.models.tangential = s.models.rolling = false;
  struct Out {
    std::vector<char> state;
    EnergySample energy;
    std::uint64_t pipelined = 0, crossing_two = 0;  // crossing_two: cross pairs from the first range into the third
  };
  auto advanced = [&s](int threads) {
    const int before = omp_get_max_threads();
    omp_set_num_threads(threads);
    Simulation sim(s);
    sim.set_parallel_balls(kParallelMin);
    sim.set_balance_window(64, 1e9);
    const auto n = static_cast<std::uint32_t>(sim.particles().size());
    std::uint64_t crossing_two = 0;
    while (sim.steps_done() < s.total_steps()) {
      if (threads == 3) sim.set_cuts({0, n / 2, n / 2 + 2, n});
      sim.advance(std::min<std::uint64_t>(6, s.total_steps() - sim.steps_done()));
      if (threads == 3)
        for (const auto& [i, j] : sim.cross_pairs()) crossing_two += i < n / 2 && j >= n / 2 + 2;
    }
    omp_set_num_threads(before);
    return Out{sim.save_state(), sim.energy(), sim.pipelined_steps(), crossing_two};
  };
  const Out one = advanced(1), three = advanced(3);
  EXPECT_GT(three.pipelined, s.total_steps() / 2) << "the steps must run pipelined";
  EXPECT_GT(three.crossing_two, 0u) << "cross pairs must reach across the thin range";
  EXPECT_TRUE(three.state == one.state);
  EXPECT_TRUE(bitwise_equal(three.energy, one.energy));
}

// A guard that fails in pipelined steps stops the run at the same step, with the same kind of
// message, as in fused steps: a contact overlap above a limit set low (5% of the radius) in the shaken box,
// first passed at step 235 (inside a region of pipelined steps: they run 64 at a time). The
// message's other figures come from the state then, which the ranges may have left a step apart.
TEST(Determinism, PipelinedGuardStopsAtTheSameStep) {
  Scene s = shaken_box(8, 8, 10, 4e-3, false);
  s.max_overlap_fraction = 0.05;
  auto stopped = [&s](int threads) {
    const int before = omp_get_max_threads();
    omp_set_num_threads(threads);
    Simulation sim(s);
    sim.set_parallel_balls(kParallelMin);
    std::string what;
    try {
      sim.advance(s.total_steps());
    } catch (const RunError& e) {
      what = e.what();
    }
    omp_set_num_threads(before);
    return std::make_pair(what, sim.pipelined_steps());
  };
  const auto one = stopped(1);
  std::printf("[pipelined guard] 1 thread: %s\n", one.first.c_str());
  ASSERT_NE(one.first.find("contact overlap passed"), std::string::npos) << one.first;
  const std::string step = one.first.substr(0, one.first.find("):"));
  for (int threads : {2, 3}) {
    const auto p = stopped(threads);
    std::printf("[pipelined guard] %d threads, %llu steps pipelined: %s\n", threads, static_cast<unsigned long long>(p.second),
                p.first.c_str());
    EXPECT_GT(p.second, 200u) << "the failing step must come in pipelined steps";
    EXPECT_EQ(p.first.substr(0, p.first.find("):")), step) << threads << " threads";
    EXPECT_NE(p.first.find("contact overlap passed"), std::string::npos) << p.first;
  }
}
