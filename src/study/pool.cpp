// The points as child processes (study/study.hpp, run_points): fork + exec of the bagdem binary,
// at most J at once, each child's stdout and stderr in its point's log.txt, point.done written
// (temporary name + rename) once a child exited 0, and a progress line at each change.
//
// Children are started with fork/exec rather than posix_spawn because they must ask the kernel to
// kill them when the sweep dies (prctl PR_SET_PDEATHSIG), which posix_spawn cannot do. Between fork
// and exec the child calls only async-signal-safe functions (the sweep may hold MPI's threads).
// The sweep polls its children with waitpid(pid, WNOHANG) every 50 ms instead of waiting on any
// child, so that it never reaps a process it did not start (an MPI library may have its own).
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <deque>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <thread>

#include "bagdem/error.hpp"
#include "bagdem/interrupt.hpp"
#include "bagdem/io/atomic_file.hpp"
#include "bagdem/io/output_lock.hpp"
#include "bagdem/study/study.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string duration_text(double s) {
  char b[32];
  if (s < 120) std::snprintf(b, sizeof b, "%.0f s", s);
  else if (s < 7200) std::snprintf(b, sizeof b, "%.1f min", s / 60);
  else std::snprintf(b, sizeof b, "%.1f h", s / 3600);
  return b;
}

std::string host_name() {
  char b[256] = {};
  if (gethostname(b, sizeof b - 1) != 0) return "?";
  return b;
}

// The last `n` non-empty lines of a log, each indented (the run's own error message ends it).
std::string log_tail(const fs::path& log, std::size_t n) {
  std::ifstream f(log);
  std::deque<std::string> lines;
  for (std::string l; std::getline(f, l);) {
    // A progress line overwrites itself with '\r': keep what was written last.
    while (!l.empty() && l.back() == '\r') l.pop_back();
    if (const auto cr = l.rfind('\r'); cr != std::string::npos) l = l.substr(cr + 1);
    if (l.find_first_not_of(" \t\r") == std::string::npos) continue;
    lines.push_back(l);
    if (lines.size() > n) lines.pop_front();
  }
  std::string o;
  for (const auto& l : lines) o += "    | " + l + "\n";
  return o;
}

std::string exit_text(int code) {
  if (code > 128) return "killed by signal " + std::to_string(code - 128);
  switch (code) {
    case 1: return "exit 1: a system error";
    case 2: return "exit 2: bad input";
    case 3: return "exit 3: the run went unstable";
    case 127: return "exit 127: the bagdem binary could not be executed";
    default: return "exit " + std::to_string(code);
  }
}

std::string quoted(const std::string& a) {
  if (!a.empty() && a.find_first_of(" \t\"'\\$`;&|<>()*?[]{}") == std::string::npos) return a;
  std::string q = "'";
  for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// The child's argument list: bagdem run CASE --set ... --out DIR --quiet --threads T.
std::vector<std::string> run_arguments(const Plan& plan, const Point& p, const PoolOptions& opt) {
  std::vector<std::string> a = {"bagdem", "run", plan.spec.case_dir};
  for (const std::string& s : p.sets) a.insert(a.end(), {"--set", s});
  a.insert(a.end(), {"--out", plan.point_dir(p), "--quiet", "--threads", std::to_string(opt.threads)});
  return a;
}

// Starts one child with its stdout and stderr on `log_fd` and stdin on /dev/null.
pid_t spawn(const std::string& executable, const std::vector<std::string>& args, int log_fd, int null_fd) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::system_error(errno, std::generic_category(), "fork");
  if (pid == 0) {
    // Die with the sweep; if it died before this line ran, the signal was never armed: leave.
    if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || getppid() != parent) _exit(127);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);  // the sweep's blocked signals are not the run's
    if (dup2(null_fd, 0) < 0 || dup2(log_fd, 1) < 0 || dup2(log_fd, 2) < 0) _exit(127);
    // MPI's sockets and the like stay with the sweep.
    if (close_range(3, ~0U, 0) != 0)
      for (int fd = 3; fd < 1024; ++fd) close(fd);
    execv(executable.c_str(), argv.data());
    static const char msg[] = "bagdem: a study cannot execute the bagdem binary\n";
    const ssize_t ignored = write(2, msg, sizeof msg - 1);
    (void)ignored;
    _exit(127);
  }
  return pid;
}

struct Child {
  pid_t pid = -1;
  std::size_t index = 0;
  Clock::time_point start;
};

