// Run guards through the command line: a run that goes unstable (overlap beyond
// simulation.max_overlap, a particle leaving the cavity, NaN, an energy budget off by more than
// simulation.max_energy_error) stops with exit code 3 and a message
// that says what happened and what to change; its record, results.failed.h5, is a valid HDF5 file
// whose root attribute "status" starts with "failed", and summary.json (the mark of a complete run)
// is not written. An earlier complete results.h5 in the same directory is kept, bit for bit.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "case_texts.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using bagdem::testing::TempDir;
using bagdem::testing::CaseText;
using bagdem::testing::kNoGravity;
using bagdem::testing::Value;
using bagdem::testing::vec;
using bagdem::testing::CmdResult;
using bagdem::testing::slurp;
using bagdem::testing::run_bagdem;

namespace {

// One steel ball of 4 mm in a 20 mm box without gravity, at `position` with `velocity` (arrays of
// one point); `simulation` are more [simulation] keys; the steel's Young's modulus is `youngs`.
std::string one_ball_case(const std::string& position, const std::string& velocity,
                          const CaseText::Keys& simulation, const Value& youngs = "200 GPa",
                          const Value& duration = "0.01 s") {
  return CaseText()
      .simulation(duration, kNoGravity)
      .set("simulation", simulation)
      .steel(youngs)
      .interactions(0.5, 0.2)
      .box("steel", "[0, 0, 0]", vec("20 mm", "20 mm", "20 mm"))
      .placed("balls", "steel", "4 mm", "[" + position + "]", "[" + velocity + "]");
}

std::string read_string_attribute(hid_t obj, const std::string& name) {
  hid_t attr = H5Aopen(obj, name.c_str(), H5P_DEFAULT);
  if (attr < 0) return "<missing>";
  hid_t type = H5Aget_type(attr);
  std::string out = "<unreadable>";
  if (H5Tis_variable_str(type) > 0) {
    char* text = nullptr;
    if (H5Aread(attr, type, &text) >= 0 && text) out = text;
    H5free_memory(text);
  } else {
    std::vector<char> buf(H5Tget_size(type) + 1, '\0');
    if (H5Aread(attr, type, buf.data()) >= 0) out = buf.data();
  }
  H5Tclose(type);
  H5Aclose(attr);
  return out;
}

// Writes the case, runs it (with `sets`), and checks everything a failed run must leave: exit code
// 3, a message on stderr holding every one of `message_parts` and naming the run's record,
// results.failed.h5 valid with status "failed...", no summary.json, no results.h5.part, no results.h5.
void run_and_expect_failure(const std::string& toml, const std::vector<std::string>& message_parts,
                            const std::vector<std::string>& more = {}) {
  TempDir tmp;
  const fs::path dir = tmp.path / "case", out = tmp.path / "out";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << toml;
  std::vector<std::string> args = {"run", dir.string(), "--out", out.string(), "--quiet", "--threads", "1"};
  args.insert(args.end(), more.begin(), more.end());
  const CmdResult r = run_bagdem(args, tmp.path);
  EXPECT_EQ(r.code, 3) << "stderr: " << r.err << "\nstdout: " << r.out;
  EXPECT_NE(r.err.find("error: run stopped at t = "), std::string::npos) << r.err;
  for (const auto& p : message_parts)
    EXPECT_NE(r.err.find(p), std::string::npos) << "the message lacks '" << p << "':\n" << r.err;
  EXPECT_NE(r.err.find((out / "results.failed.h5").string()), std::string::npos) << r.err;

  EXPECT_FALSE(fs::exists(out / "summary.json")) << "a failed run must not look complete";
  EXPECT_FALSE(fs::exists(out / "results.h5.part"));
  EXPECT_FALSE(fs::exists(out / "results.h5")) << "a failed run's record must not take the complete run's name";
  EXPECT_FALSE(fs::exists(out / "checkpoint.bin")) << "a failed run is not continued";
  EXPECT_TRUE(fs::exists(out / "results.failed.xmf"));
  const fs::path h5 = out / "results.failed.h5";
  ASSERT_TRUE(fs::exists(h5));
  ASSERT_GT(H5Fis_hdf5(h5.string().c_str()), 0);
  const hid_t f = H5Fopen(h5.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const std::string status = read_string_attribute(f, "status");
  EXPECT_EQ(status.rfind("failed", 0), 0u) << "status = " << status;
  // The status holds the message of the failure.
  for (const auto& p : message_parts)
    EXPECT_NE(status.find(p), std::string::npos) << "status lacks '" << p << "': " << status;
  // The frames written before the failure are readable.
  const hid_t ds = H5Dopen2(f, "/frames/time", H5P_DEFAULT);
  EXPECT_GE(ds, 0);
  if (ds >= 0) {
    const hid_t sp = H5Dget_space(ds);
    hsize_t n = 0;
    H5Sget_simple_extent_dims(sp, &n, nullptr);
    EXPECT_GE(n, 1u);
    H5Sclose(sp);
    H5Dclose(ds);
  }
  H5Fclose(f);
}

TEST(RunGuards, OverlapOfSoftContactStops) {
  // A 1 MPa ball at 5 m/s into a wall overlaps ~85% of its radius in Hertz theory, whatever dt.
  run_and_expect_failure(
      one_ball_case(vec("10 mm", "10 mm", "10 mm"), "[5, 0, 0]", {}, "1 MPa"),
      {"contact overlap passed", "10% of the smaller radius", "simulation.max_overlap", "reduce simulation.timestep",
       "Young's modulus"});
}

TEST(RunGuards, OverlapBeyondTinyMaxOverlapStops) {
  // Steel at 1 m/s: Hertz overlap ~0.24% of the radius, above a 0.1% limit.
  run_and_expect_failure(
      one_ball_case(vec("10 mm", "10 mm", "10 mm"), "[1, 0, 0]", {{"max_overlap", "0.001"}}),
      {"contact overlap passed", "0.1% of the smaller radius", "simulation.max_overlap"});
}

TEST(RunGuards, ParticleTunnellingThroughWallStops) {
  // dt = 1 ms (forced) at 10 m/s: the ball jumps from x = 16 mm to 26 mm, past the +x wall at
  // 20 mm, in one step. The message must say that it left the cavity, through which wall.
  run_and_expect_failure(
      one_ball_case(vec("16 mm", "10 mm", "10 mm"), "[10, 0, 0]",
                    {{"timestep", "1 ms"}, {"force_timestep", "true"}}),
      {"left the cavity", "box +x", "reduce simulation.timestep"});
}

TEST(RunGuards, ParticleLeavingPlanesCavityBoundsStops) {
  // A "planes" cavity with a floor only: its bounds [cavity.min, cavity.max] are the box the
  // particles must stay in. A ball thrown up at 10 m/s leaves them after ~1 ms.
  const std::string toml = CaseText()
                               .simulation("0.02 s", kNoGravity)
                               .steel()
                               .interactions(0.5)
                               .cavity("planes", "steel", "[0, 0, 0]", vec("20 mm", "20 mm", "20 mm"))
                               .plane("[0, 0, 0]", "[0, 0, 1]")
                               .placed("balls", "steel", "4 mm", "[" + vec("10 mm", "10 mm", "10 mm") + "]", "[[0, 0, 10]]");
  run_and_expect_failure(toml, {"left the cavity"});
}

TEST(RunGuards, NotANumberStops) {
  // 1e308 m/s over a forced 10 s step: the position overflows in the first step.
  run_and_expect_failure(
      one_ball_case(vec("10 mm", "10 mm", "10 mm"), "[1e308, 0, 0]",
                    {{"timestep", "10 s"}, {"force_timestep", "true"}}, "200 GPa", "100 s"),
      {"not a number", "reduce simulation.timestep"});
}

TEST(RunGuards, EnergyGainedByAnUnstableStepStops) {
  // cases/box-damper with a linear spring (1e5 N/m) and a step forced to 1.45 x the critical step
  // of its stiffest contact (3.46e-5 s): velocity Verlet is unstable there, and the balls gain
  // energy that no work put in. The energy guard stops the run when the budget is off by 5% of its
  // scale (simulation.max_energy_error, at t = 0.006 s); with the guard off the same run completed,
  // its budget off by 25% at the end, and nothing said so but that figure.
  const std::string toml = slurp(std::string(BAGDEM_SOURCE_DIR) + "/cases/box-damper/case.toml");
  run_and_expect_failure(toml, {"energy budget broke", "simulation.max_energy_error", "Reduce simulation.timestep"},
                         {"--set", "interactions.default.law=\"hooke\"", "--set", "interactions.default.stiffness=\"1e5 N/m\"",
                          "--set", "simulation.timestep=\"5e-5 s\"", "--set", "simulation.force_timestep=true"});
}

TEST(RunGuards, StableRunCompletes) {
  // The contrast: the same ball at 0.5 m/s with the auto step completes, with summary.json and
  // status "complete" (so the checks above can tell a failure from a success).
  TempDir tmp;
  const fs::path dir = tmp.path / "case", out = tmp.path / "out";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << one_ball_case(vec("10 mm", "10 mm", "10 mm"), "[0.5, 0, 0]", {});
  const CmdResult r = run_bagdem({"run", dir.string(), "--out", out.string(), "--quiet", "--threads", "1"}, tmp.path);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "summary.json"));
  ASSERT_TRUE(fs::exists(out / "results.h5"));
  const hid_t f = H5Fopen((out / "results.h5").string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  EXPECT_EQ(read_string_attribute(f, "status"), "complete");
  H5Fclose(f);
}

// A failed run into a directory that holds a complete run keeps that run's results.h5 bit for bit
// (it used to be replaced by the failed run's), and the next complete run removes the failed
// run's record.
TEST(RunGuards, AFailedRunKeepsTheEarlierCompleteResults) {
  TempDir tmp;
  const fs::path dir = tmp.path / "case", out = tmp.path / "out";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << one_ball_case(vec("10 mm", "10 mm", "10 mm"), "[0.5, 0, 0]", {});
  const std::vector<std::string> run = {"run", dir.string(), "--out", out.string(), "--quiet", "--threads", "1"};
  ASSERT_EQ(run_bagdem(run, tmp.path).code, 0);
  const std::string complete = slurp(out / "results.h5");
  ASSERT_FALSE(complete.empty());

  std::vector<std::string> failing = run;
  for (const char* s : {"simulation.timestep=1 ms", "simulation.force_timestep=true", "particles.balls.velocities=[[10, 0, 0]]"})
    failing.insert(failing.end(), {"--set", s});
  const CmdResult f = run_bagdem(failing, tmp.path);
  ASSERT_EQ(f.code, 3) << f.err;
  EXPECT_NE(f.err.find("results.failed.h5"), std::string::npos) << f.err;
  EXPECT_EQ(slurp(out / "results.h5"), complete) << "the failed run changed the earlier complete results.h5";
  ASSERT_TRUE(fs::exists(out / "results.failed.h5"));
  const hid_t h = H5Fopen((out / "results.failed.h5").string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(h, 0);
  EXPECT_EQ(read_string_attribute(h, "status").rfind("failed", 0), 0u);
  H5Fclose(h);

  ASSERT_EQ(run_bagdem(run, tmp.path).code, 0);
  EXPECT_FALSE(fs::exists(out / "results.failed.h5")) << "a failed run's record outlived a later complete run";
  EXPECT_FALSE(fs::exists(out / "results.failed.xmf"));
}

}  // namespace
