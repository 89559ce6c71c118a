// The stepped sine: the structure driven at one frequency after another (run/stepped_sine.hpp).
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
#include "interrupt.hpp"
#include "output_files.hpp"
#include "stepped_sine_chains.hpp"
#include "stepped_sine_files.hpp"
#include "stepped_sine_peaks.hpp"
#include "stepped_sine_state.hpp"
#include "stepped_sine_window.hpp"

namespace bagdem {
namespace fs = std::filesystem;

namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;
using Complex = std::complex<double>;

double since(std::chrono::steady_clock::time_point t0) {
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
    for (std::size_t k = 1; k < dampers_; ++k) write_reduced_csv(more_out(k) / "reduced.csv", state_.more_reduced[k - 1]);
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

void SteppedSineRun::open() {
  const fs::path part = out_ / "results.h5.part", csv = out_ / "sweep.csv";
  std::vector<std::string> mats;
  for (const auto& m : scene_.materials) mats.push_back(m.name);
  file_.emplace(opt_.resume ? reopen_results(part, state_.lengths) : open_results(part.string(), sim0(), mats, scene_.dt));
  write_run_attributes(*file_, scene_);
  if (!opt_.resume) {
    if (scene_.bag) file_->write_film(scene_.bag->rest.triangles, scene_.bag->rest.vertices.size());
    frame(frame_of(sim0(), sim0().time()));
  }
  // The points done before an interruption: their rows again (the reopened file has no /sweep).
  done_points_ = std::move(state_.points);
  done_reduced_ = std::move(state_.reduced);
  for (const SteppedSinePoint& p : done_points_) file_->append_table_row("sweep", kSteppedSineColumns, stepped_sine_row(p));
  if (!done_points_.empty()) write_stepped_sine_csv(csv, done_points_), write_reduced_csv(out_ / "reduced.csv", done_reduced_);
  rep_.points = done_points_, rep_.reduced = done_reduced_;
  state_.more_reduced.resize(dampers_ - 1);
  if (!done_points_.empty()) write_more_reduced();
  chains_.front()->first_step = first().steps_done();
  context_ = reduction_context(scene_, P_.direction);
  for (std::size_t k = 1; k < dampers_; ++k) more_context_.push_back(reduction_context(more_scene(k), P_.direction));
}

// Settling, the structure held.
void SteppedSineRun::settle() {
  const auto settle_steps = static_cast<std::uint64_t>(std::llround(scene_.settle / scene_.dt));
  if (!state_.settled) {
    while (first().steps_done() < settle_steps) halt_if_asked(*chains_.front()), first().advance(1);
    if (settle_steps > 0 && !opt_.quiet) std::fprintf(stderr, "settled for %.4g s (%.0f s)\n", scene_.settle, since(t_start_));
    state_.clearance = contents_clearance(scene_, sim0(), P_.direction.normalized());
    state_.more_clearance.clear();
    for (std::size_t k = 1; k < dampers_; ++k) state_.more_clearance.push_back(contents_clearance(more_scene(k), first()[k], P_.direction.normalized()));
    state_.settled = true;
    state_.images = {first().image()};
    checkpoint();
  }
  context_.clearance = state_.clearance;
  for (std::size_t k = 1; k < dampers_; ++k) more_context_[k - 1].clearance = state_.more_clearance[k - 1];
}

// The other chains, from the settled contents (or, resumed, from their own state at the
// interruption; before any point was written every chain's is the settled state).
void SteppedSineRun::start_chains() {
  const std::size_t n = chain_count(plan_.chains, plan_.frequencies.size());
  if (state_.images.size() != n) state_.images.assign(n, state_.images.front());
  for (std::size_t k = 1; k < n; ++k) {
    auto& c = chains_.emplace_back(std::make_unique<Chain>(scene_));
    c->d.load_image(state_.images[k]);
    c->first_step = c->d.steps_done();
  }
  for (const auto& c : chains_) image_step_.push_back(c->d.steps_done());
  last_.assign(n, std::nullopt), last_index_.assign(n, ChainTask::none);
}

void SteppedSineRun::run() {
  settle();
  start_chains();
  const std::size_t K = chains_.size();
  npts_ = plan_.frequencies.size() + plan_.refine * (plan_.modes.empty() ? 1 : plan_.modes.size());
  // Progress: a line per cycle on a terminal (rewritten in place; one chain only), a line per point.
  terminal_ = isatty(fileno(stderr)) != 0 && K == 1;
  // The window is the last 2K cycles, at least reduce_cycles: a point is settled when the mean
  // first harmonic of the window's second half differs from its first half's by less than the
  // tolerance, so that the window reduced is the window judged steady. A point's first cycle is
  // never in it: the drive has just changed frequency (and, at a chain's start, the structure is
  // released into its start state within it).
  K_ = plan_.half_window(), window_ = 2 * K_, least_ = plan_.least_cycles();
  run_tasks(planned_tasks(plan_.frequencies, K));
  // Peak refinement: per mode, `refine` more points in rounds of up to K (stepped_sine_chains.hpp).
  // Each round is chosen from the points before it (a resumed round: as it was first chosen).
  std::size_t first = plan_.frequencies.size();
  for (std::size_t r = 0; r < refinement_rounds(plan_.refine, K); ++r) {
    const std::vector<SteppedSinePoint> before(rep_.points.begin(), rep_.points.begin() + static_cast<std::ptrdiff_t>(first));
    const std::vector<ChainTask> tasks = refinement_tasks(P_, before, round_points(plan_.refine, K, r), K, scene_.dt, first);
    run_tasks(tasks);
    first += tasks.size();
  }
}

// The tasks not yet written, each chain's in order; the chains side by side on the threads given
// (each with its share of them), or one after another on one.
void SteppedSineRun::run_tasks(const std::vector<ChainTask>& tasks) {
  std::vector<std::vector<ChainTask>> per(chains_.size());
  models_.clear();
  for (const ChainTask& t : tasks) {
    if (t.index < rep_.points.size()) {  // written before an interruption: where its chain was
      last_[t.chain] = rep_.points[t.index], last_index_[t.chain] = t.index;
      continue;
    }
    per[t.chain].push_back(t);
    // A model written already (the refinement's; a resumed chain's previous point): read it now,
    // before the chains write more points.
    if (t.model < rep_.points.size()) models_[t.index] = rep_.points[t.model];
  }
  std::vector<std::size_t> busy;
  for (std::size_t k = 0; k < per.size(); ++k)
    if (!per[k].empty()) busy.push_back(k);
  const int threads = omp_get_max_threads(), outer = std::min(threads, static_cast<int>(busy.size()));
  if (outer <= 1) {
    for (std::size_t k : busy) run_chain(*chains_[k], k, per[k]);
    return;
  }
  // Exceptions cannot leave a parallel region: each chain's is kept, and the first failure (in
  // chain order), else the first signal, else the testing aid's halt, is thrown after it.
  std::vector<std::exception_ptr> errors(busy.size());
  const int inner = std::max(1, threads / outer);
  const int levels = omp_get_max_active_levels();
  if (inner > 1) omp_set_max_active_levels(2);  // each chain's own stages on its share of the threads
#pragma omp parallel for num_threads(outer) schedule(dynamic, 1)
  for (std::size_t b = 0; b < busy.size(); ++b) {
    omp_set_num_threads(inner);
    try {
      run_chain(*chains_[busy[b]], busy[b], per[busy[b]]);
    } catch (const SteppedSineHalt& h) {
      errors[b] = std::current_exception();
      if (h.signal != 0) stop_.store(true);  // the testing aid stops each chain at its own step
    } catch (...) {
      errors[b] = std::current_exception();
      stop_.store(true);
    }
  }
  omp_set_max_active_levels(levels);
  std::exception_ptr halt, signal;
  for (const std::exception_ptr& e : errors) {
    if (!e) continue;
    try {
      std::rethrow_exception(e);
    } catch (const SteppedSineHalt& h) {
      if (!halt) halt = e;
      if (h.signal != 0 && !signal) signal = e;
    } catch (...) {
      throw;
    }
  }
  if (signal) std::rethrow_exception(signal);
  if (halt) std::rethrow_exception(halt);
}

// Each point after the chain's first starts from the one before it (excitation.predict), its
// contents modelled on that point or, in the refinement, on the written point nearest in frequency.
void SteppedSineRun::run_chain(Chain& c, std::size_t k, const std::vector<ChainTask>& tasks) {
  for (const ChainTask& t : tasks) {
    const auto m = models_.find(t.index);
    const SteppedSinePoint* from = last_[k] ? &*last_[k] : nullptr;
    const SteppedSinePoint* to = m != models_.end() ? &m->second : t.model == last_index_[k] ? from : nullptr;
    DonePoint d = run_point(c, t, from, to);
    last_[k] = d.pt, last_index_[k] = t.index;
    finished(t.index, std::move(d));
  }
}

// One frequency point, from the state the chain's last one left.
DonePoint SteppedSineRun::run_point(Chain& c, const ChainTask& task, const SteppedSinePoint* from, const SteppedSinePoint* to) {
  const auto t_point = std::chrono::steady_clock::now();
  DonePoint d;
  d.chain = task.chain;
  SteppedSinePoint& pt = d.pt;
  pt.requested = task.frequency;
  const std::size_t N = steps_per_cycle(pt.requested, scene_.dt);
  pt.frequency = 1.0 / (static_cast<double>(N) * scene_.dt);
  c.d.set_drive_frequency(pt.frequency);
  const double w = kTwoPi * pt.frequency;
  // The predicted start (excitation.predict): the structure's state moves from the steady state of
  // the chain's last point (`from`, with its contents as measured there) to the one at this
  // frequency with the model's contents (`to`), the rest of the state (the decaying part, the static
  // one) kept (stepped_sine_chains.hpp).
  if (plan_.predict && from && to && dampers_ == 1) {  // one damper's impedance (several: not yet)
    const double w_a = kTwoPi * from->frequency;
    const Complex Za = contents_stiffness(*from, w_a), Zb = contents_stiffness(*to, w);
    Eigen::VectorXcd A = P_.steady_amplitudes(P_.amplitude, w_a, Za), B = P_.steady_amplitudes(P_.amplitude, w, Zb);
    for (std::size_t k = 0; k < P_.size(); ++k)  // set_drive_frequency moved the rigid-body modes
      if (P_.rigid_body[k]) A[static_cast<Eigen::Index>(k)] = B[static_cast<Eigen::Index>(k)] = 0;
    if (std::isfinite(A.norm()) && std::isfinite(B.norm())) c.d.jump_harmonic(A, w_a, B, w);
  }
  SteadyStateDetector steady(K_, plan_.tolerance);
  std::vector<PointWindow> win(dampers_);
  drive_cycles(c, pt, N, steady, win, task.index);
  measure_window(ledger(c.d), P_, win[0], steady, w, pt);
  if (dampers_ == 1) {
    d.reduced = reduce_window(win[0], scene_, context_, pt);
  } else {
    // Each damper's reduction over the window with its own contents' dissipation per cycle (the
    // point's is every damper's); the point is steady when every damper's is.
    bool steady_all = true;
    for (std::size_t k = 0; k < dampers_; ++k) {
      const std::deque<Ledger>& starts = k == 0 ? win[0].own : win[k].starts;
      SteppedSinePoint mine = pt;
      mine.dissipated_contents = (ledger(c.d[k]).dissipated_contents - starts.front().dissipated_contents) / static_cast<double>(win[k].ys.size());
      ReducedRow row = reduce_window(win[k], k == 0 ? scene_ : more_scene(k), k == 0 ? context_ : more_context_[k - 1], mine);
      steady_all = steady_all && mine.steady;
      if (k == 0) d.reduced = std::move(row);
      else d.more_reduced.push_back(std::move(row));
    }
    pt.steady = steady_all;
  }
  pt.wall_seconds = since(t_point);
  d.frame = frame_of(c.d[0], c.d.time());
  d.image = c.d.image();
  d.step = c.d.steps_done();
  return d;
}

// A point is done: its progress line, then it and any points after it that were waiting for it
// are written, in order, and the checkpoint follows. A chain runs its block in the points' order
// (stepped_sine_chains.hpp): so the points written of each chain are always the first it ran, and its
// state after the last of them is the one to resume from.
void SteppedSineRun::finished(std::size_t index, DonePoint&& d) {
  const std::lock_guard<std::mutex> lock(mutex_);
  report_point(d.pt, index, std::min<std::size_t>(d.pt.cycles, window_), ++completed_ + done_points_.size());
  waiting_.emplace(index, std::move(d));
  bool wrote = false;
  for (auto it = waiting_.find(rep_.points.size()); it != waiting_.end(); it = waiting_.find(rep_.points.size())) {
    write_point(it->second);
    waiting_.erase(it);
    wrote = true;
  }
  if (wrote) checkpoint();
}

// A point's row, frame and tables.
void SteppedSineRun::write_point(DonePoint& d) {
  rep_.points.push_back(d.pt);
  rep_.reduced.push_back(d.reduced);
  for (std::size_t k = 1; k < dampers_; ++k) state_.more_reduced[k - 1].push_back(d.more_reduced[k - 1]);
  file_->append_table_row("sweep", kSteppedSineColumns, stepped_sine_row(d.pt));
  frame(d.frame);
  write_stepped_sine_csv(out_ / "sweep.csv", rep_.points);
  write_reduced_csv(out_ / "reduced.csv", rep_.reduced);
  write_more_reduced();
  // The chain's latest state among its points written (steps_done grows along a chain).
  if (d.step > image_step_[d.chain]) state_.images[d.chain] = std::move(d.image), image_step_[d.chain] = d.step;
}

// The drive's cycles at the point's N steps each, until the window is steady or max_cycles.
void SteppedSineRun::drive_cycles(Chain& ch, SteppedSinePoint& pt, std::size_t N, SteadyStateDetector& steady,
                                  std::vector<PointWindow>& win, std::size_t i) const {
  Dampers& d = ch.d;
  // The response and each cavity with their slow drift taken out (CycleHarmonic), the cavities'
  // samples for the reduction too; the point's first cycle as projected. Window 0 is the case's
  // own damper's, its ledger every damper's (the energy balance of the whole); window k > 0 damper
  // k's, with its own ledger (and window 0's `own` the case's own damper's, with several).
  constexpr double none = std::numeric_limits<double>::quiet_NaN();
  double y1 = none, y2 = none;                                    // the means of the cycle before and the one before that
  std::vector<double> u1(dampers_, none), u2(dampers_, none);
  std::vector<CycleHarmonic> Uc(dampers_), Lc(dampers_);
  std::vector<CavitySeries*> series(dampers_);
  for (std::size_t c = 0; c < plan_.max_cycles; ++c) {
    for (std::size_t k = 0; k < dampers_; ++k) {
      PointWindow& w = win[k];
      w.starts.push_back(k == 0 ? ledger(d) : ledger(d[k]));
      if (k == 0 && dampers_ > 1) w.own.push_back(ledger(d[0]));
      if (w.recent.size() == window_) {
        w.recent.pop_front(), w.starts.pop_front(), w.ys.pop_front(), w.cav.pop_front(), w.load.pop_front();
        if (!w.own.empty()) w.own.pop_front();
      }
      series[k] = &w.recent.emplace_back();
      for (auto* v : {&series[k]->t, &series[k]->x, &series[k]->force, &series[k]->v_rel}) v->reserve(N);  // no growth inside the steps
      Uc[k] = CycleHarmonic(), Lc[k] = CycleHarmonic();
    }
    CycleHarmonic Yc;
    for (std::size_t n = 0; n < N; ++n) {
      halt_if_asked(ch);
      d.advance(1);
      const StructureResponse r = d[0].structure_response();
      const Complex e = std::polar(1.0, -r.phase);
      Yc.add(r.displacement, e);
      for (std::size_t k = 0; k < dampers_; ++k) {
        const StructureResponse rk = k == 0 ? r : d[k].structure_response();  // its cavity and load
        Uc[k].add(rk.cavity, e), Lc[k].add(rk.load, e);
        CavitySeries& sk = *series[k];
        sk.t.push_back(d.time()), sk.x.push_back(rk.cavity), sk.force.push_back(rk.load);
        sk.v_rel.push_back(d[k].contents_relative_velocity().dot(P_.direction));
      }
    }
    const CycleHarmonic::Drift dy = Yc.drift(y1, y2);
    const Complex Y = Yc.harmonic(dy);
    y2 = y1, y1 = Yc.mean();
    for (std::size_t k = 0; k < dampers_; ++k) {
      const CycleHarmonic::Drift du = Uc[k].drift(u1[k], u2[k]);
      const Complex U = Uc[k].harmonic(du), L = Lc[k].harmonic({});
      for (std::size_t n = 0; n < N; ++n) series[k]->x[n] -= du.at(n + 1, N);
      u2[k] = u1[k], u1[k] = Uc[k].mean();
      win[k].ys.push_back(Y), win[k].cav.push_back(U), win[k].load.push_back(L);
    }
    steady.add(Y);
    pt.cycles = c + 1;
    pt.change = steady.last_change();
    if (!opt_.quiet && terminal_)
      std::fprintf(stderr, "\r  [%zu/%zu] %.4g Hz: cycle %zu, |Y| = %.4g m, change %.2g%%   ", i + 1, npts_, pt.frequency,
                   c + 1, std::abs(Y), 100 * pt.change);
    // Settled: the response (SteadyStateDetector) and the window's energy (as judge_steady will
    // judge it: a window that does not balance holds a transient; run on).
    if (pt.cycles >= least_ && steady.steady() && (!scene_.models.energy || balances(window_balance(win[0], ledger(d))))) {
      pt.settled = true;
      break;
    }
  }
}

// The point's progress line, and why it is flagged unsteady if it is.
void SteppedSineRun::report_point(const SteppedSinePoint& pt, std::size_t i, std::size_t window_cycles, std::size_t done) const {
  if (!opt_.quiet) {
    const double el = since(t_start_), run = static_cast<double>(done - done_points_.size());
    std::fprintf(stderr, "%s  [%zu/%zu] %.5g Hz: |H| = %.4g +- %.2g m/N (bare %.4g), %s after %zu cycles, %.1f s; ETA %.0f s\n",
                 terminal_ ? "\r" : "", i + 1, npts_, pt.frequency, std::abs(pt.receptance), pt.receptance_ci95, std::abs(pt.bare),
                 pt.steady ? "steady" : "NOT steady", pt.cycles, pt.wall_seconds,
                 el / run * static_cast<double>(npts_ > done ? npts_ - done : 0));
  }
  if (!pt.steady) {
    std::ostringstream m;
    m << "warning: " << pt.frequency << " Hz is flagged unsteady and left out of the peaks: ";
    if (!pt.settled)
      m << "it did not settle in " << plan_.max_cycles << " cycles (last change " << 100 * pt.change << "%, tolerance "
        << 100 * plan_.tolerance << "%, and beyond the cycles' scatter; or the window's energy balance " << 100 * pt.balance
        << "%, allowed " << 100 * kSteadyBalanceTolerance << "%); raise excitation.max_cycles or excitation.steady_tolerance\n";
    else
      m << "over its last " << window_cycles << " cycles the energy balance is off by " << 100 * pt.balance
        << "% (allowed " << 100 * kSteadyBalanceTolerance << "%) or the contents' tallied dissipation is negative ("
        << pt.dissipated_contents << " J per cycle); raise excitation.min_cycles (a longer transient) or lower simulation.timestep_safety\n";
    std::fputs(m.str().c_str(), stderr);
  }
}

SteppedSineReport SteppedSineRun::halted(const SteppedSineHalt& h) {
  file_->flush();
  if (h.signal == 0) return rep_;  // the testing aid: as if killed
  if (!state_.settled) state_.images = {first().image()}, checkpoint();  // during settling; else the last point's stands
  file_->set_attribute("status", "interrupted");
  file_->close();
  rep_.signal = h.signal;
  rep_.message = interrupted_message(h.signal, sim0().time(), rep_.points.size(), out_);
  return rep_;
}

SteppedSineReport SteppedSineRun::failed(const RunError& e) {
  // The points done are this failed stepped sine's: their tables carry its name too, beside its record.
  for (const char* t : {"sweep", "reduced"})
    if (fs::exists(out_ / (std::string(t) + ".csv"))) fs::rename(out_ / (std::string(t) + ".csv"), out_ / (std::string(t) + ".failed.csv"));
  for (std::size_t k = 1; k < dampers_; ++k)
    if (fs::exists(more_out(k) / "reduced.csv")) fs::rename(more_out(k) / "reduced.csv", more_out(k) / "reduced.failed.csv");
  rep_.message = failed_run_message(e.what(), close_results(std::string("failed: ") + e.what(), false));
  fs::remove(out_ / "checkpoint.bin");  // a failed sweep is not continued: resuming it would fail again
  return rep_;
}

SteppedSineReport SteppedSineRun::finish() {
  rep_.complete = true;
  rep_.wall_seconds = since(t_start_);
  rep_.peaks = sweep_peaks(P_, rep_.points);
  close_results("complete", true);
  fs::remove(out_ / "checkpoint.bin");

  const Summary summary = stepped_sine_summary(scene_, rep_, sim0().particles().size(), chains_.size());
  write_peaks_csv(out_ / "peaks.csv", rep_.peaks);
  Scene own = scene_;  // the case's own damper alone (its drop test)
  own.more_dampers.clear();
  if (const std::string why = drop_where_no_restitution(own, rep_.reduced, out_, true); !why.empty() && !opt_.quiet)
    std::fprintf(stderr, "no restitution from the impacts or Eq. (19a), and the drop test could not run: %s\n", why.c_str());
  write_reduced_csv(out_ / "reduced.csv", rep_.reduced);
  for (std::size_t k = 1; k < dampers_; ++k) {
    std::vector<ReducedRow>& rows = state_.more_reduced[k - 1];
    if (const std::string why = drop_where_no_restitution(more_scene(k), rows, more_out(k), true); !why.empty() && !opt_.quiet)
      std::fprintf(stderr, "damper %s: no restitution from the impacts or Eq. (19a), and the drop test could not run: %s\n",
                   scene_.more_dampers[k - 1].name.c_str(), why.c_str());
    write_reduced_csv(more_out(k) / "reduced.csv", rows);
  }
  // The continuum model with the contents' C_b and M_b: one damper's (several: not yet).
  if (dampers_ == 1) {
    rep_.compare = compare_with_continuum(P_, P_.amplitude, rep_.reduced);
    write_compare_csv(out_ / "compare.csv", rep_.compare);
  }
  write_bare_curve(out_ / "bare_curve.csv", P_, rep_.points);
  write_summary(out_ / "summary.json", summary);
  return rep_;
}

}  // namespace

SteppedSineReport run_stepped_sine(const Scene& scene, const RunOptions& opt) {
  if (!scene.primary || !scene.primary->stepped_sine)
    throw InputError(scene.case_file, "excitation.kind", "", "a sweep needs a primary structure with excitation.kind = \"stepped-sine\"");
  const InterruptGuard interrupts;
  if (opt.threads > 0) omp_set_num_threads(opt.threads);
  const OutputLock lock(opt.out_dir);  // creates the directory
  clear_other_dampers(opt.out_dir, scene, opt.resume);
  for (const Damper& d : scene.more_dampers) fs::create_directories(damper_dir(opt.out_dir, d.name));
  SteppedSineRun sweep(scene, opt);
  sweep.open();
  try {
    sweep.run();
  } catch (const SteppedSineHalt& h) {
    return sweep.halted(h);
  } catch (const RunError& e) {
    return sweep.failed(e);
  }
  return sweep.finish();
}

}  // namespace bagdem
