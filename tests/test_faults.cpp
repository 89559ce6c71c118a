// Faults around a run, through the bagdem binary:
//  - a checkpoint whose bytes changed is refused (its checksum), as is a truncated one;
//  - SIGTERM and SIGINT stop a run at its next step: results.h5.part reads status "interrupted",
//    a checkpoint is left, the exit code is 128 + the signal, and --resume ends with the same bits
//    as the run uninterrupted; the same for a sweep (stopped mid-point, resumed to the same sweep);
//  - a full disk (tests/full_disk: writes to files fail with ENOSPC after a budget of bytes) ends
//    the run with exit 1 naming the file, not a crash, and an earlier complete results.h5 in the
//    same directory stays as it was.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "bagdem/case/load_case.hpp"
#include "bagdem/run/runner.hpp"
#include "h5_read.hpp"
#include "results_compare.hpp"
#include "case_texts.hpp"
#include "support.hpp"
#include "stepped_sine_support.hpp"

namespace fs = std::filesystem;
using bagdem::testing::CmdResult;
using bagdem::testing::run_bagdem;
using bagdem::testing::shell_quote;
using bagdem::testing::slurp;
using bagdem::testing::shaken_box;
using bagdem::testing::TempDir;

namespace {

struct CaseDir {
  TempDir tmp;
  fs::path dir, out;
  explicit CaseDir(const std::string& toml) : dir(tmp.path / "case"), out(tmp.path / "out") {
    fs::create_directories(dir);
    std::ofstream(dir / "case.toml") << toml;
  }
  CmdResult run(std::vector<std::string> more = {}) const {
    std::vector<std::string> args = {"run", dir.string(), "--out", out.string(), "--quiet", "--threads", "1"};
    args.insert(args.end(), more.begin(), more.end());
    return run_bagdem(args, tmp.path);
  }
};

// The root attribute "status" of an HDF5 file.
std::string status_of(const fs::path& h5) {
  const hid_t f = H5Fopen(h5.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(f, 0) << h5;
  if (f < 0) return "";
  const std::string s = bagdem::testing::read_string_attribute(f, "status");
  H5Fclose(f);
  return s;
}

// ---- checksummed checkpoints ----------------------------------------------------------------------

// A run stopped as if killed after `steps` steps (RunOptions::stop_after_steps): it leaves
// results.h5.part and checkpoint.bin.
void stop_after(const CaseDir& c, long long steps) {
  const bagdem::RunReport r = bagdem::run_scene(bagdem::load_case(c.dir.string()), bagdem::testing::quiet_run(c.out, 1, steps));
  ASSERT_FALSE(r.complete);
  ASSERT_TRUE(fs::exists(c.out / "checkpoint.bin"));
}

void flip_bytes(const fs::path& p, std::size_t at, std::size_t count) {
  std::fstream f(p, std::ios::binary | std::ios::in | std::ios::out);
  ASSERT_TRUE(f) << p;
  for (std::size_t k = 0; k < count; ++k) {
    f.seekg(static_cast<std::streamoff>(at + k));
    const char b = static_cast<char>(f.get() ^ 0x5a);
    f.seekp(static_cast<std::streamoff>(at + k));
    f.put(b);
  }
  ASSERT_TRUE(f) << p;
}

TEST(Faults, CheckpointWithFlippedBytesIsRefused) {
  CaseDir c(shaken_box("0.1 s", "10 ms"));
  stop_after(c, 2500);
  const fs::path ckpt = c.out / "checkpoint.bin";
  const std::size_t size = fs::file_size(ckpt);
  ASSERT_GT(size, 1000u);
  // Four bytes in the simulation's state (the end of the file: velocities, histories).
  flip_bytes(ckpt, size - size / 4, 4);
  const CmdResult r = c.run({"--resume"});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(ckpt.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("is corrupt: checksum"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("without --resume"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(c.out / "results.h5")) << "a refused resume wrote results";
}

TEST(Faults, TruncatedCheckpointIsRefused) {
  CaseDir c(shaken_box("0.1 s", "10 ms"));
  stop_after(c, 2500);
  const fs::path ckpt = c.out / "checkpoint.bin";
  fs::resize_file(ckpt, fs::file_size(ckpt) - 100);
  const CmdResult r = c.run({"--resume"});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(ckpt.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("without --resume"), std::string::npos) << r.err;
}

// The file offset of the first chunk of a chunked dataset (where its first rows' bytes lie).
haddr_t first_chunk_address(const fs::path& h5, const char* dataset) {
  const hid_t f = H5Fopen(h5.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t ds = H5Dopen2(f, dataset, H5P_DEFAULT);
  const hsize_t origin[3] = {0, 0, 0};
  unsigned mask = 0;
  haddr_t addr = HADDR_UNDEF;
  hsize_t size = 0;
  EXPECT_GE(H5Dget_chunk_info_by_coord(ds, origin, &mask, &addr, &size), 0) << dataset;
  H5Dclose(ds);
  H5Fclose(f);
  return addr;
}

// A resume continues only from what its checkpoint recorded: results.h5.part with 256 bytes
// overwritten in its first frame (data the checkpoint covers), or in its superblock, is refused
// with exit 2, left as it was, and nothing is written. It used to resume and finish "complete"
// with M_eff/M_bag 1.5e124.
TEST(Faults, AResumeFromADamagedPartialResultsFileIsRefused) {
  for (const bool superblock : {false, true}) {
    CaseDir c(shaken_box("0.1 s", "10 ms"));
    stop_after(c, 2500);
    const fs::path part = c.out / "results.h5.part";
    const haddr_t at = superblock ? 0 : first_chunk_address(part, "/frames/position");
    ASSERT_NE(at, HADDR_UNDEF);
    {
      std::fstream f(part, std::ios::binary | std::ios::in | std::ios::out);
      f.seekp(static_cast<std::streamoff>(at));
      const std::string junk(256, '\x7f');
      f.write(junk.data(), static_cast<std::streamsize>(junk.size()));
      ASSERT_TRUE(f);
    }
    const std::string damaged = slurp(part);
    const CmdResult r = c.run({"--resume"});
    EXPECT_EQ(r.code, 2) << (superblock ? "superblock: " : "frame 0: ") << r.err;
    EXPECT_EQ(slurp(part), damaged) << "the refused resume changed the file it refused (it used to cut it first)";
    EXPECT_NE(r.err.find(part.string()), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("without --resume"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(c.out / "results.h5")) << "a refused resume wrote results";
    EXPECT_FALSE(fs::exists(c.out / "summary.json"));
  }
}

// ---- SIGTERM and SIGINT ---------------------------------------------------------------------------

// `bagdem run` started in the background (stdout and stderr to files in the case's directory).
struct Background {
  pid_t pid = -1;
  fs::path err;
  Background(const CaseDir& c, const std::vector<std::string>& more) : err(c.tmp.path / "bg_stderr.txt") {
    std::vector<std::string> args = {BAGDEM_BINARY, "run", c.dir.string(), "--out", c.out.string(), "--threads", "1"};
    args.insert(args.end(), more.begin(), more.end());
    pid = fork();
    if (pid == 0) {
      FILE* e = std::freopen(err.c_str(), "w", stderr);
      FILE* o = std::freopen((c.tmp.path / "bg_stdout.txt").c_str(), "w", stdout);
      if (!e || !o) _exit(127);
      std::vector<char*> argv;
      for (std::string& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(argv[0], argv.data());
      _exit(127);
    }
  }
  // Exit status: the code, or -signal when a signal ended it.
  int wait() {
    int st = 0;
    waitpid(pid, &st, 0);
    pid = -1;
    return WIFEXITED(st) ? WEXITSTATUS(st) : WIFSIGNALED(st) ? -WTERMSIG(st) : -1000;
  }
  ~Background() {
    if (pid > 0) kill(pid, SIGKILL), wait();
  }
};

// Waits until the run is stepping: its header line is out (the handlers are installed before it)
// and results.h5.part has grown after its first frame.
bool wait_until_stepping(const Background& b, const fs::path& part) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  std::uintmax_t first = 0;
  while (std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (slurp(b.err).find("bagdem run") == std::string::npos || !fs::exists(part)) continue;
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(part, ec);
    if (ec) continue;
    if (first == 0) first = size;
    else if (size > first) return true;
  }
  return false;
}

void expect_interrupted_by(int sig, int code) {
  // Long enough that the signal comes mid-run on any machine (about 77 000 steps of 30 balls).
  CaseDir c(shaken_box("1 s"));
  Background b(c, {});
  ASSERT_TRUE(wait_until_stepping(b, c.out / "results.h5.part")) << slurp(b.err);
  ASSERT_EQ(kill(b.pid, sig), 0);
  EXPECT_EQ(b.wait(), code) << slurp(b.err);
  EXPECT_FALSE(fs::exists(c.out / "results.h5"));
  EXPECT_FALSE(fs::exists(c.out / "summary.json"));
  ASSERT_TRUE(fs::exists(c.out / "results.h5.part"));
  EXPECT_EQ(status_of(c.out / "results.h5.part"), "interrupted");
  EXPECT_TRUE(fs::exists(c.out / "checkpoint.bin")) << "no checkpoint to resume from";
  EXPECT_NE(slurp(b.err).find("--resume"), std::string::npos) << slurp(b.err);
}

TEST(Faults, SigintLeavesAnInterruptedRun) { expect_interrupted_by(SIGINT, 130); }

TEST(Faults, SigtermLeavesAnInterruptedRunThatResumesToTheSameBits) {
  // Without periodic checkpoints: the one written at the signal is what --resume continues.
  CaseDir c(shaken_box("1 s"));
  const CaseDir whole(shaken_box("1 s"));
  Background b(c, {});
  ASSERT_TRUE(wait_until_stepping(b, c.out / "results.h5.part")) << slurp(b.err);
  ASSERT_EQ(kill(b.pid, SIGTERM), 0);
  ASSERT_EQ(b.wait(), 143) << slurp(b.err);
  EXPECT_EQ(status_of(c.out / "results.h5.part"), "interrupted");
  ASSERT_TRUE(fs::exists(c.out / "checkpoint.bin"));
  const CmdResult resumed = c.run({"--resume"});
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  const CmdResult ref = whole.run();
  ASSERT_EQ(ref.code, 0) << ref.err;
  EXPECT_EQ(status_of(c.out / "results.h5"), "complete");
  EXPECT_FALSE(fs::exists(c.out / "checkpoint.bin"));
  bagdem::testing::expect_same_datasets(whole.out / "results.h5", c.out / "results.h5");
}

TEST(Faults, SigtermDuringASweepResumesToTheSameSweep) {
  CaseDir c(bagdem::testing::rattling_ball_sweep());
  const CaseDir whole(bagdem::testing::rattling_ball_sweep());
  Background b(c, {});
  // Stepping: the progress line of a point's cycle is out.
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < until && slurp(b.err).find("cycle") == std::string::npos)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_NE(slurp(b.err).find("cycle"), std::string::npos) << slurp(b.err);
  ASSERT_EQ(kill(b.pid, SIGTERM), 0);
  ASSERT_EQ(b.wait(), 143) << slurp(b.err);
  EXPECT_EQ(status_of(c.out / "results.h5.part"), "interrupted");
  ASSERT_TRUE(fs::exists(c.out / "checkpoint.bin"));
  EXPECT_NE(slurp(b.err).find("--resume"), std::string::npos) << slurp(b.err);
  const CmdResult resumed = c.run({"--resume"});
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  const CmdResult ref = whole.run();
  ASSERT_EQ(ref.code, 0) << ref.err;
  EXPECT_EQ(status_of(c.out / "results.h5"), "complete");
  bagdem::testing::expect_same_sweep(whole.out, c.out);
}

// A study stopped by SIGTERM says so (it was a silent exit 143): the points done are kept, the
// running one is stopped and nothing is merged; the same command then goes on and completes.
TEST(Faults, SigtermDuringAStudySaysWhatItKeptAndTheSameCommandGoesOn) {
  CaseDir c(shaken_box("0.3 s"));
  const std::vector<std::string> study = {"--seeds", "3"};
  Background b(c, study);
  // A start done (as many run at once as there are cores): the signal comes while the others run or wait.
  auto any_done = [&] {
    for (const char* p : {"point-000", "point-001", "point-002"})
      if (fs::exists(c.out / p / "point.done")) return true;
    return false;
  };
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < until && !any_done() && slurp(b.err).find("error") == std::string::npos)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_TRUE(any_done()) << slurp(b.err);
  ASSERT_EQ(kill(b.pid, SIGTERM), 0);
  ASSERT_EQ(b.wait(), 143) << slurp(b.err);
  const std::string err = slurp(b.err);
  std::size_t done = 0;
  for (const char* p : {"point-000", "point-001", "point-002"}) done += fs::exists(c.out / p / "point.done");
  ASSERT_GE(done, 1u);
  EXPECT_NE(err.find("stopped by SIGTERM: " + std::to_string(done) + " of 3 points done and kept"), std::string::npos) << err;
  EXPECT_NE(err.find("The same command goes on"), std::string::npos) << err;
  EXPECT_EQ(err.find("error:"), std::string::npos) << "a signal is not a fault: " << err;
  EXPECT_NE(err.find("interrupted: "), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(c.out / "reduced.csv")) << "a stopped study merged its tables";
  // A start stopped while it ran says, last in its log, that the study runs it afresh.
  std::size_t noted = 0;
  for (const char* p : {"point-000", "point-001", "point-002"}) {
    if (fs::exists(c.out / p / "point.done") || !fs::exists(c.out / p / "log.txt")) continue;
    const std::string log = slurp(c.out / p / "log.txt");
    EXPECT_NE(log.find(std::string("# bagdem run --seeds: ") + p + " stopped by SIGTERM with the study; the same command runs it afresh"),
              std::string::npos) << log;
    ++noted;
  }
  EXPECT_NE(err.find(", " + std::to_string(noted) + " running stopped"), std::string::npos) << "the starts noted are those stopped: " << err;
  EXPECT_NE(err.find("run --seeds (" + c.out.string() + ") stopped by SIGTERM"), std::string::npos) << "named as the command it is: " << err;
  const CmdResult again = c.run(study);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.err.find("resuming: " + std::to_string(done) + " of 3 points done by an earlier run, skipped"), std::string::npos) << again.err;
  EXPECT_TRUE(fs::exists(c.out / "point-002" / "point.done"));
}

// ---- a full disk ----------------------------------------------------------------------------------

// `bagdem run` with the full-disk library preloaded: files take `bytes` bytes in all.
CmdResult run_on_full_disk(const CaseDir& c, long long bytes) {
  const std::string cmd = "LD_PRELOAD=" + shell_quote(BAGDEM_FULL_DISK_LIB) + " BAGDEM_FULL_DISK_BYTES=" +
                          std::to_string(bytes) + " " + shell_quote(BAGDEM_BINARY) + " run " + shell_quote(c.dir.string()) +
                          " --out " + shell_quote(c.out.string()) + " --quiet --threads 1 >" +
                          shell_quote((c.tmp.path / "full_out.txt").string()) + " 2>" +
                          shell_quote((c.tmp.path / "full_err.txt").string()) + " </dev/null";
  const int st = std::system(cmd.c_str());
  CmdResult r;
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  if (WIFSIGNALED(st)) r.code = -WTERMSIG(st);
  r.out = slurp(c.tmp.path / "full_out.txt");
  r.err = slurp(c.tmp.path / "full_err.txt");
  return r;
}

TEST(Faults, FullDiskExitsOneAndKeepsTheEarlierResults) {
  CaseDir c(shaken_box("0.06 s", "10 ms"));
  ASSERT_EQ(c.run().code, 0);
  const std::string earlier = slurp(c.out / "results.h5");
  ASSERT_FALSE(earlier.empty());
  // The disk fills while results.h5.part is created, a quarter and half way through the run, near
  // its end, and later (HDF5 writes more than the file's size; the checkpoints are written too).
  const auto size = static_cast<long long>(earlier.size());
  for (long long bytes : {2000LL, size / 4, size / 2, size * 9 / 10, 2 * size, 4 * size}) {
    SCOPED_TRACE("disk full after " + std::to_string(bytes) + " bytes");
    const CmdResult r = run_on_full_disk(c, bytes);
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_NE(r.err.find("error: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.out.string() + "/"), std::string::npos) << "the file is not named: " << r.err;
    EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
    EXPECT_TRUE(slurp(c.out / "results.h5") == earlier) << "the earlier complete results changed";
    EXPECT_EQ(status_of(c.out / "results.h5"), "complete");
    EXPECT_TRUE(fs::exists(c.out / "results.h5.part")) << "the partial results lost their .part name";
  }
  // A run with room completes over them.
  const CmdResult ok = c.run();
  EXPECT_EQ(ok.code, 0) << ok.err;
  EXPECT_FALSE(fs::exists(c.out / "results.h5.part"));
}

}  // namespace
