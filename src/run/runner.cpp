#include "bagdem/run/runner.hpp"

#include <omp.h>

#include <chrono>
#include <cstring>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <optional>
#include <sstream>
#include <type_traits>

#include "bagdem/case/overrides.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/atomic_file.hpp"
#include "bagdem/io/json.hpp"
#include "bagdem/io/output_lock.hpp"
#include "bagdem/io/results_file.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "bagdem/run/bag_report.hpp"
#include "bagdem/run/clearance.hpp"
#include "bagdem/run/drop_fallback.hpp"
#include "bagdem/step/dampers.hpp"
#include "bagdem/step/simulation.hpp"
#include "checkpoint_file.hpp"
#include "bagdem/interrupt.hpp"
#include "output_files.hpp"
#include "run_summary.hpp"

namespace bagdem {
namespace fs = std::filesystem;

namespace {

// Steps between two events of an interval (at least 1).
std::uint64_t every(double interval, double dt) {
  return std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(interval / dt)));
}

// The energy budget's closure: residual = in - (change of stored) - dissipated, and its scale.
struct Closure {
  double residual, scale;
};
Closure closure(const EnergySample& e, double stored0) {
  const double in = e.work_cavity + e.work_gravity;
  const double diss = e.dissipated();
  return {in - (e.kinetic + e.elastic - stored0) - diss,
          std::max({std::abs(e.work_cavity) + std::abs(e.work_gravity), diss, e.kinetic + e.elastic, stored0, 1e-300})};
}

// Relative closure of the energy budget: |in - (change of stored) - dissipated| / scale.
double balance_error(const EnergySample& e, double stored0) {
  const Closure c = closure(e, stored0);
  return std::abs(c.residual) / c.scale;
}

// /structure columns (results_file.hpp): time; the response at x_a along e; the external force at
// x_f; the cavity's displacement; the contents' transverse force on the cavity; the structure's
// cumulative work and dissipation tallies and its stored energy.
const std::vector<TableColumn> kStructureColumns = {
    {"time", "s"},           {"displacement", "m"},     {"velocity", "m/s"},  {"acceleration", "m/s^2"},
    {"force", "N"},          {"cavity_displacement", "m"}, {"contents_force", "N"}, {"work_external", "J"},
    {"work_contents", "J"},  {"dissipated", "J"},       {"energy", "J"}};

// What the run loop itself must carry across a restart, beside the simulation state: 8-byte
// fields only, so that the image has no padding.
struct RunTallies {
  SeriesLengths lengths;               // rows written to results.h5
  double dissipated_at_measure = 0;    // total dissipation when the measured cycles began (J)
  double bag_packing = -1;             // the bag's packing fraction when settling ended (-1: not yet)
  double bag_outer[3] = {0, 0, 0};     // its outer size then (m)
};
static_assert(std::is_trivially_copyable_v<RunTallies> && sizeof(RunTallies) == sizeof(SeriesLengths) + 5 * sizeof(double));

// checkpoint.bin of a run (checkpoint_file.hpp): the tallies, then the simulation's state image.
void save_checkpoint(const fs::path& path, const Simulation& sim, const RunTallies& l) {
  const std::vector<char> state = sim.save_state();
  save_checkpoint_file(path, checkpoint_of("run", sim.scene(),
                                           {std::string(reinterpret_cast<const char*>(&l), sizeof l), std::string(state.begin(), state.end())}));
}

struct Checkpoint {
  RunTallies tallies;
  std::vector<char> state;
};

Checkpoint load_checkpoint(const fs::path& path, const Scene& scene) {
  const CheckpointData d = load_checkpoint_file(path, "run");
  require_checkpoint_case(d, scene);
  Checkpoint c;
  if (d.blocks.size() != 2 || d.blocks[0].size() != sizeof c.tallies)
    throw InputError("checkpoint " + path.string() + " has not the blocks of a run; run again without --resume");
  std::memcpy(static_cast<void*>(&c.tallies), d.blocks[0].data(), sizeof c.tallies);
  c.state.assign(d.blocks[1].begin(), d.blocks[1].end());
  return c;
}