// Kills the children still running and reaps them, each taken out of `running` as it is reaped (its
// pid is then free for another process). reaped(child, status), when given, is told of each:
// status is -1 if waitpid failed (no status known).
void kill_and_reap(std::vector<Child>& running, const std::function<void(const Child&, int)>& reaped = nullptr) {
  for (const Child& c : running) kill(c.pid, SIGKILL);
  while (!running.empty()) {
    const Child c = running.back();
    int st = 0;
    pid_t r;
    do r = waitpid(c.pid, &st, 0);
    while (r < 0 && errno == EINTR);
    running.pop_back();
    if (reaped) reaped(c, r == c.pid ? st : -1);
  }
}

// Kills and reaps the children still running if run_points leaves by an exception.
struct Reaper {
  std::vector<Child>& running;
  ~Reaper() { kill_and_reap(running); }
};

// A point started: its directory made afresh (whatever an interrupted run left is not trusted),
// point.toml, the log's head line, the child's process.
Child start_point(const Plan& plan, std::size_t index, const PoolOptions& opt, const std::string& host, int null_fd) {
  const Point& p = plan.points[index];
  const fs::path dir = plan.point_dir(p);
  refuse_if_locked(dir);
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_atomically(dir / "point.toml", point_toml(plan, p));
  const std::vector<std::string> args = run_arguments(plan, p, opt);
  const std::string log = (dir / "log.txt").string();
  const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) throw std::system_error(errno, std::generic_category(), "cannot write " + log);
  std::string head = "# bagdem " + plan.spec.command + ": " + p.name + " on rank " + std::to_string(opt.rank) + " of " + std::to_string(opt.ranks) + " (" +
                     host + "):";
  for (const std::string& a : args) head.append(" ").append(quoted(a));
  head += "\n";
  const ssize_t wrote = write(fd, head.data(), head.size());
  Child c;
  c.index = index;
  c.start = Clock::now();
  try {
    if (wrote != static_cast<ssize_t>(head.size())) throw std::system_error(errno, std::generic_category(), "cannot write " + log);
    c.pid = spawn(opt.executable, args, fd, null_fd);
  } catch (...) {
    close(fd);
    throw;
  }
  close(fd);
  return c;
}

// A point the signal stopped: the last line of its log says that the study runs it afresh (its run may
// have written "continue with --resume", which the study does not do: its directory is made anew).
void note_stopped(const Plan& plan, const Child& c, int sig) {
  const fs::path path = fs::path(plan.point_dir(plan.points[c.index])) / "log.txt";
  char last = '\n';
  if (std::ifstream in(path, std::ios::binary); in.seekg(-1, std::ios::end)) in.get(last);
  std::ofstream log(path, std::ios::app);
  if (last != '\n') log << "\n";  // a run killed in the middle of a line
  log << "# bagdem " << plan.spec.command << ": " << plan.points[c.index].name << " stopped by " << signal_name(sig)
      << " with the study; the same command runs it afresh (its checkpoint and partial results are not used)\n";
}

