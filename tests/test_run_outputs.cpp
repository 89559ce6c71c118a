// What a run leaves in its output directory, through the bagdem binary and run_scene:
//  - a rerun starts from a clean slate: the tables of an earlier run (reduced.csv, compare.csv,
//    peaks.csv, sweep.csv, bare_curve.csv, summary.json, the drop test's files) are gone when the
//    new run writes none;
//  - `reduce` and `compare` refuse a case that differs from the one results.h5 was run with
//    (its resolved_config), naming the first difference, and change nothing;
//  - a resumed bag run's summary.json equals the uninterrupted run's, apart from the timings;
//  - while a run writes a directory (it holds OUT/.bagdem-lock), another run or drop test into it
//    is refused (exit 2) and changes nothing.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "bagdem/case/load_case.hpp"
#include "bagdem/io/output_lock.hpp"
#include "bagdem/run/runner.hpp"
#include "bag_support.hpp"
#include "case_texts.hpp"
#include "stepped_sine_support.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using bagdem::testing::CmdResult;
using bagdem::testing::run_bagdem;
using bagdem::testing::slurp;
using bagdem::testing::TempDir;

namespace {

// 30 soft balls shaken at 25 Hz in a box (as tests/test_restart.cpp): 0.2 s reduce to one row.
const std::string kShakenBox = bagdem::testing::shaken_box("0.2 s");

struct CaseDir {
  TempDir tmp;
  fs::path dir, out;
  explicit CaseDir(const std::string& toml) : dir(tmp.path / "case"), out(dir / "out") {
    fs::create_directories(dir);
    std::ofstream(dir / "case.toml") << toml;
  }
  CmdResult cli(const std::string& command, std::vector<std::string> more = {}) const {
    std::vector<std::string> args = {command, dir.string()};
    if (command == "run") args.insert(args.end(), {"--quiet", "--threads", "1"});
    args.insert(args.end(), more.begin(), more.end());
    return run_bagdem(args, tmp.path);
  }
};

TEST(RunOutputs, RerunRemovesTheEarlierRunsTables) {
  CaseDir c(kShakenBox);
  ASSERT_EQ(c.cli("run").code, 0);
  ASSERT_TRUE(fs::exists(c.out / "reduced.csv"));
  // Tables other commands and other kinds of run leave in the same directory, and a file of the user's.
  for (const char* f : {"compare.csv", "peaks.csv", "sweep.csv", "bare_curve.csv", "drop.csv", "drop_result.csv", "drop_result.toml"})
    std::ofstream(c.out / f) << "stale\n";
  std::ofstream(c.out / "notes.txt") << "mine\n";
  // Under two cycles after settling: the rerun reduces nothing and writes no reduced.csv.
  const CmdResult r = c.cli("run", {"--set", "simulation.duration=\"0.05 s\""});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("reduction skipped: the run measured"), std::string::npos) << "said, not silent: " << r.err;
  EXPECT_NE(r.err.find("needs at least 2: no reduced.csv"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(c.out / "summary.json"));
  EXPECT_TRUE(fs::exists(c.out / "results.h5"));
  for (const char* f : {"reduced.csv", "compare.csv", "peaks.csv", "sweep.csv", "bare_curve.csv", "drop.csv", "drop_result.csv", "drop_result.toml"})
    EXPECT_FALSE(fs::exists(c.out / f)) << f << " of the earlier run is still there";
  EXPECT_EQ(slurp(c.out / "notes.txt"), "mine\n") << "a file bagdem does not write was touched";
}

// Without the lock the second run truncated the first's results.h5.part as it created its own
// (HDF5 truncates before it locks), leaving the first run's file unreadable.
TEST(RunOutputs, ARunIntoADirectoryAnotherRunWritesIsRefused) {
  CaseDir c(kShakenBox);
  ASSERT_EQ(c.cli("run", {"--set", "simulation.duration=\"0.05 s\""}).code, 0);
  const std::string before = slurp(c.out / "results.h5");
  {
    const bagdem::OutputLock held(c.out);  // as a run in progress holds it
    for (const char* command : {"run", "drop"}) {
      const CmdResult r = c.cli(command);
      EXPECT_EQ(r.code, 2) << command << ": " << r.err;
      EXPECT_NE(r.err.find("another bagdem run is writing to this output directory"), std::string::npos) << r.err;
    }
    EXPECT_EQ(slurp(c.out / "results.h5"), before) << "the refused run touched results.h5";
    EXPECT_FALSE(fs::exists(c.out / "results.h5.part"));
    EXPECT_FALSE(fs::exists(c.out / "drop.csv"));
    // Nor do the commands that read its record and write tables beside it (they paired an earlier
    // record with the new run's tables).
    for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
             {"reduce", c.dir.string()}, {"export", c.out.string()}}) {
      const CmdResult r = run_bagdem(args, c.tmp.path);
      EXPECT_EQ(r.code, 2) << args[0] << ": " << r.err;
      EXPECT_NE(r.err.find("another bagdem run is writing to this output directory"), std::string::npos) << args[0] << ": " << r.err;
    }
    EXPECT_FALSE(fs::exists(c.out / "export.csv"));
  }
  EXPECT_EQ(c.cli("run", {"--set", "simulation.duration=\"0.05 s\""}).code, 0) << "the lock outlived its holder";
}

