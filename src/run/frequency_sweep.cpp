// Stepped-sine frequency sweep (run/frequency_sweep.hpp).
#include "bagdem/run/frequency_sweep.hpp"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <deque>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>

#include "bagdem/error.hpp"
#include "bagdem/io/atomic_file.hpp"
#include "bagdem/io/json.hpp"
#include "bagdem/io/results_file.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/reduce/compare.hpp"
#include "bagdem/reduce/interval.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "bagdem/run/clearance.hpp"
#include "bagdem/run/drop_fallback.hpp"
#include "bagdem/step/simulation.hpp"
#include "bagdem/structure/response.hpp"
#include "interrupt.hpp"
#include "output_files.hpp"
#include "sweep_peaks.hpp"
#include "sweep_state.hpp"

namespace bagdem {
namespace fs = std::filesystem;

namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;
using Complex = std::complex<double>;

const std::vector<TableColumn> kSweepColumns = {
    {"requested_frequency", "Hz"}, {"frequency", "Hz"},
    {"response_re", "m"},          {"response_im", "m"},
    {"receptance_re", "m/N"},      {"receptance_im", "m/N"},
    {"bare_receptance_re", "m/N"}, {"bare_receptance_im", "m/N"},
    {"acceleration_re", "m/s^2"},  {"acceleration_im", "m/s^2"},
    {"accelerance_abs", "m/s^2/N"}, {"bare_accelerance_abs", "m/s^2/N"},
    {"cavity_re", "m"},            {"cavity_im", "m"},
    {"contents_force_re", "N"},    {"contents_force_im", "N"},
    {"work_external_per_cycle", "J"}, {"dissipated_structure_per_cycle", "J"},
    {"dissipated_contents_per_cycle", "J"}, {"energy_balance", "1"},
    {"receptance_abs_ci95", "m/N"},
    {"cycles", "1"},               {"steady", "1"},
    {"spread", "1"},
    {"change", "1"},               {"wall_time", "s"}};

std::vector<double> row_of(const SweepPoint& p) {
  const double w = kTwoPi * p.frequency;
  return {p.requested, p.frequency, p.response.real(), p.response.imag(), p.receptance.real(), p.receptance.imag(),
          p.bare.real(), p.bare.imag(), -w * w * p.response.real(), -w * w * p.response.imag(), w * w * std::abs(p.receptance), w * w * std::abs(p.bare), p.cavity.real(),
          p.cavity.imag(), p.contents_force.real(), p.contents_force.imag(), p.work_external, p.dissipated_structure,
          p.dissipated_contents, p.balance, p.receptance_ci95, static_cast<double>(p.cycles), p.steady ? 1.0 : 0.0, p.spread, p.change,
          p.wall_seconds};
}

void write_csv(const fs::path& path, const std::vector<SweepPoint>& points) {
  std::vector<std::vector<double>> rows;
  for (const SweepPoint& p : points) rows.push_back(row_of(p));
  write_table_csv(path, kSweepColumns, rows);
}

// bare_curve.csv: the bare structure's analytic response at 400 frequencies over the swept band,
// the smooth reference of the plots.
void write_bare_curve(const fs::path& path, const Primary& P, const std::vector<SweepPoint>& points) {
  static const std::vector<TableColumn> columns = {{"frequency", "Hz"}, {"bare_receptance_abs", "m/N"}, {"bare_accelerance_abs", "m/s^2/N"}};
  if (points.empty()) return;
  double lo = points.front().frequency, hi = lo;
  for (const SweepPoint& p : points) lo = std::min(lo, p.frequency), hi = std::max(hi, p.frequency);
  std::vector<std::vector<double>> rows;
  const int n = hi > lo ? 400 : 1;
  for (int k = 0; k < n; ++k) {
    const double f = n > 1 ? lo + (hi - lo) * k / (n - 1) : lo, w = kTwoPi * f, h = std::abs(P.bare_receptance(w));
    rows.push_back({f, h, w * w * h});
  }
  write_table_csv(path, columns, rows);
}

// Energy the run has seen so far, for per-cycle differences.
struct Ledger {
  double work_external = 0, dissipated_structure = 0, dissipated_contents = 0, stored = 0;
};
Ledger ledger(const Simulation& sim) {
  Ledger l;
  const auto& S = sim.structure().scalars;
  l.work_external = S.work_external;
  l.dissipated_structure = S.dissipated;
  if (sim.scene().models.energy) {
    const EnergySample e = sim.energy();
    l.dissipated_contents = e.dissipated();
    // Contents: kinetic + elastic + gravity's potential (-work of gravity).
    l.stored = e.kinetic + e.elastic - e.work_gravity;
  }
  l.stored += sim.structure_energy();
  return l;
}

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The last `window` cycles of a point: the ledger at the start of each, the first harmonics of the
// response, the cavity's displacement and the contents' force, and the samples.
struct PointWindow {
  std::deque<Ledger> starts;
  std::deque<Complex> ys, cav, load;
  std::deque<CavitySeries> recent;
};

// The energy balance over the window as it stands: (W - D_s - D_c - dE) / |W| per cycle, and the
// contents' dissipation per cycle (sweep.csv's energy_balance and dissipated_contents_per_cycle).
struct WindowBalance {
  double balance = 0, dissipated_contents = 0, work_external = 0, dissipated_structure = 0;
};
WindowBalance window_balance(const PointWindow& win, const Simulation& sim) {
  const Ledger end = ledger(sim), &from = win.starts.front();
  const double cycles = static_cast<double>(win.ys.size());
  WindowBalance b;
  b.work_external = (end.work_external - from.work_external) / cycles;
  b.dissipated_structure = (end.dissipated_structure - from.dissipated_structure) / cycles;
  b.dissipated_contents = (end.dissipated_contents - from.dissipated_contents) / cycles;
  const double residual = b.work_external - b.dissipated_structure - b.dissipated_contents - (end.stored - from.stored) / cycles;
  b.balance = b.work_external != 0 ? residual / std::abs(b.work_external) : 0.0;
  return b;
}

// As judge_steady (reduce/reduce.hpp) will judge the window.
bool balances(const WindowBalance& b) {
  return !(std::abs(b.balance) > kSteadyBalanceTolerance) && !(b.dissipated_contents < 0);
}

// One sweep of a scene: its simulation, its results file, the points done.
class FrequencySweep {
 public:
  FrequencySweep(const Scene& scene, const RunOptions& opt)
      : scene_(scene), opt_(opt), P_(*scene.primary), plan_(*P_.sweep), out_(opt.out_dir), sim_(scene) {
    // The state of an interrupted sweep (sweep_state.hpp), or a fresh start.
    start_sweep_state(out_, opt_.resume, sim_, state_);
    t_start_ = std::chrono::steady_clock::now();
  }
  // results.h5.part open, and the points done before an interruption written again.
  void open();
  // Settling, then the points; throws SweepHalt or RunError when stopped.
  void run();
  SweepReport halted(const SweepHalt& h);
  SweepReport failed(const RunError& e);
  SweepReport finish();

