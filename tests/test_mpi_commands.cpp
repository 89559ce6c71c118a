// `bagdem design` and `bagdem calibrate` under mpirun with 2 ranks on one machine (study/pool.cpp,
// run_round): each of their studies (design's maps and its coupled check, calibrate's rounds) is
// shared among the ranks as a sweep's points are (rank r runs the points with index % 2 == r), the
// lead alone writes the tables and reports, and the tables are those of a serial run, byte for byte.
// 1. design: the rolling ball on the SDOF of tests/test_design.cpp (two maps of 12 runs, the best
//    checked with 2 starts); again with a run of one map damaged (the candidate is out, the ranks
//    go on alike); --check prints the plan once and runs nothing.
// 2. calibrate: the impact damper of tests/test_calibrate.cpp, its force fitted to the reduction at
//    0.06 N (a scan of 3, then refinement rounds). Resumed under 2 ranks it runs nothing and gives
//    the same answer; bad input is said once (exit 2); a fit on maps is refused under several ranks;
//    a later round whose recorded runs differ is refused by the lead (exit 1) without an MPI abort.
// The lead alone chooses each study and sends it; the other ranks run their share of what it sends.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "case_texts.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using bagdem::testing::CmdResult;
using bagdem::testing::run_bagdem;
using bagdem::testing::slurp;