TEST(RunOutputs, ReduceRefusesAnotherCaseThanTheRun) {
  CaseDir c(kShakenBox);
  ASSERT_EQ(c.cli("run").code, 0);
  const std::string reduced = slurp(c.out / "reduced.csv");
  ASSERT_FALSE(reduced.empty());
  const CmdResult other = c.cli("reduce", {"--set", "cavity.motion.frequency=\"30 Hz\""});
  EXPECT_EQ(other.code, 2) << other.err;
  EXPECT_NE(other.err.find((c.out / "results.h5").string()), std::string::npos) << other.err;
  // The key is named with both values (it used to name a line of the case's text).
  EXPECT_NE(other.err.find("cavity.motion.frequency: was '25 Hz', now '30 Hz'"), std::string::npos) << other.err;
  EXPECT_EQ(slurp(c.out / "reduced.csv"), reduced) << "a refused reduce rewrote reduced.csv";
  // An edit of case.toml is refused the same way; the case as run reduces.
  std::ofstream(c.dir / "case.toml") << std::regex_replace(kShakenBox, std::regex("amplitude = \"2 mm\""), "amplitude = \"3 mm\"");
  const CmdResult edited = c.cli("reduce");
  EXPECT_EQ(edited.code, 2) << edited.err;
  EXPECT_NE(edited.err.find("amplitude"), std::string::npos) << edited.err;
  std::ofstream(c.dir / "case.toml") << kShakenBox;
  const CmdResult same = c.cli("reduce");
  EXPECT_EQ(same.code, 0) << same.err;
  EXPECT_EQ(slurp(c.out / "reduced.csv"), reduced);
  // A drop test of another case in the directory is refused before reduce rewrites reduced.csv (a
  // harmonic run's is rewritten by the reduction itself).
  ASSERT_EQ(c.cli("drop", {"--threads", "1", "--set", "interactions.default.restitution=0.9"}).code, 0);
  const CmdResult other_drop = c.cli("reduce");
  EXPECT_EQ(other_drop.code, 2) << other_drop.err;
  EXPECT_NE(other_drop.err.find("is the drop test of another case"), std::string::npos) << other_drop.err;
  EXPECT_EQ(slurp(c.out / "reduced.csv"), reduced) << "a refused reduce rewrote reduced.csv";
  fs::remove(c.out / "drop_result.csv"), fs::remove(c.out / "drop_result.toml");
  // output.skip_cycles chooses the cycles reduced, not the run: another value reduces (fewer cycles).
  const CmdResult later = c.cli("reduce", {"--set", "output.skip_cycles=2"});
  EXPECT_EQ(later.code, 0) << later.err;
  EXPECT_NE(slurp(c.out / "reduced.csv"), reduced);
}

