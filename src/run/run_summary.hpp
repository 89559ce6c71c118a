// What a run reports beside its records (runner.cpp): its progress on stderr, and summary.json.
// Private to src/run/.
#pragma once
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <vector>

#include "bagdem/reduce/summary.hpp"
#include "bagdem/run/runner.hpp"
#include "bagdem/scene.hpp"
#include "bagdem/step/simulation.hpp"

namespace bagdem {

// Progress on stderr: on a terminal one line rewritten in place every second; in a log (stderr not
// a terminal) a line of its own at every tenth of the run.
class Progress {
 public:
  Progress(bool quiet, std::uint64_t first_step)
      : quiet_(quiet), terminal_(isatty(fileno(stderr)) != 0), first_(first_step), start_(clock::now()), last_(start_) {}
  void update(std::uint64_t step, std::uint64_t total, double t) {
    if (quiet_ || (step % 1024 != 0 && step != total)) return;  // the clock is read now and then
    const auto now = clock::now();
    const double frac = static_cast<double>(step) / static_cast<double>(total);
    if (terminal_ ? now - last_ < std::chrono::seconds(1) && step != total : std::floor(10 * frac) <= tenths_) return;
    last_ = now;
    tenths_ = std::floor(10 * frac);
    const double el = std::chrono::duration<double>(now - start_).count();
    // ETA from this session's pace (a resumed run started at first_).
    const double done = static_cast<double>(step - first_), left = static_cast<double>(total - step);
    const double eta = done > 0 ? el * left / done : 0;
    std::fprintf(stderr, "%s  %5.1f%%  t = %.5g s  elapsed %.0f s  ETA %.0f s%s", terminal_ ? "\r" : "", 100 * frac, t, el, eta,
                 terminal_ ? "   " : "\n");
    if (terminal_ && step == total) std::fprintf(stderr, "\n");
  }

 private:
  using clock = std::chrono::steady_clock;
  bool quiet_, terminal_;
  std::uint64_t first_;
  clock::time_point start_, last_;
  double tenths_ = 0;  // the last tenth printed in a log
};

// summary.json of a complete run: rep's headline figures (the structure's are set here), `psteps`
// the particle-steps of this session, `response` and `response_acc` the structure's response at x_a
// after release, sampled every ds (s); `structure`: this damper reports the structure (the case's own).
Summary run_summary(const Scene& scene, const Simulation& sim, RunReport& rep, double psteps, const std::vector<double>& response,
                    const std::vector<double>& response_acc, double ds, bool structure);

}  // namespace bagdem
