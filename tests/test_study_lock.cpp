// One writer per study directory, through the bagdem binary: while a study (sweep, an ensemble,
// trade, calibrate, characterize, design) writes OUT it holds OUT/.bagdem-lock, as a run holds its
// own; another study given the same --out meanwhile is refused with exit code 2 before it touches
// anything. Before the lock, a second `bagdem sweep` into a directory a first one wrote deleted the
// first's point directories, its own runs failed, and it still exited 0.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "bagdem/io/output_lock.hpp"
#include "case_texts.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using bagdem::testing::CmdResult;
using bagdem::testing::run_bagdem;
using bagdem::testing::TempDir;

namespace {

// The names in a directory.
std::vector<std::string> listing(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}

}  // namespace

TEST(StudyLock, AStudyIntoADirectoryAnotherWritesIsRefusedAndTouchesNothing) {
  TempDir t;
  const fs::path dir = t.path / "case", out = t.path / "study";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << bagdem::testing::ball_on_sdof_floor();
  const std::string c = dir.string(), o = out.string();
  const std::vector<std::vector<std::string>> commands = {
      {"sweep", c, "--vary", "excitation.amplitude=\"0.05 N\",\"0.1 N\"", "--out", o},
      {"run", c, "--seeds", "2", "--out", o},
      {"trade", c, "--knobs", "none", "--out", o},
      {"calibrate", c, "--target", "mode=1,reduction_db=3", "--bounds", "\"0.03 N\",\"0.2 N\"", "--out", o},
      {"characterize", c, "--gamma", "0.1,0.4", "--amplitudes", "2", "--frequencies", "2", "--out", o},
      {"design", c, "--vary", "particles.ball.diameter=\"6 mm\",\"8 mm\"", "--budget", "0.5", "--out", o}};
  const bagdem::OutputLock held(out);  // as a study in progress holds it
  for (const auto& args : commands) {
    const CmdResult r = run_bagdem(args, t.path);
    EXPECT_EQ(r.code, 2) << args[0] << ": " << r.err << r.out;
    EXPECT_NE(r.err.find("another bagdem run is writing to this output directory"), std::string::npos) << args[0] << ": " << r.err;
    EXPECT_EQ(listing(out), std::vector<std::string>{".bagdem-lock"}) << args[0] << " wrote into a directory another study holds";
  }
}

// A study's rounds, maps and points lie inside its OUT: a run or a study into a directory inside an
// OUT another process holds is refused too (a sweep into a running calibration's OUT/round-00 used
// to replace its points, and the calibration reported the sweep's figure as its own). The study's
// own runs write there (the Study suite runs them).
TEST(StudyLock, ARunOrStudyInsideADirectoryAnotherWritesIsRefused) {
  TempDir t;
  const fs::path dir = t.path / "case", out = t.path / "cal";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << bagdem::testing::ball_on_sdof_floor();
  const bagdem::OutputLock held(out);  // as a calibration in progress holds it
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"sweep", dir.string(), "--vary", "excitation.amplitude=\"0.05 N\",\"0.1 N\"", "--out", (out / "round-00").string()},
           {"run", dir.string(), "--out", (out / "round-00" / "point-001").string()}}) {
    const CmdResult r = run_bagdem(args, t.path);
    EXPECT_EQ(r.code, 2) << args[0] << ": " << r.err << r.out;
    EXPECT_NE(r.err.find("lies inside " + out.string() + ", which another bagdem process (a study) is writing now"), std::string::npos)
        << args[0] << ": " << r.err;
    EXPECT_FALSE(fs::exists(out / "round-00")) << args[0] << " wrote inside a directory another study holds";
  }
}