// A complete run seals its series (a CRC-32 each, ResultsFile::seal): values changed in place
// afterwards (a damaged disk, an edit) are refused where they are read. Before, reduce gave new
// figures from a force scaled by 3 over 300 samples (exit 0).
TEST(RunOutputs, ReduceRefusesAResultsFileChangedAfterItsRun) {
  CaseDir c(kShakenBox);
  ASSERT_EQ(c.cli("run").code, 0);
  ASSERT_EQ(c.cli("reduce").code, 0);
  const std::string h5 = (c.out / "results.h5").string();
  {
    const hid_t f = H5Fopen(h5.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    const hid_t ds = H5Dopen2(f, "/cavity/force", H5P_DEFAULT);
    ASSERT_GE(ds, 0);
    ASSERT_GT(H5Aexists(ds, "crc32"), 0) << "the run did not seal its series";
    const hid_t space = H5Dget_space(ds);
    std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
    H5Sclose(space);
    ASSERT_GE(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
    v[v.size() / 2] += 1e-3;  // one value (a force may be zero: scaling it would change nothing)
    ASSERT_GE(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
    H5Dclose(ds);
    H5Fclose(f);
  }
  const CmdResult r = c.cli("reduce");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("/cavity/force: its values differ from the CRC-32 the run recorded"), std::string::npos) << r.err;
}

TEST(RunOutputs, CompareRefusesAnotherCaseThanTheSweep) {
  CaseDir c(bagdem::testing::rattling_ball_sweep());
  const CmdResult run = c.cli("run");
  ASSERT_EQ(run.code, 0) << run.err;
  const std::string compare = slurp(c.out / "compare.csv");
  ASSERT_FALSE(compare.empty());
  const CmdResult other = c.cli("compare", {"--set", "excitation.amplitude=\"2 N\""});
  EXPECT_EQ(other.code, 2) << other.err;
  EXPECT_NE(other.err.find((c.out / "results.h5").string()), std::string::npos) << other.err;
  EXPECT_NE(other.err.find("amplitude"), std::string::npos) << other.err;
  EXPECT_EQ(slurp(c.out / "compare.csv"), compare);
  const CmdResult reduce = c.cli("reduce", {"--set", "excitation.amplitude=\"2 N\""});
  EXPECT_EQ(reduce.code, 2) << reduce.err;
  const CmdResult peaks_other = c.cli("peaks", {"--set", "excitation.amplitude=\"2 N\""});
  EXPECT_EQ(peaks_other.code, 2) << peaks_other.err;  // it rewrote summary.json with another case's figures
  const CmdResult same = c.cli("compare");
  EXPECT_EQ(same.code, 0) << same.err;

  // peaks reads sweep.csv only where it is the text of results.h5's /sweep: a receptance halved by
  // hand, or a table cut short, is refused (it gave a 6-dB reduction from a 0.5-dB run, exit 0).
  ASSERT_EQ(c.cli("peaks").code, 0);
  const std::string sweep = slurp(c.out / "sweep.csv"), peaks = slurp(c.out / "peaks.csv");
  const std::size_t row2 = sweep.find('\n', sweep.find('\n') + 1) + 1, col = sweep.find(',', sweep.find(',', row2) + 1) + 1;
  const std::string halved = sweep.substr(0, col) + "0" + sweep.substr(sweep.find(',', col));  // its first response_re zeroed
  for (const std::string& text : {halved, sweep.substr(0, row2)}) {
    std::ofstream(c.out / "sweep.csv", std::ios::trunc) << text;
    const CmdResult edited = c.cli("peaks");
    EXPECT_EQ(edited.code, 2) << edited.err;
    EXPECT_NE(edited.err.find("results.h5's /sweep"), std::string::npos) << edited.err;
  }
  EXPECT_EQ(slurp(c.out / "peaks.csv"), peaks);

  // compare and reduce read reduced.csv only where it is the text of results.h5's /reduced: a cell
  // edited by hand is refused (C_eff x 10 changed compare.csv, exit 0).
  const std::string reduced = slurp(c.out / "reduced.csv");
  const std::size_t first = reduced.find('\n') + 1;
  std::ofstream(c.out / "reduced.csv", std::ios::trunc) << reduced.substr(0, first) + "1" + reduced.substr(first);  // its first frequency x 10 or so
  for (const char* command : {"compare", "reduce"}) {
    const CmdResult edited = c.cli(command);
    EXPECT_EQ(edited.code, 2) << command << ": " << edited.err;
    EXPECT_NE(edited.err.find("results.h5's /reduced"), std::string::npos) << edited.err;
  }
}

// summary.json without the keys that measure the machine (wall time, speed, threads).
std::string without_timings(const std::string& json) {
  std::istringstream in(json);
  std::string line, out;
  const std::regex timing("\"(wall_time_s|particle_steps_per_second|ns_per_particle_step|threads)\"");
  while (std::getline(in, line))
    if (!std::regex_search(line, timing)) out += line + "\n";
  return out;
}

TEST(RunOutputs, ResumedBagRunKeepsItsSummary) {
  // A bag of 20 steel balls settled for 1 ms, then shaken; checkpoints every 1 ms.
  using bagdem::testing::vec;
  const std::string toml = bagdem::testing::bag_scene("0.004 s", 4)
                               .set("simulation", "settle", "0.001 s")
                               .box("steel", vec("-25 mm", "-12 mm", "-12 mm"), vec("25 mm", "12 mm", "12 mm"))
                               .harmonic("1 mm", "30 Hz", "[1, 0, 0]")
                               .capsule_bag("7 mm", 200, 20)
                               .set("output", {{"frame_interval", "1 ms"}, {"checkpoint_interval", "1 ms"}});
  bagdem::testing::LoadedCase c(toml);
  ASSERT_TRUE(c.scene.bag);
  const std::uint64_t total = c.scene.total_steps(), settle = static_cast<std::uint64_t>(c.scene.settle / c.scene.dt);
  auto run = [&](const fs::path& out, long long stop, bool resume) {
    return bagdem::run_scene(c.scene, bagdem::testing::quiet_run(out, 1, stop, resume));
  };
  const fs::path a = c.dir.path / "A", b = c.dir.path / "B";
  ASSERT_TRUE(run(a, -1, false).complete);
  // Stopped after the settling (and a checkpoint after it), resumed to the end.
  EXPECT_FALSE(run(b, static_cast<long long>(settle + (total - settle) * 3 / 4), false).complete);
  ASSERT_TRUE(run(b, -1, true).complete);
  const std::string ja = slurp(a / "summary.json"), jb = slurp(b / "summary.json");
  ASSERT_NE(ja.find("\"bag\""), std::string::npos) << ja;
  EXPECT_EQ(without_timings(jb), without_timings(ja));
}

}  // namespace