// When a run records, checks and reports, in steps.
struct RunSchedule {
  std::uint64_t total, n_frame, n_cavity, n_energy, n_ckpt;
  double f_drive;             // the motion's frequency (Hz; 0 without harmonic motion)
  std::uint64_t measure_step;  // the per-cycle figures start here
  std::uint64_t settle_step;
};

RunSchedule schedule_of(const Scene& scene) {
  RunSchedule r;
  r.total = scene.total_steps();
  r.n_frame = every(scene.output.frame_interval, scene.dt);
  r.n_cavity = every(scene.output.cavity_interval, scene.dt);
  r.n_energy = every(scene.output.energy_interval, scene.dt);
  r.n_ckpt = scene.output.checkpoint_interval > 0 ? every(scene.output.checkpoint_interval, scene.dt) : 0;
  // Per-cycle figures are taken over whole cycles after settling, the motion's ramp, and
  // output.skip_cycles of start-up.
  r.f_drive = scene.motion->frequency();
  const double skip = scene.motion->ramp_time() + (r.f_drive > 0 ? scene.output.skip_cycles / r.f_drive : 0.0);
  r.measure_step = static_cast<std::uint64_t>(std::llround((scene.settle + skip) / scene.dt));
  r.settle_step = static_cast<std::uint64_t>(std::llround(scene.settle / scene.dt));
  return r;
}

double total_dissipation(const EnergySample& e) { return e.dissipated(); }

// What a run steps: one damper's simulation, or several dampers on one structure (Dampers).
struct Stepped {
  Simulation* one = nullptr;
  Dampers* many = nullptr;
  void advance(std::uint64_t n) { one ? one->advance(n) : many->advance(n); }
  std::uint64_t done() const { return one ? one->steps_done() : many->steps_done(); }
  double time() const { return one ? one->time() : many->time(); }
};

// One damper's record of a run: its results file and what it records on the way, in its output
// directory; the structure's table with the case's own damper only. The simulation is stepped by
// step_all.
class RunLoop {
 public:
  // who: "" for a case of one damper, else "damper NAME: " (its messages start with it).
  RunLoop(const Scene& scene, const RunOptions& opt, Simulation& sim, fs::path out, bool structure, std::string who = "")
      : scene_(scene), opt_(opt), out_(std::move(out)), sim_(sim), at_(schedule_of(scene)), structure_(structure), who_(std::move(who)) {}

  // Restores an interrupted run (--resume) or starts a new one: results.h5.part open.
  void open() {
    if (opt_.resume) resume();
    else start();
  }
  // What is due at step s (just done).
  void record(std::uint64_t s);
  // The next step after s at which something is recorded or checked.
  std::uint64_t next_event(std::uint64_t s) const;
  // This session's steps start at `first` (the testing aid counts from it).
  void begin(std::uint64_t first) { first_step_ = first; }
  // When settling ended before the first step (simulation.settle = 0).
  void settled_at_start() {
    if (scene_.bag) bag_settled();
    record_clearance();
  }
  // A signal stopped the run: the state as a checkpoint, results.h5.part kept.
  void interrupted(int sig);
  // The simulated kill of the testing aid: nothing finalised.
  void killed() { file_->flush(); }
  // The run went unstable: results.failed.h5, no checkpoint.
  void failed(const RunError& e) {
    rep_.message = failed_run_message(e.what(), close_results(std::string("failed: ") + e.what(), false));
    fs::remove(ckpt());  // a failed run is not continued: resuming it would fail again
  }
  // The headline figures, results.h5 in place, summary.json and the reduction of a complete run
  // (wall: the seconds the steps took from first_step on).
  // particles: the run's, every damper's.
  void finish(double wall, std::uint64_t first_step, std::size_t particles);
  RunReport& report() { return rep_; }
  const RunSchedule& schedule() const { return at_; }

