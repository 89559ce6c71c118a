// Checkpoint and resume of a stepped-sine sweep (src/run/stepped_sine_state.hpp): a sweep killed in the
// middle of a point (RunOptions::stop_after_steps, which leaves results.h5.part and the checkpoint
// of the last point done as a kill would), resumed, killed again in the refinement and resumed to
// the end, writes the same results.h5 (every dataset, bit for bit, but the points' wall times),
// sweep.csv and reduced.csv as the sweep uninterrupted. So does a sweep of two chains
// (run/stepped_sine_chains.hpp), killed while both run, and it writes the same on one thread as on two.
// A resume by a bagdem that resolves the same case to another scene (another default) is refused.
// The CLI's SIGTERM during a sweep is in test_faults.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "bagdem/reduce/summary.hpp"
#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/run/stepped_sine.hpp"
#include "results_compare.hpp"
#include "support.hpp"
#include "stepped_sine_support.hpp"

namespace fs = std::filesystem;
using bagdem::testing::TempDir;


namespace {

TEST(SweepRestart, KilledTwiceAndResumedIsBitwiseEqual) {
  TempDir tmp;
  const fs::path dir = tmp.path / "case";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << bagdem::testing::rattling_ball_sweep(1);
  const bagdem::Scene scene = bagdem::load_case(dir.string());
  auto sweep = [&](const fs::path& out, long long stop, bool resume) {
    return bagdem::run_stepped_sine(scene, bagdem::testing::quiet_run(out, 1, stop, resume));
  };
  const fs::path a = tmp.path / "A", b = tmp.path / "B";
  const bagdem::SteppedSineReport ra = sweep(a, -1, false);
  ASSERT_TRUE(ra.complete) << ra.message;
  ASSERT_EQ(ra.points.size(), 4u) << "three planned points and one refinement";
  // The steps of the whole sweep: settling, then each point's cycles.
  double steps = std::round(scene.settle / scene.dt);
  for (const bagdem::SteppedSinePoint& p : ra.points) steps += static_cast<double>(p.cycles) * std::round(1 / (p.frequency * scene.dt));
  // Killed during the second point, then during the refinement (the fourth point).
  const bagdem::SteppedSineReport rb1 = sweep(b, std::llround(0.35 * steps), false);
  EXPECT_FALSE(rb1.complete);
  EXPECT_TRUE(fs::exists(b / "checkpoint.bin"));
  EXPECT_TRUE(fs::exists(b / "results.h5.part"));
  EXPECT_FALSE(fs::exists(b / "results.h5"));
  {
    // The same case resolved by a bagdem whose time-step rule differs (its text is the same): the
    // resume is refused, naming the line of `bagdem check` that differs, and nothing is touched.
    bagdem::Scene other = scene;
    other.dt *= 0.5;
    const std::string before = bagdem::testing::slurp((b / "checkpoint.bin").string());
    try {
      bagdem::run_stepped_sine(other, bagdem::testing::quiet_run(b, 1, -1, true));
      ADD_FAILURE() << "a resume by a bagdem that resolves the case to another time step was not refused";
    } catch (const bagdem::InputError& e) {
      std::printf("  another time step: %s\n", e.what());
      EXPECT_NE(std::string(e.what()).find("another scene"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("was 'time step"), std::string::npos) << e.what();
    }
    EXPECT_EQ(bagdem::testing::slurp((b / "checkpoint.bin").string()), before);
    EXPECT_FALSE(fs::exists(b / "results.h5"));
  }
  EXPECT_FALSE(sweep(b, std::llround(0.55 * steps), true).complete);
  const bagdem::SteppedSineReport rb = sweep(b, -1, true);
  ASSERT_TRUE(rb.complete) << rb.message;
  ASSERT_EQ(rb.points.size(), ra.points.size());
  bagdem::testing::expect_same_sweep(a, b);
}

// Two chains around the resonance at 30 Hz: 26 and 30 Hz on the first, 38 then 34 Hz on the
// second (it runs towards the resonance); the refinement's two points, one on each.
TEST(SweepRestart, TwoChainsAreTheSameOnAnyThreadsAndAfterKills) {
  TempDir tmp;
  const fs::path dir = tmp.path / "case";
  fs::create_directories(dir);
  std::string text = bagdem::testing::rattling_ball_sweep(2);
  text.replace(text.find("[26, 30, 34]"), 12, "[26, 30, 34, 38]");
  text.replace(text.find("refine = 1"), 10, "refine = 2");
  std::ofstream(dir / "case.toml") << text;
  const bagdem::Scene scene = bagdem::load_case(dir.string());
  auto sweep = [&](const fs::path& out, int threads, long long stop, bool resume) {
    return bagdem::run_stepped_sine(scene, bagdem::testing::quiet_run(out, threads, stop, resume));
  };
  const fs::path a = tmp.path / "A", b = tmp.path / "B", c = tmp.path / "C", s = tmp.path / "serial";
  const bagdem::SteppedSineReport ra = sweep(a, 1, -1, false);
  ASSERT_TRUE(ra.complete) << ra.message;
  ASSERT_EQ(ra.points.size(), 6u);
  EXPECT_EQ(bagdem::read_summary(a / "summary.json").chains, 2u);
  // The first chain runs 26 and 30 Hz as a serial sweep does; the second starts at 38 Hz as the
  // sweep's first point does at 26 Hz, and reaches 34 Hz from there, where a serial sweep
  // continues from 30 Hz instead.
  bagdem::Scene serial = scene;
  auto plan = std::make_shared<bagdem::Primary::SteppedSine>(*scene.primary->stepped_sine);
  plan->chains = 1;
  auto primary = std::make_shared<bagdem::Primary>(*scene.primary);
  primary->stepped_sine = plan;
  serial.primary = primary;
  const bagdem::SteppedSineReport rs = bagdem::run_stepped_sine(serial, bagdem::testing::quiet_run(s));
  ASSERT_TRUE(rs.complete) << rs.message;
  EXPECT_EQ(rs.points[0].receptance, ra.points[0].receptance);
  EXPECT_EQ(rs.points[1].receptance, ra.points[1].receptance);
  EXPECT_NE(rs.points[2].receptance, ra.points[2].receptance);
  // Two threads: the chains side by side, the same bits.
  const bagdem::SteppedSineReport rc = sweep(c, 2, -1, false);
  ASSERT_TRUE(rc.complete) << rc.message;
  bagdem::testing::expect_same_sweep(a, c);
  // Killed on two threads, each chain at its own step count (settling is the first's): in B with
  // both in the refinement (points 0-3 written, the second chain's state after 34 Hz, the last it
  // ran), resumed on one thread; in D while both run their blocks, resumed on two.
  auto steps = [&](std::size_t i) {
    const bagdem::SteppedSinePoint& p = ra.points[i];
    return static_cast<double>(p.cycles) * std::round(1 / (p.frequency * scene.dt));
  };
  const double kill = std::round(scene.settle / scene.dt) + steps(0) + steps(1) + 0.1 * steps(4);
  ASSERT_GT(kill, steps(2) + steps(3));
  ASSERT_LT(kill, steps(2) + steps(3) + steps(5));
  EXPECT_FALSE(sweep(b, 2, std::llround(kill), false).complete);
  const std::string part = bagdem::testing::slurp(b / "sweep.partial.csv");
  EXPECT_FALSE(fs::exists(b / "sweep.csv") || fs::exists(b / "reduced.csv")) << "an interrupted sweep's tables are its partial ones";
  EXPECT_EQ(std::count(part.begin(), part.end(), '\n'), 5) << "the header and the 4 planned points";
  const fs::path d = tmp.path / "D";
  EXPECT_FALSE(sweep(d, 2, std::llround(0.5 * steps(3)), false).complete);
  EXPECT_TRUE(fs::exists(d / "checkpoint.bin"));
  const bagdem::SteppedSineReport rd = sweep(d, 2, -1, true);
  ASSERT_TRUE(rd.complete) << rd.message;
  bagdem::testing::expect_same_sweep(a, d);
  const bagdem::SteppedSineReport rb = sweep(b, 1, -1, true);
  ASSERT_TRUE(rb.complete) << rb.message;
  bagdem::testing::expect_same_sweep(a, b);
}

}  // namespace
