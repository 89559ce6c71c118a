// The stepped sine: the structure driven at one frequency after another (run/stepped_sine.hpp).
#include "bagdem/run/stepped_sine.hpp"

#include "stepped_sine_run.hpp"

namespace bagdem {
namespace stepped_sine_run {

void SteppedSineRun::open() {
  for (std::size_t k = 1; k < dampers_; ++k) fs::create_directories(more_out(k));
  const fs::path part = out_ / "results.h5.part", csv = out_ / kSweepPartial;
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
  if (!done_points_.empty()) write_stepped_sine_csv(csv, done_points_), write_reduced_csv(out_ / kReducedPartial, done_reduced_);
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
    if (fs::exists(out_ / (std::string(t) + ".partial.csv"))) fs::rename(out_ / (std::string(t) + ".partial.csv"), out_ / (std::string(t) + ".failed.csv"));
  for (std::size_t k = 1; k < dampers_; ++k)
    if (fs::exists(more_out(k) / kReducedPartial)) fs::rename(more_out(k) / kReducedPartial, more_out(k) / "reduced.failed.csv");
  rep_.message = failed_run_message(e.what(), close_results(std::string("failed: ") + e.what(), false));
  fs::remove(out_ / "checkpoint.bin");  // a failed sweep is not continued: resuming it would fail again
  return rep_;
}

SteppedSineReport SteppedSineRun::finish() {
  rep_.complete = true;
  rep_.wall_seconds = since(t_start_);
  rep_.peaks = sweep_peaks(P_, rep_.points);
  // Everything that takes time before results.h5 is complete: a run stopped here resumes from its
  // checkpoint (the drop tests may take seconds; killed after the rename, nothing could resume it).
  Scene own = scene_;  // the case's own damper alone (its drop test)
  own.more_dampers.clear();
  if (const std::string why = drop_where_no_restitution(own, rep_.reduced, out_, true); !why.empty() && !opt_.quiet)
    std::fprintf(stderr, "no restitution from the impacts or Eq. (19a), and the drop test could not run: %s\n", why.c_str());
  for (std::size_t k = 1; k < dampers_; ++k)
    if (const std::string why = drop_where_no_restitution(more_scene(k), state_.more_reduced[k - 1], more_out(k), true); !why.empty() && !opt_.quiet)
      std::fprintf(stderr, "damper %s: no restitution from the impacts or Eq. (19a), and the drop test could not run: %s\n",
                   scene_.more_dampers[k - 1].name.c_str(), why.c_str());
  // The continuum model with the contents' C_b and M_b (several dampers: the modal model with each
  // at its place).
  if (dampers_ == 1) {
    rep_.compare = compare_with_continuum(P_, P_.amplitude, rep_.reduced);
  } else {
    std::vector<const Primary*> primaries{&P_};
    std::vector<std::vector<ReducedRow>> rows{rep_.reduced};
    for (std::size_t k = 1; k < dampers_; ++k) primaries.push_back(more_scene(k).primary.get()), rows.push_back(state_.more_reduced[k - 1]);
    rep_.compare = compare_with_dampers(primaries, P_.amplitude, rows);
  }
  const Summary summary = stepped_sine_summary(scene_, rep_, sim0().particles().size(), chains_.size());
  // The reduced rows in the record too, sealed with it: reduce and compare check reduced.csv against them.
  for (const ReducedRow& r : rep_.reduced) file_->append_table_row("reduced", reduced_columns(), reduced_values(r));

  close_results("complete", true);
  fs::remove(out_ / "checkpoint.bin");
  // The tables of the points, whole now: under their own names, the partial ones gone.
  write_peaks_csv(out_ / "peaks.csv", rep_.peaks);
  write_stepped_sine_csv(out_ / "sweep.csv", rep_.points);
  write_reduced_csv(out_ / "reduced.csv", rep_.reduced);
  fs::remove(out_ / kSweepPartial), fs::remove(out_ / kReducedPartial);
  for (std::size_t k = 1; k < dampers_; ++k) {
    write_reduced_csv(more_out(k) / "reduced.csv", state_.more_reduced[k - 1]);
    fs::remove(more_out(k) / kReducedPartial);
  }
  write_compare_csv(out_ / "compare.csv", rep_.compare);
  write_bare_curve(out_ / "bare_curve.csv", P_, rep_.points);
  write_summary(out_ / "summary.json", summary);
  return rep_;
}

}  // namespace stepped_sine_run

SteppedSineReport run_stepped_sine(const Scene& scene, const RunOptions& opt) {
  if (!scene.primary || !scene.primary->stepped_sine)
    throw InputError(scene.case_file, "excitation.kind", "", "a sweep needs a primary structure with excitation.kind = \"stepped-sine\"");
  const InterruptGuard interrupts;
  if (opt.threads > 0) omp_set_num_threads(opt.threads);
  refuse_other_outputs(opt.out_dir, OutputOwner::run);
  const OutputLock lock(opt.out_dir);  // creates the directory
  clear_other_dampers(opt.out_dir, scene, opt.resume);
  stepped_sine_run::SteppedSineRun sweep(scene, opt);
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