 private:
  void resume();
  void start();
  void bag_settled();
  void record_clearance() {
    if (excitation_.norm() > 0) file_->set_attribute("clearance", contents_clearance(scene_, sim_, excitation_));
  }
  void structure_row();
  void check_bag(double t) const;
  void check_energy(double t, const EnergySample& e);
  void save() {
    file_->flush();
    run_.lengths = file_->lengths();
    save_checkpoint(ckpt(), sim_, run_);
  }
  fs::path close_results(const std::string& status, bool complete) {
    return close_results_file(*file_, out_, status, complete, frame_times_,
                              {sim_.particles().size(), sim_.film().size(), scene_.bag ? scene_.bag->rest.triangles.size() : 0});
  }
  fs::path part() const { return out_ / "results.h5.part"; }
  fs::path ckpt() const { return out_ / "checkpoint.bin"; }

  const Scene& scene_;
  const RunOptions& opt_;
  const fs::path out_;
  Simulation& sim_;
  const RunSchedule at_;
  const bool structure_;  // this damper writes the structure's table
  const std::string who_;
  RunReport rep_;
  RunTallies run_;
  double energy_scale_ = 0;  // the largest scale of the energy budget so far (check_energy; unit: J)
  // The primary structure's response at x_a after release, for the summary's RMS and decay figures.
  std::vector<double> response_, response_acc_;
  std::vector<double> frame_times_;
  std::optional<ResultsFile> file_;
  // The contents' free travel along the excitation when settling ends (reduce/reduce.hpp: d/X).
  const Vec3 excitation_ = excitation_direction(scene_);
  std::uint64_t first_step_ = 0;  // where this session's steps started (the testing aid counts from it)
};

// When settling ends: the bag's packing and size, and the settled bag saved for reuse (bag.from).
void RunLoop::bag_settled() {
  const BagReport b = measure_bag(scene_, sim_);
  run_.bag_packing = b.packing_fraction;
  for (int k = 0; k < 3; ++k) run_.bag_outer[k] = b.outer[k];
  rep_.bag = true;
  rep_.bag_packing = b.packing_fraction;
  rep_.bag_outer = b.outer;
  if (scene_.settle > 0) save_bag((out_ / "bag.h5").string(), saved_bag(scene_, sim_));
  if (!opt_.quiet) {
    std::ostringstream m;
    m << std::setprecision(3) << "bag at t = " << sim_.time() << " s: packing fraction " << b.packing_fraction
      << ", outer " << 1e3 * b.outer.x() << " x " << 1e3 * b.outer.y() << " x " << 1e3 * b.outer.z() << " mm"
      << (scene_.settle > 0 ? "; settled bag saved to " + (out_ / "bag.h5").string() : std::string()) << "\n";
    std::fputs(m.str().c_str(), stderr);
  }
}

// The primary structure at each cavity sample (instantaneous values at the sample's end).
void RunLoop::structure_row() {
  if (!scene_.primary || !structure_) return;
  const StructureResponse r = sim_.structure_response();
  const auto& S = sim_.structure().scalars;
  file_->append_table_row("structure", kStructureColumns,
                          {sim_.time(), r.displacement, r.velocity, r.acceleration, r.force, r.cavity, r.load,
                           S.work_external, S.work_contents, S.dissipated, sim_.structure_energy()});
  if (S.released) response_.push_back(r.displacement), response_acc_.push_back(r.acceleration);
}

void RunLoop::resume() {
  Checkpoint c = load_checkpoint(ckpt(), scene_);
  if (!fs::exists(part())) throw InputError(part().string(), "", "", "the partial results file of the interrupted run is missing; run again without --resume");
  try {
    sim_.load_state(c.state);
  } catch (const std::exception& e) {
    throw InputError(ckpt().string(), "", "", std::string(e.what()) + "; run again without --resume");
  }
  run_ = c.tallies;
  if (run_.bag_packing >= 0) {  // settled before the interruption
    rep_.bag = true;
    rep_.bag_packing = run_.bag_packing;
    rep_.bag_outer = Vec3(run_.bag_outer[0], run_.bag_outer[1], run_.bag_outer[2]);
  }
  remove_derived_tables(out_);  // a run in progress is not complete
  file_.emplace(reopen_results(part(), run_.lengths));
  write_run_attributes(*file_, scene_);
  if (scene_.primary && structure_ && run_.lengths.structure > 0) {
    // The response before the interruption, for the summary's RMS and decay over the whole run:
    // the rows after release (the structure is released at the start of the step after settling).
    const std::vector<double> t = file_->read_series("/structure/time");
    const std::vector<double> y = file_->read_series("/structure/displacement");
    const std::vector<double> a = file_->read_series("/structure/acceleration");
    for (std::size_t k = 0; k < t.size(); ++k)
      if (t[k] > scene_.settle + 0.5 * scene_.dt) response_.push_back(y[k]), response_acc_.push_back(a[k]);
  }
  for (std::size_t k = 0; k < run_.lengths.frames; ++k) {
    const std::uint64_t s = std::min<std::uint64_t>(k * at_.n_frame, at_.total);
    frame_times_.push_back(static_cast<double>(s) * scene_.dt);
  }
}

