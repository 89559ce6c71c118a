// Test support shared by the suites that work through files and the command line: a temporary
// directory removed with its contents, and running the bagdem binary with its output captured.
#pragma once
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bagdem/run/runner.hpp"

namespace bagdem::testing {

// A fresh directory under the system temp dir, removed with everything in it.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    std::random_device rd;
    path = std::filesystem::temp_directory_path() / ("bagdem_test_" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  // Writes a file in the directory (e.g. "case.toml").
  void write(const std::string& name, const std::string& text) const { std::ofstream(path / name) << text; }
  std::string str() const { return path.string(); }
};

inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') q += "'\\''";
    else q += c;
  }
  return q + "'";
}

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

struct CmdResult {
  int code = -1;
  std::string out, err;
};

#ifdef BAGDEM_BINARY
// Runs `bagdem <args...>` (each argument quoted), capturing stdout and stderr in `dir`.
// With `ranks` > 0, under `mpirun -np ranks` (a build with MPI; BAGDEM_MPIEXEC).
inline CmdResult run_bagdem(const std::vector<std::string>& args, const std::filesystem::path& dir, [[maybe_unused]] int ranks = 0) {
  const auto out = dir / "stdout.txt", err = dir / "stderr.txt";
  std::string cmd = shell_quote(BAGDEM_BINARY);
#ifdef BAGDEM_MPIEXEC
  if (ranks > 0) {
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    cmd = shell_quote(BAGDEM_MPIEXEC) + " --oversubscribe --allow-run-as-root -np " + std::to_string(ranks) + " " + cmd;
  }
#endif
  for (const auto& a : args) cmd.append(" ").append(shell_quote(a));
  cmd.append(" >").append(shell_quote(out.string()));
  cmd.append(" 2>").append(shell_quote(err.string()));
  cmd.append(" </dev/null");
  const int st = std::system(cmd.c_str());
  CmdResult r;
  r.code = (st != -1 && WIFEXITED(st)) ? WEXITSTATUS(st) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}
#endif

// A run's options in the tests: outputs in `out`, no progress line, `threads` threads (0: all
// cores), stopped as if killed after `stop_after` steps (-1: never), resumed from its checkpoint.
inline RunOptions quiet_run(const std::filesystem::path& out, int threads = 1, long long stop_after = -1,
                            bool resume = false) {
  RunOptions o;
  o.out_dir = out.string();
  o.threads = threads;
  o.quiet = true;
  o.stop_after_steps = stop_after;
  o.resume = resume;
  return o;
}

}  // namespace bagdem::testing
