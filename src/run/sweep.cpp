// Stepped-sine sweep (run/sweep.hpp).
#include "bagdem/run/sweep.hpp"

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
#include "bagdem/io/results_file.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/reduce/compare.hpp"
#include "bagdem/reduce/interval.hpp"
#include "bagdem/reduce/reduce.hpp"
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

}  // namespace

SweepReport run_sweep(const Scene& scene, const RunOptions& opt) {
  if (!scene.primary || !scene.primary->sweep)
    throw InputError(scene.case_file, "excitation.kind", "", "a sweep needs a primary structure with excitation.kind = \"stepped-sine\"");
  const InterruptGuard interrupts;
  if (opt.threads > 0) omp_set_num_threads(opt.threads);
  const Primary& P = *scene.primary;
  const Primary::Sweep& plan = *P.sweep;
  const fs::path out = opt.out_dir;
  fs::create_directories(out);
  const fs::path part = out / "results.h5.part", final_h5 = out / "results.h5", summary = out / "summary.json";
  const fs::path csv = out / "sweep.csv", ckpt = out / "checkpoint.bin";
  // The state of an interrupted sweep (sweep_state.hpp), or a fresh start.
  SweepState state;
  Simulation sim(scene);
  start_sweep_state(out, opt.resume, sim, state);

  const auto t_start = std::chrono::steady_clock::now();
  auto since = [](std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  std::vector<std::string> mats;
  for (const auto& m : scene.materials) mats.push_back(m.name);
  ResultsFile file = opt.resume ? ResultsFile::reopen(part.string(), state.lengths) : open_results(part.string(), sim, mats, scene.dt);
  std::vector<double>& frame_times = state.frame_times;
  auto frame = [&] {
    append_ball_frame(file, sim.time(), sim);
    if (scene.bag) file.append_film_frame(sim.film().x);
    frame_times.push_back(sim.time());
  };
  file.set_attribute("status", "running");
  if (!opt.resume) {
    file.set_attribute("case_file", scene.case_file);
    file.set_attribute("resolved_config", scene.resolved);
    file.set_attribute("settle_end", scene.settle);
    file.set_attribute("timestep", scene.dt);
    if (scene.bag) file.write_film(scene.bag->rest.triangles, scene.bag->rest.vertices.size());
    frame();
  }

  SweepReport rep;
  const double F = P.amplitude;
  // The points done before an interruption: their rows again (the reopened file has no /sweep).
  const std::vector<SweepPoint> done_points = std::move(state.points);
  const std::vector<ReducedRow> done_reduced = std::move(state.reduced);
  for (const SweepPoint& p : done_points) file.append_table_row("sweep", kSweepColumns, row_of(p));
  if (!done_points.empty()) write_csv(csv, done_points), write_reduced_csv(out / "reduced.csv", done_reduced);
  const std::uint64_t first_step = sim.steps_done();  // a signal, or the testing aid, stops the next step
  auto halt_if_asked = [&] {
    if (const int sig = pending_interrupt()) throw SweepHalt{sig};
    if (opt.stop_after_steps >= 0 && sim.steps_done() - first_step >= static_cast<std::uint64_t>(opt.stop_after_steps))
      throw SweepHalt{0};
  };
  ReductionContext context = reduction_context(scene, nullptr, P.direction);
  // A checkpoint of the sweep as it stands (between points, or during settling).
  auto checkpoint = [&] {
    file.flush();
    state.lengths = file.lengths(), state.points = rep.points, state.reduced = rep.reduced;
    save_sweep_checkpoint(ckpt, sim, state);
  };
  try {
    // Settling, the structure held.
    const auto settle_steps = static_cast<std::uint64_t>(std::llround(scene.settle / scene.dt));
    if (!state.settled) {
      while (sim.steps_done() < settle_steps) halt_if_asked(), sim.step();
      if (settle_steps > 0 && !opt.quiet) std::fprintf(stderr, "settled for %.4g s (%.0f s)\n", scene.settle, since(t_start));
      state.clearance = reduction_context(scene, &sim, P.direction).clearance;
      state.settled = true;
      checkpoint();
    }
    context.clearance = state.clearance;

    std::size_t npts = plan.frequencies.size() + plan.refine * (plan.modes.empty() ? 1 : plan.modes.size());
    // An upper bound of the points: group_by_mode's pointers into rep.points stay valid.
    rep.points.reserve(plan.frequencies.size() + plan.refine * std::max<std::size_t>(P.size(), 1));
    // Progress: a line per cycle on a terminal (rewritten in place), a line per point in a log.
    const bool terminal = isatty(fileno(stderr)) != 0;
    // The window is the last 2K cycles, at least reduce_cycles: a point is settled when the mean
    // first harmonic of the window's second half differs from its first half's by less than the
    // tolerance, so that the window reduced is the window judged steady. A point's first cycle is
    // never in it: the drive has just changed frequency (and, at the sweep's start, the structure
    // is released into its start state within it).
    const std::size_t K = plan.half_window(), window = 2 * K, least = plan.least_cycles();
    // One frequency point, from the state the last one left.
    auto run_point = [&](double requested) {
      const auto t_point = std::chrono::steady_clock::now();
      const std::size_t i = rep.points.size();
      SweepPoint pt;
      pt.requested = requested;
      const std::size_t N = steps_per_cycle(pt.requested, scene.dt);
      pt.frequency = 1.0 / (static_cast<double>(N) * scene.dt);
      sim.set_drive_frequency(pt.frequency);
      const double w = kTwoPi * pt.frequency;
      SteadyStateDetector steady(K, plan.tolerance);
      // The last `window` cycles: the ledger at the start of each, the first harmonics, the samples.
      std::deque<Ledger> starts;
      std::deque<Complex> ys, cav, load;
      std::deque<CavitySeries> recent;
      for (std::size_t c = 0; c < plan.max_cycles; ++c) {
        starts.push_back(ledger(sim));
        Complex Y(0, 0), U(0, 0), L(0, 0);
        if (recent.size() == window) recent.pop_front(), starts.pop_front(), ys.pop_front(), cav.pop_front(), load.pop_front();
        CavitySeries& series = recent.emplace_back();
        for (auto* v : {&series.t, &series.x, &series.force, &series.v_rel}) v->reserve(N);  // no growth inside the steps
        for (std::size_t n = 0; n < N; ++n) {
          halt_if_asked();
          sim.step();
          const StructureResponse r = sim.structure_response();
          const Complex e = std::polar(1.0, -r.phase);
          Y += r.displacement * e, U += r.cavity * e, L += r.load * e;
          series.t.push_back(sim.time()), series.x.push_back(r.cavity), series.force.push_back(r.load);
          series.v_rel.push_back(sim.contents_relative_velocity().dot(P.direction));
        }
        const double k = 2.0 / static_cast<double>(N);
        Y *= k, U *= k, L *= k;
        steady.add(Y);
        ys.push_back(Y), cav.push_back(U), load.push_back(L);
        pt.cycles = c + 1;
        pt.change = steady.last_change();
        if (!opt.quiet && terminal)
          std::fprintf(stderr, "\r  [%zu/%zu] %.4g Hz: cycle %zu, |Y| = %.4g m, change %.2g%%   ", i + 1, npts, pt.frequency,
                       c + 1, std::abs(Y), 100 * pt.change);
        if (pt.cycles >= least && steady.steady()) {
          pt.settled = true;
          break;
        }
      }
      // Response, energy, first harmonics and reduction over the window.
      const Ledger end = ledger(sim), &from = starts.front();
      const double cycles = static_cast<double>(ys.size());
      std::vector<double> magnitude;
      pt.response = pt.cavity = pt.contents_force = Complex(0, 0);
      for (std::size_t c = 0; c < ys.size(); ++c) {
        pt.response += ys[c] / cycles, pt.cavity += cav[c] / cycles, pt.contents_force += load[c] / cycles;
        magnitude.push_back(std::abs(ys[c]) / F);
      }
      pt.receptance_ci95 = batch_means_interval(magnitude).ci95;
      pt.work_external = (end.work_external - from.work_external) / cycles;
      pt.dissipated_structure = (end.dissipated_structure - from.dissipated_structure) / cycles;
      pt.dissipated_contents = (end.dissipated_contents - from.dissipated_contents) / cycles;
      const double residual = pt.work_external - pt.dissipated_structure - pt.dissipated_contents - (end.stored - from.stored) / cycles;
      pt.balance = pt.work_external != 0 ? residual / std::abs(pt.work_external) : 0.0;
      pt.receptance = pt.response / Complex(0, -F);
      pt.bare = P.bare_receptance(w);
      pt.spread = steady.spread();
      // The damper's effective parameters over the same cycles (one step = one sample).
      CavitySeries last;
      for (const CavitySeries& c : recent) {
        last.t.insert(last.t.end(), c.t.begin(), c.t.end()), last.x.insert(last.x.end(), c.x.begin(), c.x.end());
        last.force.insert(last.force.end(), c.force.begin(), c.force.end());
        last.v_rel.insert(last.v_rel.end(), c.v_rel.begin(), c.v_rel.end());
      }
      ReducedRow reduced = reduce_series(last, pt.frequency, last.t.front() - 0.5 * scene.dt, context);
      reduced.response_amplitude = std::abs(pt.response);
      // Without the contents' energy tallies (output.energy = false) the balance cannot close: unknown.
      if (scene.models.energy) reduced.dissipated_per_cycle = pt.dissipated_contents, reduced.energy_balance = pt.balance;
      if (!pt.settled) reduced.steady = 0;
      judge_steady(reduced);
      pt.steady = reduced.steady == 1;
      rep.reduced.push_back(reduced);
      pt.wall_seconds = since(t_point);
      rep.points.push_back(pt);
      file.append_table_row("sweep", kSweepColumns, row_of(pt));
      frame();
      write_csv(csv, rep.points);
      write_reduced_csv(out / "reduced.csv", rep.reduced);
      if (!opt.quiet) {
        const double el = since(t_start);
        std::fprintf(stderr, "%s  [%zu/%zu] %.5g Hz: |H| = %.4g +- %.2g m/N (bare %.4g), %s after %zu cycles, %.1f s; ETA %.0f s\n",
                     terminal ? "\r" : "", i + 1, npts, pt.frequency, std::abs(pt.receptance), pt.receptance_ci95, std::abs(pt.bare),
                     pt.steady ? "steady" : "NOT steady", pt.cycles, pt.wall_seconds,
                     el / static_cast<double>(i + 1) * static_cast<double>(npts > i + 1 ? npts - i - 1 : 0));
      }
      if (!pt.steady) {
        std::ostringstream m;
        m << "warning: " << pt.frequency << " Hz is flagged unsteady and left out of the peaks: ";
        if (!pt.settled)
          m << "it did not settle in " << plan.max_cycles << " cycles (last change " << 100 * pt.change << "%, tolerance "
            << 100 * plan.tolerance << "%); raise excitation.max_cycles or excitation.steady_tolerance\n";
        else
          m << "over its last " << ys.size() << " cycles the energy balance is off by " << 100 * pt.balance
            << "% (allowed " << 100 * kSteadyBalanceTolerance << "%) or the contents' tallied dissipation is negative ("
            << pt.dissipated_contents << " J per cycle); raise excitation.min_cycles (a longer transient) or lower simulation.timestep_safety\n";
        std::fputs(m.str().c_str(), stderr);
      }
    };
    // The next point: one done before an interruption is taken as it was (the refinement then
    // chooses as it did), a new one is run and checkpointed.
    auto point = [&](double f) {
      if (rep.points.size() < done_points.size()) {
        rep.reduced.push_back(done_reduced[rep.points.size()]);
        rep.points.push_back(done_points[rep.points.size()]);
        return;
      }
      run_point(f);
      checkpoint();
    };
    for (double f : plan.frequencies) point(f);
    // Peak refinement: per mode, `refine` more points, each halving the gap on the peak's side.
    for (std::size_t r = 0; r < plan.refine; ++r)
      for (const ModePoints& m : group_by_mode(P, rep.points))
        if (const double f = refinement_frequency(m, scene.dt); f > 0) point(f);
  } catch (const SweepHalt& h) {
    file.flush();
    if (h.signal == 0) return rep;  // the testing aid: as if killed
    if (!state.settled) checkpoint();  // during settling; else the last point's checkpoint stands
    file.set_attribute("status", "interrupted");
    file.close();
    rep.signal = h.signal;
    rep.message = interrupted_message(h.signal, sim.time(), rep.points.size(), out);
    return rep;
  } catch (const RunError& e) {
    rep.message = e.what();
    file.set_attribute("status", std::string("failed: ") + e.what());
    file.close();
    fs::rename(part, final_h5);
    write_xdmf((out / "results.xmf").string(), "results.h5", sim.particles().size(), frame_times, sim.film().size(),
               scene.bag ? scene.bag->rest.triangles.size() : 0);
    return rep;
  }
  rep.complete = true;
  rep.wall_seconds = since(t_start);
  rep.peaks = sweep_peaks(P, rep.points);
  file.set_attribute("status", "complete");
  file.close();
  fs::rename(part, final_h5);
  write_xdmf((out / "results.xmf").string(), "results.h5", sim.particles().size(), frame_times, sim.film().size(),
             scene.bag ? scene.bag->rest.triangles.size() : 0);
  fs::remove(ckpt);

  std::ostringstream j;
  j << std::setprecision(10);
  j << "{\n  \"status\": \"complete\",\n  \"case\": \"" << json_escape(scene.case_file) << "\",\n  \"kind\": \"stepped-sine\",\n"
    << "  \"particles\": " << sim.particles().size() << ",\n  \"dt\": " << scene.dt << ",\n"
    << "  \"threads\": " << omp_get_max_threads() << ",\n  \"wall_time_s\": " << rep.wall_seconds << ",\n"
    << "  \"points\": " << rep.points.size() << ",\n  \"not_steady\": "
    << std::count_if(rep.points.begin(), rep.points.end(), [](const SweepPoint& p) { return !p.steady; }) << ",\n"
    << "  \"force_amplitude_N\": " << F << ",\n  \"peaks\": ";
  j << peaks_json(rep.peaks) << "\n}\n";
  write_peaks_csv(out / "peaks.csv", rep.peaks);
  if (const std::string why = drop_where_no_restitution(scene, rep.reduced, out, true); !why.empty() && !opt.quiet)
    std::fprintf(stderr, "no restitution from the impacts or Eq. (19a), and the drop test could not run: %s\n", why.c_str());
  write_reduced_csv(out / "reduced.csv", rep.reduced);
  rep.compare = compare_with_continuum(P, F, rep.reduced);
  write_compare_csv(out / "compare.csv", rep.compare);
  write_bare_curve(out / "bare_curve.csv", P, rep.points);
  write_atomically(summary, j.str());
  return rep;
}

}  // namespace bagdem