void RunLoop::start() {
  fs::create_directories(out_);  // a damper's own (OUT/dampers/NAME)
  // The tables of an earlier run go; its results.h5 stays until this run's replaces it.
  remove_derived_tables(out_);
  fs::remove(ckpt());
  std::vector<std::string> mats;
  for (const auto& m : scene_.materials) mats.push_back(m.name);
  file_.emplace(open_results(part().string(), sim_, mats, at_.n_cavity * scene_.dt));
  write_run_attributes(*file_, scene_);
  if (scene_.bag) file_->write_film(scene_.bag->rest.triangles, scene_.bag->rest.vertices.size());
  append_frame(*file_, frame_of(sim_, 0));
  if (scene_.models.energy) file_->append_energy(0, sim_.energy().terms());
  frame_times_.push_back(0);
}

// The next step after s at which something is recorded or checked: the steps up to it run as one
// advance (Simulation::advance, the same bits as step by step, one pass over the balls fewer).
std::uint64_t RunLoop::next_event(std::uint64_t s) const {
  const bool energy = scene_.models.energy;
  std::uint64_t e = at_.total;
  for (std::uint64_t every : {at_.n_cavity, energy ? at_.n_energy : 0, at_.n_frame, at_.n_ckpt, std::uint64_t{1024}})
    if (every > 0) e = std::min(e, (s / every + 1) * every);
  for (std::uint64_t at : {at_.settle_step, energy ? at_.measure_step : 0})
    if (at > s) e = std::min(e, at);
  if (opt_.stop_after_steps >= 0) e = std::min(e, std::max(s + 1, first_step_ + static_cast<std::uint64_t>(opt_.stop_after_steps)));
  return e;
}

// Behind the per-step guard (a ball beyond the film's mid-surface), a global check at each frame:
// every ball of the bag is inside its film (winding number).
void RunLoop::check_bag(double t) const {
  if (!scene_.bag) return;
  const std::vector<std::size_t> out_of_bag = sim_.balls_outside_bag();
  if (!out_of_bag.empty())
    throw RunError(who_ + "run stopped at t = " + std::to_string(t) + " s: " + std::to_string(out_of_bag.size()) +
                   " ball(s) of the bag (first: " + std::to_string(out_of_bag.front()) +
                   ") are outside its film. The film let them through: raise the film material's "
                   "youngs_modulus, refine the film (bag.triangles), or reduce simulation.timestep.");
}

// The energy budget at time t: the contents (and the film) may not gain energy no work put in, by
// more than simulation.max_energy_error of the budget's largest scale so far (the largest scale, not
// the present one: a run's first samples have little work in them). An element or a contact that
// goes unstable shows here first, where its energy jumps within a few steps.
void RunLoop::check_energy(double t, const EnergySample& e) {
  const double limit = scene_.max_energy_error;
  if (!(limit > 0)) return;
  const Closure c = closure(e, sim_.initial_stored_energy());
  energy_scale_ = std::max(energy_scale_, c.scale);
  if (std::abs(c.residual) <= limit * energy_scale_) return;
  std::ostringstream m;
  m << who_ << "run stopped at t = " << t << " s: the energy budget broke: the stored energy and the dissipation differ from the work "
    << "put in by " << c.residual << " J, " << std::abs(c.residual) / energy_scale_ << " of its scale (limit "
    << limit << ", key simulation.max_energy_error). Something went unstable within a few steps: a contact too stiff "
    << "for the step, or the film crushed finer than its triangles resolve. Reduce simulation.timestep (or simulation.timestep_safety), "
    << "refine the film (bag.triangles), or lower the excitation.";
  throw RunError(m.str());
}