 private:
  void frame() {
    append_ball_frame(*file_, sim_.time(), sim_);
    if (scene_.bag) file_->append_film_frame(sim_.film().x);
    state_.frame_times.push_back(sim_.time());
  }
  // A signal, or the testing aid, stops the next step.
  void halt_if_asked() const {
    if (const int sig = pending_interrupt()) throw SweepHalt{sig};
    if (opt_.stop_after_steps >= 0 && sim_.steps_done() - first_step_ >= static_cast<std::uint64_t>(opt_.stop_after_steps))
      throw SweepHalt{0};
  }
  // A checkpoint of the sweep as it stands (between points, or during settling).
  void checkpoint() {
    file_->flush();
    state_.lengths = file_->lengths(), state_.points = rep_.points, state_.reduced = rep_.reduced;
    save_sweep_checkpoint(out_ / "checkpoint.bin", sim_, state_);
  }
  void close_results(const std::string& status) {
    file_->set_attribute("status", status);
    file_->close();
    fs::rename(out_ / "results.h5.part", out_ / "results.h5");
    write_xdmf((out_ / "results.xmf").string(), "results.h5", sim_.particles().size(), state_.frame_times, sim_.film().size(),
               scene_.bag ? scene_.bag->rest.triangles.size() : 0);
  }
  void settle();
  void point(double f);
  void run_point(double requested);
  void drive_cycles(SweepPoint& pt, std::size_t N, SteadyStateDetector& steady, PointWindow& win, std::size_t i);
  void measure_window(SweepPoint& pt, const PointWindow& win, const SteadyStateDetector& steady, double w) const;
  ReducedRow reduce_window(SweepPoint& pt, const PointWindow& win) const;
  void report_point(const SweepPoint& pt, std::size_t i, std::size_t window_cycles) const;
  std::string summary_json() const;