// The study stopped by signal sig: its running points let end for a moment, then killed, and reaped
// (one that exited 0 by then is finished, and kept: `finish`), each stopped point's log noted (note_stopped), and
// Interrupted thrown, saying what was kept (done: the points done by then).
[[noreturn]] void stop_points(const Plan& plan, int sig, std::vector<Child>& running, std::vector<Child>& stopped, const std::size_t& done,
                              std::size_t total, const std::function<void(const Child&, int)>& finish) {
  std::vector<std::pair<Child, int>> ended;  // finished after the kill and reap, which never throw
  // A run that ends on its own within a moment of the signal (it was finishing, or its own guard
  // stops it) is let end: one that exits 0 is kept. Then the rest are killed.
  for (const auto until = Clock::now() + std::chrono::milliseconds(200); !running.empty() && Clock::now() < until;) {
    for (std::size_t k = 0; k < running.size();) {
      int st = 0;
      if (waitpid(running[k].pid, &st, WNOHANG) == running[k].pid) {
        ended.emplace_back(running[k], st);
        running.erase(running.begin() + static_cast<long>(k));
      } else {
        ++k;
      }
    }
    if (!running.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill_and_reap(running, [&](const Child& c, int st) { ended.emplace_back(c, st); });
  for (const auto& [c, st] : ended)
    if (st >= 0 && WIFEXITED(st) && WEXITSTATUS(st) == 0) finish(c, st);
    else stopped.push_back(c);
  for (const Child& c : stopped) note_stopped(plan, c, sig);
  throw Interrupted(sig, plan.spec.command + " (" + plan.spec.out_dir + ") stopped by " + signal_name(sig) + ": " + std::to_string(done) +
                             " of " + std::to_string(total) + " points done and kept (each with its point.done), " +
                             std::to_string(stopped.size()) + " running stopped, nothing merged. The same command goes on where it "
                             "stopped (the stopped points start afresh)");
}

// A point's child ended with `status`: point.done when it exited 0, else the end of its log.
PointOutcome finish_point(const Plan& plan, const Child& c, int status, const PoolOptions& opt, const std::string& host,
                          const std::string& prefix) {
  const Point& p = plan.points[c.index];
  const fs::path dir = plan.point_dir(p);
  PointOutcome o;
  o.index = c.index;
  o.wall_seconds = seconds_since(c.start);
  o.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 1;
  o.done = o.exit_code == 0;
  if (o.done) {
    std::ostringstream d;
    d << "# bagdem " << plan.spec.command << ": the run of " << p.name << " exited 0\nrank = " << opt.rank << "\nranks = " << opt.ranks << "\nhost = \"" << host
      << "\"\nwall_time = " << o.wall_seconds << "  # s\n" << point_tables_text(dir);
    write_atomically(dir / "point.done", d.str());
  } else {
    std::fprintf(stderr, "%s%s failed (%s) after %s; the end of %s:\n%s", prefix.c_str(), p.name.c_str(), exit_text(o.exit_code).c_str(),
                 duration_text(o.wall_seconds).c_str(), (dir / "log.txt").c_str(), log_tail(dir / "log.txt", 6).c_str());
  }
  return o;
}

}  // namespace

std::vector<PointOutcome> run_points(const Plan& plan, const std::vector<std::size_t>& todo, const PoolOptions& opt) {
  const std::string prefix = opt.ranks > 1 ? "[rank " + std::to_string(opt.rank) + "/" + std::to_string(opt.ranks) + "] " : "";
  const std::string host = host_name();
  const int null_fd = open("/dev/null", O_RDONLY | O_CLOEXEC);
  if (null_fd < 0) throw std::system_error(errno, std::generic_category(), "open /dev/null");
  struct CloseFd {
    int fd;
    ~CloseFd() { close(fd); }
  } close_null{null_fd};

  std::deque<std::size_t> queue(todo.begin(), todo.end());
  std::vector<Child> running;
  Reaper reaper{running};
  std::vector<PointOutcome> outcomes;
  std::size_t done = opt.done_before, failed = 0;
  double done_seconds = 0;  // wall time of the points done in this sweep
  std::size_t done_now = 0;
  const auto t0 = Clock::now();
  const auto jobs = static_cast<std::size_t>(std::max(1, opt.jobs));

  auto progress = [&] {
    const double el = seconds_since(t0);
    std::string eta = "--";
    if (done_now > 0) {
      // What is left: the unstarted points at the mean time each, and the running ones' remainders,
      // shared among the J slots.
      const double mean = done_seconds / static_cast<double>(done_now);
      double work = mean * static_cast<double>(queue.size());
      for (const Child& c : running) work += std::max(0.0, mean - seconds_since(c.start));
      eta = duration_text(work / static_cast<double>(jobs));
    }
    std::fprintf(stderr, "%s%s: %zu done, %zu running, %zu failed, %zu left (of %zu); %s elapsed, ETA %s\n", prefix.c_str(),
                 plan.spec.command.c_str(), done,
                 running.size(), failed, queue.size(), opt.total, duration_text(el).c_str(), eta.c_str());
  };

  auto start = [&](std::size_t index) { running.push_back(start_point(plan, index, opt, host, null_fd)); };
  auto finish = [&](const Child& c, int status) {
    const PointOutcome o = finish_point(plan, c, status, opt, host, prefix);
    if (o.done) ++done, ++done_now, done_seconds += o.wall_seconds;
    else ++failed;
    outcomes.push_back(o);
  };

  auto fill = [&] {
    while (running.size() < jobs && !queue.empty()) {
      const std::size_t next = queue.front();
      queue.pop_front();
      start(next);
    }
  };
  if (queue.empty()) return outcomes;
  // SIGINT or SIGTERM: no point is started after it, the points that ended well by then are kept,
  // the running ones are stopped (stop_points; each starts afresh when the study goes on).
  InterruptGuard guard;
  std::vector<Child> stopped;  // runs the signal ended too (Ctrl-C reaches the whole process group)
  auto stop_if_told = [&] {
    if (const int sig = pending_interrupt()) stop_points(plan, sig, running, stopped, done, opt.total, finish);
  };
  stop_if_told();
  fill();
  progress();
  while (!running.empty()) {
    bool changed = false;
    for (std::size_t k = 0; k < running.size();) {
      int status = 0;
      const pid_t r = waitpid(running[k].pid, &status, WNOHANG);
      if (r == 0 || (r < 0 && errno == EINTR)) {
        ++k;
        continue;
      }
      if (r < 0) throw std::system_error(errno, std::generic_category(), "waitpid");
      const Child c = running[k];
      running.erase(running.begin() + static_cast<long>(k));
      // A run the signal stopped too (Ctrl-C reaches the whole process group: it exits 130 or 143, or
      // dies by the signal itself before its own guard is up) is not a failure.
      const int code = WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 0;
      if (pending_interrupt() && (code == 128 + SIGINT || code == 128 + SIGTERM)) {
        stopped.push_back(c);
        continue;
      }
      finish(c, status);
      changed = true;
    }
    stop_if_told();
    if (changed) {
      fill();  // before the report, so that the line shows the pool as it now is
      progress();
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }
  return outcomes;
}

int holding_interrupts(const std::string& command, const std::function<int()>& body) {
  InterruptGuard guard;
  const int code = body();
  if (const int sig = pending_interrupt(); sig && code < 128) {
    std::fprintf(stderr, "%s stopped by %s, which came while it planned or wrote its tables: it finished writing them first (its "
                 "outcome without the signal: exit %d)\n", command.c_str(), signal_name(sig), code);
    return 128 + sig;
  }
  return code;
}

void run_share(const Plan& plan, const std::vector<bool>& done, const Budget& budget, const std::string& executable,
               int rank, int ranks, const std::string& prefix) {
  PoolOptions pool;
  pool.executable = executable;
  pool.jobs = budget.jobs;
  pool.threads = budget.threads;
  pool.rank = rank;
  pool.ranks = ranks;
  std::vector<std::size_t> todo;
  for (const Point& p : plan.points) {
    if (static_cast<int>(p.index % static_cast<std::size_t>(ranks)) != rank) continue;
    ++pool.total;
    if (done[p.index]) ++pool.done_before;
    else todo.push_back(p.index);
  }
  if (pool.done_before > 0)
    std::fprintf(stderr, "%sresuming: %zu of %zu points done by an earlier run, skipped\n", prefix.c_str(), pool.done_before, pool.total);
  run_points(plan, todo, pool);
}

std::vector<bool> run_round(const Plan& plan, const std::vector<bool>& done, const Budget& budget, const std::string& executable,
                            const Ranks& ranks, const std::string& prefix, const std::function<void(const std::vector<bool>&)>& after) {
  const bool lead = ranks.rank() == 0;
  // The lead's step, then every rank learns whether it failed (the others would wait for ever).
  const auto lead_step = [&](const std::function<void()>& step) {
    std::exception_ptr error;
    if (lead) try {
        step();
      } catch (...) {
        error = std::current_exception();
      }
    if (ranks.broadcast(error ? 1 : 0) == 0) return;
    if (lead) std::rethrow_exception(error);
    throw RoundFailed("the lead rank failed on " + plan.spec.out_dir + " (its message says why)");
  };
  lead_step([&] {
    fs::create_directories(plan.spec.out_dir);
    remove_merged_tables(plan);
  });
  try {
    run_share(plan, done, budget, executable, ranks.rank(), ranks.size(), rank_prefix(ranks) + prefix);
  } catch (const std::exception& e) {
    if (ranks.size() == 1) throw;
    std::fprintf(stderr, "%s%s: %s\n", rank_prefix(ranks).c_str(), error_label(e), e.what());
    ranks.abort(exit_code_after_runs(e));
  }
  ranks.barrier();
  const std::vector<bool> finished = finished_points(plan);
  lead_step([&] {  // on every rank, whether its `after` is given or not: the ranks' broadcasts pair up
    if (after) after(finished);
  });
  return finished;
}

std::vector<bool> finished_points(const Plan& plan) {
  std::vector<bool> finished(plan.points.size());
  for (const Point& p : plan.points) finished[p.index] = fs::exists(fs::path(plan.point_dir(p)) / "point.done");
  return finished;
}

}  // namespace bagdem::study