// What is due at step s (just done).
void RunLoop::record(std::uint64_t s) {
  const bool energy = scene_.models.energy;
  const double t = sim_.time();
  if (s == at_.settle_step) {
    if (scene_.bag) bag_settled();
    record_clearance();
  }
  if (energy && s == at_.measure_step) run_.dissipated_at_measure = total_dissipation(sim_.energy());
  if (s % at_.n_cavity == 0 || s == at_.total) {
    const CavitySample c = sim_.take_cavity_sample();
    file_->append_cavity(c.time, c.position, c.velocity, c.force, c.torque, c.contents_velocity);
    structure_row();
  }
  if (energy && (s % at_.n_energy == 0 || s == at_.total)) {
    const EnergySample e = sim_.energy();
    file_->append_energy(t, e.terms());
    check_energy(t, e);
  }
  if (s % at_.n_frame == 0 || s == at_.total) {
    check_bag(t);
    append_frame(*file_, frame_of(sim_, t));
    frame_times_.push_back(t);
  }
  if (at_.n_ckpt && s % at_.n_ckpt == 0 && s != at_.total) save();
}

// SIGINT/SIGTERM: the state after a whole step as a checkpoint, results.h5.part kept.
void RunLoop::interrupted(int sig) {
  save();
  file_->set_attribute("status", "interrupted");
  file_->close();
  rep_.signal = sig;
  std::ostringstream m;
  m << signal_name(sig) << " at t = " << sim_.time() << " s (step " << sim_.steps_done() << " of " << at_.total
    << "): " << part().string() << " and " << ckpt().string() << " kept; continue with --resume";
  rep_.message = m.str();
}

void RunLoop::finish(double wall, std::uint64_t first_step, std::size_t particles) {
  // Headline numbers.
  const EnergySample e = sim_.energy();
  rep_.complete = true;
  rep_.wall_seconds = wall;
  const double psteps = static_cast<double>(particles) * static_cast<double>(at_.total - first_step);
  rep_.ns_per_particle_step = psteps > 0 ? 1e9 * wall / psteps : 0;
  const double cycles = at_.f_drive > 0 && at_.total > at_.measure_step
                            ? static_cast<double>(at_.total - at_.measure_step) * scene_.dt * at_.f_drive : 0.0;
  if (scene_.models.energy) {
    rep_.energy_balance_error = balance_error(e, sim_.initial_stored_energy());
    if (cycles >= 1) {  // less than a cycle measured gives no per-cycle figure
      rep_.cycles = cycles;
      rep_.dissipated_per_cycle = (total_dissipation(e) - run_.dissipated_at_measure) / rep_.cycles;
    }
  }
  close_results("complete", true);
  fs::remove(ckpt());

  const double ds = static_cast<double>(at_.n_cavity) * scene_.dt;
  write_summary(out_ / "summary.json", run_summary(scene_, sim_, rep_, psteps, response_, response_acc_, ds, structure_));
  // Harmonic cavity motion: the effective parameters of the contents (reduced.csv).
  if (!scene_.primary && at_.f_drive > 0 && cycles >= 2) {  // with or without the energy tallies
    try {
      rep_.reduced = reduce_run(scene_, out_.string());
      const std::string why = drop_where_no_restitution(scene_, rep_.reduced, out_, opt_.quiet);
      if (!why.empty()) rep_.reduce_message = "no restitution: the drop test could not run: " + why;
      write_reduced_csv(out_ / "reduced.csv", rep_.reduced);
    } catch (const InputError& e) {
      rep_.reduce_message = e.what();
    }
  } else if (!scene_.primary && at_.f_drive > 0) {
    rep_.reduce_message = "the run measured " + short_text(cycles) + " cycles of the drive after settling, the motion's ramp and "
                          "output.skip_cycles, and the reduction needs at least 2: no reduced.csv. Give a longer simulation.duration";
  }
}