namespace {

std::vector<std::string> with_out(std::vector<std::string> args, const fs::path& out) {
  args.push_back("--out");
  args.push_back(out.string());
  return args;
}

// How many of a study's points (point-NNN/point.done) each rank ran: {rank 0, rank 1}.
std::vector<int> points_per_rank(const fs::path& study) {
  std::vector<int> n(2, 0);
  for (const auto& e : fs::directory_iterator(study)) {
    const fs::path done = e.path() / "point.done";
    if (!fs::exists(done)) continue;
    const std::string text = slurp(done);
    EXPECT_NE(text.find("ranks = 2\n"), std::string::npos) << done;
    n[text.find("rank = 1\n") != std::string::npos ? 1 : 0]++;
  }
  return n;
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST(MpiCommands, DesignOnTwoRanksGivesTheSerialTable) {
#if defined(BAGDEM_WITH_MPI) && defined(BAGDEM_MPIEXEC)
  bagdem::testing::TempDir t;
  const fs::path dir = t.path / "case";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << bagdem::testing::ball_on_sdof_floor();
  const std::vector<std::string> args = {
      "design", dir.string(), "--vary", "particles.ball.diameter=\"6 mm\",\"8 mm\"", "--budget", "0.15", "--set", "primary.mass=\"0.02 kg\"",
      "--set", "primary.stiffness=\"315.827 N/m\"", "--set", "excitation.amplitude=\"2 mN\"", "--gamma", "0.02,0.5", "--amplitudes", "3",
      "--frequencies", "2", "--seeds", "2", "--cycles", "6", "--skip", "2", "--window-time", "0", "--skip-time", "0", "--verify", "2",
      "--verify-seeds", "2", "--jobs", "1"};
  const CmdResult serial = run_bagdem(with_out(args, t.path / "serial"), t.path);
  ASSERT_EQ(serial.code, 0) << serial.err;
  const CmdResult ranked = run_bagdem(with_out(args, t.path / "ranked"), t.path, 2);
  std::printf("  mpirun -np 2: %s", ranked.out.c_str());
  ASSERT_EQ(ranked.code, 0) << ranked.err;
  EXPECT_EQ(slurp(t.path / "ranked" / "design.csv"), slurp(t.path / "serial" / "design.csv"));
  std::string chosen = slurp(t.path / "ranked" / "chosen" / "case.toml");  // its header names its design.csv
  chosen.replace(chosen.find("/ranked/"), 8, "/serial/");
  EXPECT_EQ(chosen, slurp(t.path / "serial" / "chosen" / "case.toml"));
  EXPECT_EQ(count(ranked.out, "design complete"), 1u) << "the lead alone reports";
  // Both ranks ran points of each map and of the check.
  std::size_t maps = 0;
  for (const auto& m : fs::directory_iterator(t.path / "ranked" / "maps")) {
    ++maps;
    EXPECT_EQ(slurp(m.path() / "map.csv"), slurp(t.path / "serial" / "maps" / m.path().filename() / "map.csv"));
    EXPECT_EQ(points_per_rank(m.path()), (std::vector<int>{6, 6})) << m.path();
  }
  EXPECT_EQ(maps, 2u);
  EXPECT_EQ(points_per_rank(t.path / "ranked" / "verify"), (std::vector<int>{2, 2}));
  // A run of the 6-mm map damaged: the lead's map fails, the candidate is out, the other ranks go on
  // to the next study the lead sends; the same table as without MPI.
  for (const char* out : {"serial", "ranked"}) {
    for (const auto& m : fs::directory_iterator(t.path / out / "maps"))
      if (slurp(m.path() / "damper.toml").find("'particles.ball.diameter' = '0.006'") != std::string::npos) std::ofstream(m.path() / "point-000" / "reduced.csv") << "garbage\n";
    fs::remove_all(t.path / out / "verify");
  }
  const CmdResult serial2 = run_bagdem(with_out(args, t.path / "serial"), t.path);
  const CmdResult ranked2 = run_bagdem(with_out(args, t.path / "ranked"), t.path, 2);
  EXPECT_EQ(serial2.code, 0) << serial2.err;
  EXPECT_EQ(ranked2.code, 0) << ranked2.err;
  EXPECT_NE(ranked2.err.find("does not load"), std::string::npos) << ranked2.err;
  std::string table = slurp(t.path / "ranked" / "design.csv");  // the damaged run's path is in its status
  for (std::size_t at = table.find("/ranked/"); at != std::string::npos; at = table.find("/ranked/", at)) table.replace(at, 8, "/serial/");
  EXPECT_EQ(table, slurp(t.path / "serial" / "design.csv"));
  EXPECT_EQ(points_per_rank(t.path / "ranked" / "verify"), (std::vector<int>{1, 1})) << "the 8-mm ball checked alone";
  // --check under 2 ranks: the plan, once; nothing run.
  std::vector<std::string> plan_only = with_out(args, t.path / "checked");
  plan_only.push_back("--check");
  const CmdResult check = run_bagdem(plan_only, t.path, 2);
  EXPECT_EQ(check.code, 0) << check.err;
  EXPECT_EQ(count(check.out, "bagdem design"), 1u) << check.out;
  EXPECT_FALSE(fs::exists(t.path / "checked" / "maps"));
#else
  GTEST_SKIP() << "built without MPI (configure with -DBAGDEM_MPI=ON to test the ranks)";
#endif
}

// --dampers 2 (tests/test_design_pairs.cpp's beam): the pairs' table and chosen pair as without MPI,
// and both ranks run the pairs' coupled check.
TEST(MpiCommands, DesignOfPairsOnTwoRanksGivesTheSerialTable) {
#if defined(BAGDEM_WITH_MPI) && defined(BAGDEM_MPIEXEC)
  bagdem::testing::TempDir t;
  const fs::path dir = t.path / "case";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << bagdem::testing::rolling_balls_on_beam();
  const std::vector<std::string> args = {
      "design", dir.string(), "--vary", "particles.ball.diameter=\"6 mm\"", "--positions", "0.2,0.7", "--dampers", "2", "--budget", "0.1",
      "--gamma", "0.002,0.5", "--amplitudes", "4", "--frequencies", "2", "--seeds", "2", "--cycles", "6", "--skip", "2", "--window-time", "0",
      "--skip-time", "0", "--verify", "1", "--verify-seeds", "2", "--jobs", "1"};
  const CmdResult serial = run_bagdem(with_out(args, t.path / "serial"), t.path);
  ASSERT_EQ(serial.code, 0) << serial.err;
  const CmdResult ranked = run_bagdem(with_out(args, t.path / "ranked"), t.path, 2);
  ASSERT_EQ(ranked.code, 0) << ranked.err;
  for (const char* f : {"design.csv", "design-pairs.csv"}) EXPECT_EQ(slurp(t.path / "ranked" / f), slurp(t.path / "serial" / f)) << f;
  std::string chosen = slurp(t.path / "ranked" / "chosen-pair" / "case.toml");  // its header names its table
  chosen.replace(chosen.find("/ranked/"), 8, "/serial/");
  EXPECT_EQ(chosen, slurp(t.path / "serial" / "chosen-pair" / "case.toml"));
  EXPECT_EQ(points_per_rank(t.path / "ranked" / "verify-pairs"), (std::vector<int>{1, 1}));
#else
  GTEST_SKIP() << "built without MPI (configure with -DBAGDEM_MPI=ON to test the ranks)";
#endif
}

TEST(MpiCommands, CalibrateOnTwoRanksGivesTheSerialCalibration) {
#if defined(BAGDEM_WITH_MPI) && defined(BAGDEM_MPIEXEC)
  bagdem::testing::TempDir t;
  const fs::path dir = t.path / "case";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << bagdem::testing::impact_damper_sdof();
  const std::vector<std::string> args = {"calibrate", dir.string(), "--target", "mode=1,reduction_db=4.6", "--bounds", "\"0.03 N\",\"0.2 N\"",
                                         "--seeds", "1", "--jobs", "1", "--scan", "3"};
  const CmdResult serial = run_bagdem(with_out(args, t.path / "serial"), t.path);
  ASSERT_EQ(serial.code, 0) << serial.err << serial.out;
  const CmdResult ranked = run_bagdem(with_out(args, t.path / "ranked"), t.path, 2);
  std::printf("  mpirun -np 2: %s", ranked.out.c_str());
  ASSERT_EQ(ranked.code, 0) << ranked.err;
  for (const char* f : {"calibrate.csv", "calibration.json"}) EXPECT_EQ(slurp(t.path / "ranked" / f), slurp(t.path / "serial" / f)) << f;
  EXPECT_EQ(count(ranked.out, "calibration complete"), 1u) << "the lead alone reports";
  const std::vector<int> first = points_per_rank(t.path / "ranked" / "round-00");
  EXPECT_EQ(first, (std::vector<int>{2, 1})) << "the scan's 3 values shared";
  // Resumed under 2 ranks: every round is done, nothing runs, the same answer.
  const std::string before = slurp(t.path / "ranked" / "calibration.json");
  const CmdResult again = run_bagdem(with_out(args, t.path / "ranked"), t.path, 2);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_EQ(slurp(t.path / "ranked" / "calibration.json"), before);
  EXPECT_NE(again.err.find("resuming"), std::string::npos) << again.err;
  // Bad input under 2 ranks: said once, exit 2, nothing written.
  const CmdResult bad = run_bagdem({"calibrate", dir.string(), "--target", "mode=7,reduction_db=3", "--out", (t.path / "bad").string()}, t.path, 2);
  EXPECT_EQ(bad.code, 2) << bad.err;
  EXPECT_EQ(count(bad.err, "error:"), 1u) << bad.err;
  EXPECT_FALSE(fs::exists(t.path / "bad"));
  // A fit on maps runs no simulation: refused under several ranks, said once.
  const CmdResult maps = run_bagdem({"calibrate", dir.string(), "--target", "mode=1,reduction_db=3", "--maps", (t.path / "serial").string(),
                                     "--out", (t.path / "maps").string()}, t.path, 2);
  EXPECT_EQ(maps.code, 2) << maps.err;
  EXPECT_EQ(count(maps.err, "gains nothing from 2 MPI ranks"), 1u) << maps.err;
  // A round after the first whose recorded runs differ (here its first point's overrides): the
  // lead refuses it (exit 1, said once), the other rank stops with it, no MPI abort.
  const fs::path round1 = t.path / "ranked" / "round-01" / "point-000" / "point.toml";
  ASSERT_TRUE(fs::exists(round1)) << "a scan of 3 is refined in later rounds";
  std::string text = slurp(round1);
  text.replace(text.find("set = ["), 7, "set = [\"primary.damping_ratio=0.5\",");
  std::ofstream(round1) << text;
  const CmdResult stale = run_bagdem(with_out(args, t.path / "ranked"), t.path, 2);
  EXPECT_EQ(stale.code, 1) << stale.err;
  EXPECT_EQ(count(stale.err, "error:"), 1u) << stale.err;
  EXPECT_NE(stale.err.find("round-01"), std::string::npos) << stale.err;
  EXPECT_EQ(stale.err.find("MPI_ABORT"), std::string::npos) << stale.err;
#else
  GTEST_SKIP() << "built without MPI (configure with -DBAGDEM_MPI=ON to test the ranks)";
#endif
}
