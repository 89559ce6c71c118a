// Checkpoint and restart, bit for bit: a run interrupted (RunOptions.stop_after_steps, which leaves
// results.h5.part and checkpoint.bin as a kill would) and resumed (RunOptions.resume) writes the same
// results.h5, dataset by dataset and bit by bit, as the same run uninterrupted; and the CLI refuses
// --resume where there is nothing to resume.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "bagdem/reduce/summary.hpp"
#include "bagdem/case/load_case.hpp"
#include "bagdem/run/runner.hpp"

#include "results_compare.hpp"
#include "case_texts.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using bagdem::testing::TempDir;
using bagdem::testing::CmdResult;
using bagdem::testing::slurp;
using bagdem::testing::run_bagdem;

namespace {

// 30 soft balls with friction in a box shaken along (1, 0, 1), gravity, a settle phase, frames and
// checkpoints every few hundred steps (~9300 steps of ~1.3e-5 s).
const std::string kCase = bagdem::testing::shaken_box("0.1 s", "10 ms");

// Every dataset of A is in B with the same shape and the same bits, and vice versa.
void expect_same_results(const fs::path& a, const fs::path& b) {
  const auto A = bagdem::testing::read_all_datasets(a), B = bagdem::testing::read_all_datasets(b);
  // The layout of results.h5 (include/bagdem/io/results_file.hpp): the series compared must exist.
  for (const char* name : {"/frames/time", "/frames/position", "/frames/velocity", "/frames/angular_velocity",
                           "/cavity/time", "/cavity/position", "/cavity/velocity", "/cavity/force",
                           "/cavity/torque", "/energy/time", "/energy/kinetic", "/energy/dissipated_tangential",
                           "/particles/radius"}) {
    EXPECT_TRUE(A.count(name)) << name << " missing in " << a;
  }
  ASSERT_TRUE(A.count("/frames/time"));
  EXPECT_GE(A.at("/frames/time").dims.at(0), 20u) << "expected ~25 frames";
  bagdem::testing::expect_same_datasets(A, a, B, b);
}

struct RestartRun {
  TempDir tmp;
  fs::path case_dir;
  bagdem::Scene scene;
  RestartRun() {
    case_dir = tmp.path / "case";
    fs::create_directories(case_dir);
    std::ofstream(case_dir / "case.toml") << kCase;
    scene = bagdem::load_case(case_dir.string());
  }
  bagdem::RunReport run(const fs::path& out, long long stop_after = -1, bool resume = false) const {
    return bagdem::run_scene(scene, bagdem::testing::quiet_run(out, 1, stop_after, resume));
  }
};

// A killed run leaves the partial results and the checkpoint, and nothing that looks complete.
void expect_interrupted(const fs::path& out) {
  EXPECT_TRUE(fs::exists(out / "results.h5.part"));
  EXPECT_TRUE(fs::exists(out / "checkpoint.bin"));
  EXPECT_FALSE(fs::exists(out / "results.h5"));
  EXPECT_FALSE(fs::exists(out / "summary.json"));
}

void expect_complete_and_equal(const fs::path& a, const fs::path& b, const bagdem::Scene& scene) {
  ASSERT_TRUE(fs::exists(b / "results.h5"));
  EXPECT_FALSE(fs::exists(b / "results.h5.part"));
  EXPECT_FALSE(fs::exists(b / "checkpoint.bin")) << "a complete run removes its checkpoint";
  expect_same_results(a / "results.h5", b / "results.h5");
  ASSERT_TRUE(fs::exists(b / "summary.json")) << "no summary.json after the resumed run";
  const bagdem::Summary sa = bagdem::read_summary(a / "summary.json"), sb = bagdem::read_summary(b / "summary.json");
  EXPECT_EQ(sa.particles, 30u);
  EXPECT_EQ(sb.particles, sa.particles);
  EXPECT_EQ(sa.steps, scene.total_steps());
  EXPECT_EQ(sb.steps, sa.steps);
}

TEST(Restart, ResumedRunIsBitwiseEqual) {
  RestartRun s;
  ASSERT_EQ(s.scene.particles.size(), 30u);
  ASSERT_TRUE(s.scene.models.tangential);
  const std::uint64_t total = s.scene.total_steps();
  const auto ckpt_steps = static_cast<std::uint64_t>(std::llround(s.scene.output.checkpoint_interval / s.scene.dt));
  ASSERT_GT(total, 4 * ckpt_steps);

  const fs::path a = s.tmp.path / "A", b = s.tmp.path / "B";
  const bagdem::RunReport ra = s.run(a);
  ASSERT_TRUE(ra.complete) << ra.message;

  // Killed between two checkpoints, after the settle phase: the frames written after the last
  // checkpoint must be cut on resume.
  const long long stop = static_cast<long long>(2 * ckpt_steps + ckpt_steps / 2);
  const bagdem::RunReport rb1 = s.run(b, stop);
  EXPECT_FALSE(rb1.complete);
  expect_interrupted(b);
  // Mark the partial file: the resumed run must continue this file (cut to the checkpoint's
  // lengths), not start a new one from step 0 (which would also end bitwise equal).
  {
    const hid_t f = H5Fopen((b / "results.h5.part").string().c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    const hid_t sp = H5Screate(H5S_SCALAR);
    const hid_t at = H5Acreate2(f, "restart_test_marker", H5T_NATIVE_INT, sp, H5P_DEFAULT, H5P_DEFAULT);
    const int one = 1;
    EXPECT_GE(H5Awrite(at, H5T_NATIVE_INT, &one), 0);
    H5Aclose(at);
    H5Sclose(sp);
    H5Fclose(f);
  }
  const bagdem::RunReport rb2 = s.run(b, -1, true);
  ASSERT_TRUE(rb2.complete) << rb2.message;
  expect_complete_and_equal(a, b, s.scene);
  const hid_t f = H5Fopen((b / "results.h5").string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  EXPECT_GT(H5Aexists(f, "restart_test_marker"), 0) << "the resumed run did not continue the partial file";
  H5Fclose(f);
}

TEST(Restart, TwiceInterruptedRunIsBitwiseEqual) {
  RestartRun s;
  const auto ckpt_steps = static_cast<std::uint64_t>(std::llround(s.scene.output.checkpoint_interval / s.scene.dt));
  const fs::path a = s.tmp.path / "A", b = s.tmp.path / "B";
  ASSERT_TRUE(s.run(a).complete);
  // Killed during the settle phase (before the motion starts), resumed, killed again during the
  // shaking, resumed to the end.
  EXPECT_FALSE(s.run(b, static_cast<long long>(ckpt_steps + 7)).complete);
  expect_interrupted(b);
  EXPECT_FALSE(s.run(b, static_cast<long long>(3 * ckpt_steps + 11), true).complete);
  expect_interrupted(b);
  ASSERT_TRUE(s.run(b, -1, true).complete);
  expect_complete_and_equal(a, b, s.scene);
}

TEST(Restart, CliResumeWithoutCheckpointIsRefused) {
  TempDir tmp;
  const fs::path dir = tmp.path / "case", out = tmp.path / "out";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << kCase;
  const CmdResult r = run_bagdem({"run", dir.string(), "--out", out.string(), "--resume", "--quiet"}, tmp.path);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find((out / "checkpoint.bin").string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no checkpoint to resume from"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "results.h5"));
  EXPECT_FALSE(fs::exists(out / "summary.json"));
}

TEST(Restart, CliResumeOfCompleteRunIsRefusedAndChangesNothing) {
  // A complete run removed its checkpoint: --resume has nothing to continue. It must say so
  // (exit 2) and leave the complete run's files as they were.
  TempDir tmp;
  const fs::path dir = tmp.path / "case", out = tmp.path / "out";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << kCase;
  const CmdResult done = run_bagdem({"run", dir.string(), "--out", out.string(), "--quiet", "--threads", "1",
                                 "--set", "simulation.duration=\"0.01 s\""},
                                tmp.path);
  ASSERT_EQ(done.code, 0) << done.err;
  ASSERT_TRUE(fs::exists(out / "summary.json"));
  const std::string summary = slurp(out / "summary.json");
  const CmdResult r = run_bagdem({"run", dir.string(), "--out", out.string(), "--resume", "--quiet",
                              "--set", "simulation.duration=\"0.01 s\""},
                             tmp.path);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("no checkpoint to resume from"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(out / "results.h5"));
  EXPECT_TRUE(fs::exists(out / "summary.json")) << "a refused --resume deleted the complete run's summary.json";
  EXPECT_EQ(slurp(out / "summary.json"), summary);
}

}  // namespace