// Steps the run to its end, each damper's loop recording what is due (the same schedule for all);
// false when it stopped early (a signal, a failure, the testing aid), with the reports as they stand.
bool step_all(Stepped steps, std::vector<std::unique_ptr<RunLoop>>& loops, const RunOptions& opt, double& wall, std::uint64_t& first) {
  RunLoop& lead = *loops.front();
  const std::uint64_t total = lead.schedule().total;
  if (lead.schedule().settle_step == 0 && steps.done() == 0)
    for (auto& l : loops) l->settled_at_start();
  Progress progress(opt.quiet, steps.done());
  const auto t0 = std::chrono::steady_clock::now();
  first = steps.done();
  for (auto& l : loops) l->begin(first);
  try {
    while (steps.done() < total) {
      if (const int sig = pending_interrupt()) {
        for (auto& l : loops) l->interrupted(sig);
        return false;
      }
      if (opt.stop_after_steps >= 0 && steps.done() - first >= static_cast<std::uint64_t>(opt.stop_after_steps)) {
        for (auto& l : loops) l->killed();
        return false;
      }
      steps.advance(lead.next_event(steps.done()) - steps.done());
      for (auto& l : loops) l->record(steps.done());
      progress.update(steps.done(), total, steps.time());
    }
  } catch (const RunError& e) {
    for (auto& l : loops) l->failed(e);
    return false;
  }
  wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return true;
}

}  // namespace

RunReport run_scene(const Scene& scene, const RunOptions& opt) {
  const InterruptGuard interrupts;
  if (opt.threads > 0) omp_set_num_threads(opt.threads);
  refuse_other_outputs(opt.out_dir, OutputOwner::run);
  const OutputLock lock(opt.out_dir);  // creates the directory
  clear_other_dampers(opt.out_dir, scene, opt.resume);
  std::optional<Simulation> one;
  std::optional<Dampers> many;
  std::vector<std::unique_ptr<RunLoop>> loops;
  Stepped steps;
  if (scene.more_dampers.empty()) {
    one.emplace(scene);
    steps.one = &*one;
    loops.push_back(std::make_unique<RunLoop>(scene, opt, *one, fs::path(opt.out_dir), true));
  } else {
    many.emplace(scene);
    steps.many = &*many;
    loops.push_back(std::make_unique<RunLoop>(scene, opt, (*many)[0], fs::path(opt.out_dir), true, "damper " + many->name(0) + ": "));
    for (std::size_t k = 1; k < many->size(); ++k) {
      loops.push_back(std::make_unique<RunLoop>(*scene.more_dampers[k - 1].scene, opt, (*many)[k], damper_dir(opt.out_dir, many->name(k)),
                                                false, "damper " + many->name(k) + ": "));
    }
  }
  for (auto& l : loops) l->open();
  if (many) {
    // Each damper's checkpoint is its own file: a run stopped between two of them left them at
    // different steps, which cannot go on as one run.
    for (std::size_t k = 1; k < many->size(); ++k)
      if ((*many)[k].steps_done() != (*many)[0].steps_done())
        throw InputError((damper_dir(opt.out_dir, many->name(k)) / "checkpoint.bin").string(), "", "",
                         "damper " + many->name(k) + "'s checkpoint is of step " + std::to_string((*many)[k].steps_done()) + ", the case's own " +
                             "damper's of step " + std::to_string((*many)[0].steps_done()) + ": the run stopped while they were written; run again "
                             "without --resume");
    many->restored();
  }
  double wall = 0;
  std::uint64_t first = 0;
  std::size_t particles = scene.particles.size();
  for (const Damper& d : scene.more_dampers) particles += d.scene->particles.size();
  if (step_all(steps, loops, opt, wall, first))
    for (auto& l : loops) l->finish(wall, first, particles);
  RunReport report = loops.front()->report();
  for (std::size_t k = 1; k < loops.size(); ++k) {
    const RunReport& r = loops[k]->report();
    if (report.message.empty() && !r.message.empty()) report.message = "damper " + many->name(k) + ": " + r.message;
    report.dampers.push_back({many->name(k), damper_dir(opt.out_dir, many->name(k)).string()});
  }
  return report;
}

}  // namespace bagdem