  const Scene& scene_;
  const RunOptions& opt_;
  const Primary& P_;
  const Primary::Sweep& plan_;
  const fs::path out_;
  SweepState state_;
  Simulation sim_;
  std::chrono::steady_clock::time_point t_start_;
  std::optional<ResultsFile> file_;
  SweepReport rep_;
  // The points done before an interruption.
  std::vector<SweepPoint> done_points_;
  std::vector<ReducedRow> done_reduced_;
  std::uint64_t first_step_ = 0;
  ReductionContext context_;
  std::size_t npts_ = 0;        // the points planned (for the progress lines)
  bool terminal_ = false;       // stderr is a terminal
  std::size_t K_ = 0, window_ = 0, least_ = 0;
};

void FrequencySweep::open() {
  const fs::path part = out_ / "results.h5.part", csv = out_ / "sweep.csv";
  std::vector<std::string> mats;
  for (const auto& m : scene_.materials) mats.push_back(m.name);
  file_.emplace(opt_.resume ? ResultsFile::reopen(part.string(), state_.lengths) : open_results(part.string(), sim_, mats, scene_.dt));
  file_->set_attribute("status", "running");
  if (!opt_.resume) {
    file_->set_attribute("case_file", scene_.case_file);
    file_->set_attribute("resolved_config", scene_.resolved);
    file_->set_attribute("settle_end", scene_.settle);
    file_->set_attribute("timestep", scene_.dt);
    if (scene_.bag) file_->write_film(scene_.bag->rest.triangles, scene_.bag->rest.vertices.size());
    frame();
  }
  // The points done before an interruption: their rows again (the reopened file has no /sweep).
  done_points_ = std::move(state_.points);
  done_reduced_ = std::move(state_.reduced);
  for (const SweepPoint& p : done_points_) file_->append_table_row("sweep", kSweepColumns, row_of(p));
  if (!done_points_.empty()) write_csv(csv, done_points_), write_reduced_csv(out_ / "reduced.csv", done_reduced_);
  first_step_ = sim_.steps_done();
  context_ = reduction_context(scene_, P_.direction);
}

// Settling, the structure held.
void FrequencySweep::settle() {
  const auto settle_steps = static_cast<std::uint64_t>(std::llround(scene_.settle / scene_.dt));
  if (!state_.settled) {
    while (sim_.steps_done() < settle_steps) halt_if_asked(), sim_.step();
    if (settle_steps > 0 && !opt_.quiet) std::fprintf(stderr, "settled for %.4g s (%.0f s)\n", scene_.settle, since(t_start_));
    state_.clearance = contents_clearance(scene_, sim_, P_.direction.normalized());
    state_.settled = true;
    checkpoint();
  }
  context_.clearance = state_.clearance;
}

void FrequencySweep::run() {
  settle();
  npts_ = plan_.frequencies.size() + plan_.refine * (plan_.modes.empty() ? 1 : plan_.modes.size());
  // An upper bound of the points: group_by_mode's pointers into rep_.points stay valid.
  rep_.points.reserve(plan_.frequencies.size() + plan_.refine * std::max<std::size_t>(P_.size(), 1));
  // Progress: a line per cycle on a terminal (rewritten in place), a line per point in a log.
  terminal_ = isatty(fileno(stderr)) != 0;
  // The window is the last 2K cycles, at least reduce_cycles: a point is settled when the mean
  // first harmonic of the window's second half differs from its first half's by less than the
  // tolerance, so that the window reduced is the window judged steady. A point's first cycle is
  // never in it: the drive has just changed frequency (and, at the sweep's start, the structure
  // is released into its start state within it).
  K_ = plan_.half_window(), window_ = 2 * K_, least_ = plan_.least_cycles();
  for (double f : plan_.frequencies) point(f);
  // Peak refinement: per mode, `refine` more points, each halving the gap on the peak's side.
  for (std::size_t r = 0; r < plan_.refine; ++r)
    for (const ModePoints& m : group_by_mode(P_, rep_.points))
      if (const double f = refinement_frequency(m, scene_.dt); f > 0) point(f);
}

// The next point: one done before an interruption is taken as it was (the refinement then
// chooses as it did), a new one is run and checkpointed.
void FrequencySweep::point(double f) {
  if (rep_.points.size() < done_points_.size()) {
    rep_.reduced.push_back(done_reduced_[rep_.points.size()]);
    rep_.points.push_back(done_points_[rep_.points.size()]);
    return;
  }
  run_point(f);
  checkpoint();
}

// One frequency point, from the state the last one left.
void FrequencySweep::run_point(double requested) {
  const auto t_point = std::chrono::steady_clock::now();
  const std::size_t i = rep_.points.size();
  SweepPoint pt;
  pt.requested = requested;
  const std::size_t N = steps_per_cycle(pt.requested, scene_.dt);
  pt.frequency = 1.0 / (static_cast<double>(N) * scene_.dt);
  sim_.set_drive_frequency(pt.frequency);
  const double w = kTwoPi * pt.frequency;
  SteadyStateDetector steady(K_, plan_.tolerance);
  PointWindow win;
  drive_cycles(pt, N, steady, win, i);
  measure_window(pt, win, steady, w);
  rep_.reduced.push_back(reduce_window(pt, win));
  pt.wall_seconds = since(t_point);
  rep_.points.push_back(pt);
  file_->append_table_row("sweep", kSweepColumns, row_of(pt));
  frame();
  write_csv(out_ / "sweep.csv", rep_.points);
  write_reduced_csv(out_ / "reduced.csv", rep_.reduced);
  report_point(pt, i, win.ys.size());
}

// The drive's cycles at the point's N steps each, until the window is steady or max_cycles.
void FrequencySweep::drive_cycles(SweepPoint& pt, std::size_t N, SteadyStateDetector& steady, PointWindow& win,
                                  std::size_t i) {
  for (std::size_t c = 0; c < plan_.max_cycles; ++c) {
    win.starts.push_back(ledger(sim_));
    Complex Y(0, 0), U(0, 0), L(0, 0);
    if (win.recent.size() == window_)
      win.recent.pop_front(), win.starts.pop_front(), win.ys.pop_front(), win.cav.pop_front(), win.load.pop_front();
    CavitySeries& series = win.recent.emplace_back();
    for (auto* v : {&series.t, &series.x, &series.force, &series.v_rel}) v->reserve(N);  // no growth inside the steps
    for (std::size_t n = 0; n < N; ++n) {
      halt_if_asked();
      sim_.step();
      const StructureResponse r = sim_.structure_response();
      const Complex e = std::polar(1.0, -r.phase);
      Y += r.displacement * e, U += r.cavity * e, L += r.load * e;
      series.t.push_back(sim_.time()), series.x.push_back(r.cavity), series.force.push_back(r.load);
      series.v_rel.push_back(sim_.contents_relative_velocity().dot(P_.direction));
    }
    const double k = 2.0 / static_cast<double>(N);
    Y *= k, U *= k, L *= k;
    steady.add(Y);
    win.ys.push_back(Y), win.cav.push_back(U), win.load.push_back(L);
    pt.cycles = c + 1;
    pt.change = steady.last_change();
    if (!opt_.quiet && terminal_)
      std::fprintf(stderr, "\r  [%zu/%zu] %.4g Hz: cycle %zu, |Y| = %.4g m, change %.2g%%   ", i + 1, npts_, pt.frequency,
                   c + 1, std::abs(Y), 100 * pt.change);
    // Settled: the response (SteadyStateDetector) and the window's energy (as judge_steady will
    // judge it: a window that does not balance holds a transient; run on).
    if (pt.cycles >= least_ && steady.steady() && (!scene_.models.energy || balances(window_balance(win, sim_)))) {
      pt.settled = true;
      break;
    }
  }
}

// Response, energy and first harmonics over the window.
void FrequencySweep::measure_window(SweepPoint& pt, const PointWindow& win, const SteadyStateDetector& steady,
                                   double w) const {
  const double F = P_.amplitude;
  const double cycles = static_cast<double>(win.ys.size());
  std::vector<double> magnitude;
  pt.response = pt.cavity = pt.contents_force = Complex(0, 0);
  for (std::size_t c = 0; c < win.ys.size(); ++c) {
    pt.response += win.ys[c] / cycles, pt.cavity += win.cav[c] / cycles, pt.contents_force += win.load[c] / cycles;
    magnitude.push_back(std::abs(win.ys[c]) / F);
  }
  pt.receptance_ci95 = batch_means_interval(magnitude).ci95;
  const WindowBalance b = window_balance(win, sim_);
  pt.work_external = b.work_external, pt.dissipated_structure = b.dissipated_structure;
  pt.dissipated_contents = b.dissipated_contents, pt.balance = b.balance;
  pt.receptance = pt.response / Complex(0, -F);
  pt.bare = P_.bare_receptance(w);
  pt.spread = steady.spread();
}

// The damper's effective parameters over the same cycles (one step = one sample); sets pt.steady.
ReducedRow FrequencySweep::reduce_window(SweepPoint& pt, const PointWindow& win) const {
  CavitySeries last;
  for (const CavitySeries& c : win.recent) {
    last.t.insert(last.t.end(), c.t.begin(), c.t.end()), last.x.insert(last.x.end(), c.x.begin(), c.x.end());
    last.force.insert(last.force.end(), c.force.begin(), c.force.end());
    last.v_rel.insert(last.v_rel.end(), c.v_rel.begin(), c.v_rel.end());
  }
  ReducedRow reduced = reduce_series(last, pt.frequency, last.t.front() - 0.5 * scene_.dt, context_);
  reduced.response_amplitude = std::abs(pt.response);
  // Without the contents' energy tallies (output.energy = false) the balance cannot close: unknown.
  if (scene_.models.energy) reduced.dissipated_per_cycle = pt.dissipated_contents, reduced.energy_balance = pt.balance;
  if (!pt.settled) reduced.steady = 0;
  judge_steady(reduced);
  pt.steady = reduced.steady == 1;
  return reduced;
}

// The point's progress line, and why it is flagged unsteady if it is.
void FrequencySweep::report_point(const SweepPoint& pt, std::size_t i, std::size_t window_cycles) const {
  if (!opt_.quiet) {
    const double el = since(t_start_);
    std::fprintf(stderr, "%s  [%zu/%zu] %.5g Hz: |H| = %.4g +- %.2g m/N (bare %.4g), %s after %zu cycles, %.1f s; ETA %.0f s\n",
                 terminal_ ? "\r" : "", i + 1, npts_, pt.frequency, std::abs(pt.receptance), pt.receptance_ci95, std::abs(pt.bare),
                 pt.steady ? "steady" : "NOT steady", pt.cycles, pt.wall_seconds,
                 el / static_cast<double>(i + 1) * static_cast<double>(npts_ > i + 1 ? npts_ - i - 1 : 0));
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

SweepReport FrequencySweep::halted(const SweepHalt& h) {
  file_->flush();
  if (h.signal == 0) return rep_;  // the testing aid: as if killed
  if (!state_.settled) checkpoint();  // during settling; else the last point's checkpoint stands
  file_->set_attribute("status", "interrupted");
  file_->close();
  rep_.signal = h.signal;
  rep_.message = interrupted_message(h.signal, sim_.time(), rep_.points.size(), out_);
  return rep_;
}

SweepReport FrequencySweep::failed(const RunError& e) {
  rep_.message = e.what();
  close_results(std::string("failed: ") + e.what());
  return rep_;
}

std::string FrequencySweep::summary_json() const {
  std::ostringstream j;
  j << std::setprecision(10);
  j << "{\n  \"status\": \"complete\",\n  \"case\": \"" << json_escape(scene_.case_file) << "\",\n  \"kind\": \"stepped-sine\",\n"
    << "  \"particles\": " << sim_.particles().size() << ",\n  \"dt\": " << scene_.dt << ",\n"
    << "  \"threads\": " << omp_get_max_threads() << ",\n  \"wall_time_s\": " << rep_.wall_seconds << ",\n"
    << "  \"points\": " << rep_.points.size() << ",\n  \"not_steady\": "
    << std::count_if(rep_.points.begin(), rep_.points.end(), [](const SweepPoint& p) { return !p.steady; }) << ",\n"
    << "  \"force_amplitude_N\": " << P_.amplitude << ",\n  \"peaks\": ";
  j << peaks_json(rep_.peaks) << "\n}\n";
  return j.str();
}

SweepReport FrequencySweep::finish() {
  rep_.complete = true;
  rep_.wall_seconds = since(t_start_);
  rep_.peaks = sweep_peaks(P_, rep_.points);
  close_results("complete");
  fs::remove(out_ / "checkpoint.bin");

  const std::string summary = summary_json();
  write_peaks_csv(out_ / "peaks.csv", rep_.peaks);
  if (const std::string why = drop_where_no_restitution(scene_, rep_.reduced, out_, true); !why.empty() && !opt_.quiet)
    std::fprintf(stderr, "no restitution from the impacts or Eq. (19a), and the drop test could not run: %s\n", why.c_str());
  write_reduced_csv(out_ / "reduced.csv", rep_.reduced);
  rep_.compare = compare_with_continuum(P_, P_.amplitude, rep_.reduced);
  write_compare_csv(out_ / "compare.csv", rep_.compare);
  write_bare_curve(out_ / "bare_curve.csv", P_, rep_.points);
  write_atomically(out_ / "summary.json", summary);
  return rep_;
}

}  // namespace

SweepReport run_sweep(const Scene& scene, const RunOptions& opt) {
  if (!scene.primary || !scene.primary->sweep)
    throw InputError(scene.case_file, "excitation.kind", "", "a sweep needs a primary structure with excitation.kind = \"stepped-sine\"");
  const InterruptGuard interrupts;
  if (opt.threads > 0) omp_set_num_threads(opt.threads);
  fs::create_directories(opt.out_dir);
  FrequencySweep sweep(scene, opt);
  sweep.open();
  try {
    sweep.run();
  } catch (const SweepHalt& h) {
    return sweep.halted(h);
  } catch (const RunError& e) {
    return sweep.failed(e);
  }
  return sweep.finish();
}

}  // namespace bagdem
