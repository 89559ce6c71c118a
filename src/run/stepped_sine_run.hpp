// Internal to src/run: a stepped sine run (run/stepped_sine.hpp): its chains, its points and the
// class that runs them. stepped_sine.cpp sets up, settles, runs the chains and finishes;
// stepped_sine_point.cpp runs and writes a point.
#pragma once
#include "bagdem/run/stepped_sine.hpp"
#include <omp.h>
#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <optional>
#include <sstream>
#include "bagdem/error.hpp"
#include "bagdem/io/atomic_file.hpp"
#include "bagdem/io/output_lock.hpp"
#include "bagdem/io/results_file.hpp"
#include "bagdem/reduce/compare.hpp"
#include "bagdem/reduce/interval.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "bagdem/run/clearance.hpp"
#include "bagdem/run/drop_fallback.hpp"
#include "bagdem/step/dampers.hpp"
#include "bagdem/step/simulation.hpp"
#include "bagdem/structure/response.hpp"
#include "bagdem/interrupt.hpp"
#include "output_files.hpp"
#include "stepped_sine_chains.hpp"
#include "stepped_sine_files.hpp"
#include "stepped_sine_peaks.hpp"
#include "stepped_sine_state.hpp"
#include "stepped_sine_window.hpp"

namespace bagdem::stepped_sine_run {
namespace fs = std::filesystem;

constexpr double kTwoPi = 2 * std::numbers::pi;
using Complex = std::complex<double>;

inline double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A chain of the stepped sine (stepped_sine_chains.hpp): its simulation (several dampers' on one
// structure, step/dampers.hpp; one damper's is its Simulation alone), and where its steps are
// counted from (the testing aid RunOptions::stop_after_steps).
struct Chain {
  explicit Chain(const Scene& scene) : d(scene) {}
  Dampers d;
  std::uint64_t first_step = 0;
};

// A point run, waiting for the points before it to be written: the points are written in their
// order whatever the chains' pace, so the files are the same for any thread count.
struct DonePoint {
  SteppedSinePoint pt;
  ReducedRow reduced;
  std::vector<ReducedRow> more_reduced;  // the other dampers' (several dampers)
  Frame frame;
  std::vector<char> image;  // its chain's state after it (the checkpoint's)
  std::uint64_t step = 0;   // its chain's steps then
  std::size_t chain = 0;
};

// One stepped sine of a scene: its chains, its results file, the points done.
class SteppedSineRun {
 public:
  SteppedSineRun(const Scene& scene, const RunOptions& opt)
      : scene_(scene), opt_(opt), P_(*scene.primary), plan_(*P_.stepped_sine), out_(opt.out_dir) {
    chains_.push_back(std::make_unique<Chain>(scene));
    dampers_ = chains_.front()->d.size();
    // The state of an interrupted stepped sine (stepped_sine_state.hpp), or a fresh start.
    start_stepped_sine_state(out_, opt_.resume, chains_.front()->d, state_);
    for (std::size_t k = 1; k < dampers_; ++k) remove_derived_tables(more_out(k));
    t_start_ = std::chrono::steady_clock::now();
  }
  // results.h5.part open, and the points done before an interruption written again.
  void open();
  // Settling, then the points; throws SteppedSineHalt or RunError when stopped.
  void run();
  SteppedSineReport halted(const SteppedSineHalt& h);
  SteppedSineReport failed(const RunError& e);
  SteppedSineReport finish();

 private:
  // The first chain: it settles the contents, and the other chains start from it; its case's damper.
  Dampers& first() { return chains_.front()->d; }
  Simulation& sim0() { return first()[0]; }
  // Several dampers: damper k's directory (k > 0) and scene.
  fs::path more_out(std::size_t k) const { return damper_dir(out_, scene_.more_dampers[k - 1].name); }
  const Scene& more_scene(std::size_t k) const { return *scene_.more_dampers[k - 1].scene; }
  void write_more_reduced() {
    for (std::size_t k = 1; k < dampers_; ++k) write_reduced_csv(more_out(k) / kReducedPartial, state_.more_reduced[k - 1]);
  }
  void frame(const Frame& f) {
    append_frame(*file_, f);
    state_.frame_times.push_back(f.t);
  }
  // A signal, the testing aid, or another chain's failure stops the next step.
  void halt_if_asked(const Chain& c) const {
    if (const int sig = pending_interrupt()) throw SteppedSineHalt{sig};
    if (stop_.load(std::memory_order_relaxed)) throw SteppedSineHalt{0};
    if (opt_.stop_after_steps >= 0 && c.d.steps_done() - c.first_step >= static_cast<std::uint64_t>(opt_.stop_after_steps))
      throw SteppedSineHalt{0};
  }
  // A checkpoint of the stepped sine as it stands: the points written and each chain's state after its
  // last one written.
  void checkpoint() {
    file_->flush();
    state_.lengths = file_->lengths(), state_.points = rep_.points, state_.reduced = rep_.reduced;
    save_stepped_sine_checkpoint(out_ / "checkpoint.bin", scene_, state_);
  }
  fs::path close_results(const std::string& status, bool complete) {
    return close_results_file(*file_, out_, status, complete, state_.frame_times,
                              {sim0().particles().size(), sim0().film().size(), scene_.bag ? scene_.bag->rest.triangles.size() : 0});
  }
  void settle();
  void start_chains();
  void run_tasks(const std::vector<ChainTask>& tasks);
  void run_chain(Chain& c, std::size_t k, const std::vector<ChainTask>& tasks);
  DonePoint run_point(Chain& c, const ChainTask& task, const SteppedSinePoint* from, const SteppedSinePoint* to);
  void drive_cycles(Chain& c, SteppedSinePoint& pt, std::size_t N, SteadyStateDetector& steady, std::vector<PointWindow>& win,
                    std::size_t i) const;
  void finished(std::size_t index, DonePoint&& d);
  void write_point(DonePoint& d);
  void report_point(const SteppedSinePoint& pt, std::size_t i, std::size_t window_cycles, std::size_t done) const;

  const Scene& scene_;
  const RunOptions& opt_;
  const Primary& P_;
  const Primary::SteppedSine& plan_;
  const fs::path out_;
  SteppedSineState state_;
  std::vector<std::unique_ptr<Chain>> chains_;
  std::chrono::steady_clock::time_point t_start_;
  std::optional<ResultsFile> file_;
  SteppedSineReport rep_;
  // The points done before an interruption.
  std::vector<SteppedSinePoint> done_points_;
  std::vector<ReducedRow> done_reduced_;
  ReductionContext context_;
  std::vector<ReductionContext> more_context_;  // several dampers: the others' (index k - 1)
  std::size_t dampers_ = 1;
  std::size_t npts_ = 0;        // the points planned (for the progress lines)
  bool terminal_ = false;       // stderr is a terminal
  std::size_t K_ = 0, window_ = 0, least_ = 0;
  // Between the chains: points run but not yet written (by index), the points run this session,
  // and a chain's failure that stops the others.
  std::mutex mutex_;
  std::map<std::size_t, DonePoint> waiting_;
  std::map<std::size_t, SteppedSinePoint> models_;  // per task of run_tasks, a model written before it
  std::vector<std::optional<SteppedSinePoint>> last_;  // per chain, its last point (each chain its own)
  std::vector<std::size_t> last_index_;
  std::vector<std::uint64_t> image_step_;  // per chain, the steps of its state in state_.images
  std::size_t completed_ = 0;
  std::atomic<bool> stop_{false};
};

}  // namespace bagdem::stepped_sine_run
