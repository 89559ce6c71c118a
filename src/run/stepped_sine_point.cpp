// A stepped sine's point: run from its chain's state, its window measured and reduced, written in
// order (stepped_sine_run.hpp).
#include "stepped_sine_run.hpp"

namespace bagdem::stepped_sine_run {

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
  write_stepped_sine_csv(out_ / kSweepPartial, rep_.points);
  write_reduced_csv(out_ / kReducedPartial, rep_.reduced);
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

}  // namespace bagdem::stepped_sine_run
