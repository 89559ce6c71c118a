// bagdem: command line. Subcommands: check, run, sweep, trade, calibrate, characterize, predict, design, reduce, compare, peaks, drop, export,
// modes, bench.
// `bagdem <cmd> --help` explains each.
#include <CLI/CLI.hpp>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/output_lock.hpp"
#include "bagdem/reduce/compare.hpp"
#include "bagdem/run/drop_test.hpp"
#include "bagdem/reduce/export.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "bagdem/run/bench.hpp"
#include "bagdem/run/runner.hpp"
#include "bagdem/run/frequency_sweep.hpp"
#include "bagdem/structure/modal_table.hpp"
#include "bagdem/study/calibrate.hpp"
#include "bagdem/study/characterize.hpp"
#include "bagdem/study/design.hpp"
#include "bagdem/study/trade.hpp"
#include "bagdem/study/study.hpp"

using namespace bagdem;

namespace {

// More threads than cores are taken (the results are the same for any count), but they share the
// cores and the run is slower than with one per core: said on stderr.
void warn_threads_above_cores(const std::vector<int>& threads) {
  const int cores = omp_get_num_procs();
  for (int t : threads)
    if (t > cores)
      std::cerr << "warning: --threads " << t << " is more than the " << cores << " cores of this machine: the threads "
                << "share the cores and run slower than " << cores << " would; use --threads " << cores << " or fewer\n";
}

// What the subcommands read from the command line.
struct Args {
  std::string case_dir, out_dir;
  std::vector<std::string> sets;
  std::string fidelity;  // --fidelity: a preset's overrides, appended to sets (study/trade.hpp)
  int threads = 0;
  bool quiet = false, resume = false;
  int seeds = 1;
  std::string form = "consistent";
  double drop_speed = 0;
  std::vector<std::string> formats = {"csv", "json", "h5"};
  std::string export_to;
  BenchOptions bench;
  study::SweepArgs sweep;
  study::TradeArgs trade;
  study::CalibrateArgs calibrate;
  study::CharacterizeArgs characterize;
  study::PredictArgs predict;
  study::DesignArgs design;
  // The output directory: --out, or CASE_DIR/out.
  std::string out() const { return out_dir.empty() ? (std::filesystem::path(case_dir) / "out").string() : out_dir; }
};

void add_fidelity(CLI::App* sub, std::string& fidelity) {
  sub->add_option("--fidelity", fidelity,
                  "A preset of the speed/accuracy trade: fast, balanced (the case as written) or reference (see bagdem trade)")
      ->check(CLI::IsMember({"fast", "balanced", "reference"}));
}

CLI::App* add_check(CLI::App& app, Args& a) {
  CLI::App* check = app.add_subcommand("check", "Validate a case and print the resolved scene: what is modelled, N, dt and how it was chosen, steps, memory; for a bag its size, fill, film resolution and strings.");
  check->add_option("case_dir", a.case_dir, "Case directory (holds case.toml)")->required();
  check->add_option("--set", a.sets, "Override a key of case.toml: --set simulation.duration=\"0.5 s\" (repeatable)");
  add_fidelity(check, a.fidelity);
  return check;
}

CLI::App* add_run(CLI::App& app, Args& a) {
  CLI::App* run = app.add_subcommand("run", "Run a case: writes results.h5 (+ results.xmf for ParaView) and, when complete, summary.json. "
                                      "A case with a primary structure ([primary]: sdof, beam, fe-beam) driven by a stepped-sine "
                                      "[excitation] runs a frequency sweep instead: sweep.csv, the table /sweep in results.h5, and "
                                      "each mode's peak reduction (dB, %) against the bare structure in summary.json. A run that goes "
                                      "unstable leaves its record as results.failed.h5 and an earlier complete results.h5 as it was.");
  run->add_option("case_dir", a.case_dir, "Case directory (holds case.toml)")->required();
  run->add_option("--out", a.out_dir, "Output directory (default CASE_DIR/out)");
  run->add_option("--threads", a.threads, "OpenMP threads (default: all cores; results are identical for any count; the balls' stages use several threads from 2048 balls, below that one (the fork and join would cost more than they save), and each thread's share of the balls follows its measured speed; a stepped-sine sweep runs its chains, excitation.chains, side by side on them)")->check(CLI::Range(1, 1024));
  run->add_option("--set", a.sets, "Override a key of case.toml, dotted path: --set particles.balls.count=200 (repeatable)");
  add_fidelity(run, a.fidelity);
  run->add_flag("--quiet", a.quiet, "No progress line");
  run->add_flag("--resume", a.resume, "Continue an interrupted run from OUT/checkpoint.bin (left by output.checkpoint_interval > 0, and by SIGINT or SIGTERM, which stop a run with exit code 130 or 143); OUT/results.h5.part must hold the data the checkpoint recorded (verified), or the resume is refused");
  run->add_option("--seeds", a.seeds,
                  "An ensemble of N perturbed starts (simulation.seed = 1..N, each in OUT/point-NNN, resumable, as bagdem sweep runs "
                  "them; --threads is then per start): every table with its mean and 95% interval over the starts "
                  "(OUT/<table>_ensemble.csv), the peak reduction among them. A chaotic bed's figure from one start is not a measurement")
      ->check(CLI::Range(1, 100000));
  return run;
}

// A command that reads a finished run (a sweep when `run` says so) in OUT: the case, the output
// directory and the --set the run was made with.
CLI::App* add_run_reader(CLI::App& app, Args& a, const char* name, const std::string& help, const std::string& run) {
  CLI::App* c = app.add_subcommand(name, help);
  c->add_option("case_dir", a.case_dir, "Case directory (holds case.toml)")->required();
  c->add_option("--out", a.out_dir, "Output directory of the " + run + " (default CASE_DIR/out)");
  c->add_option("--set", a.sets, "The --set overrides the " + run + " was made with (repeatable)");
  add_fidelity(c, a.fidelity);
  return c;
}

CLI::App* add_reduce(CLI::App& app, Args& a) {
  return add_run_reader(app, a, "reduce", "Reduce a finished run to the bag's effective parameters (also done at the end of run): per driven frequency "
                                          "M_eff and C_eff by first-harmonic projection over whole steady cycles, energy per cycle, "
                                          "loss factor, M_eff/M_bag, C_b/(M_b w), Gamma, d/X, the impacts (phase, peak force, duration) and the "
                                          "restitution e (per impact between free flights, else Eq. 19a, else the drop test; e_method says which), "
                                          "each with its standard error and 95% interval over the correlated cycles, and steady = 0 for a window "
                                          "whose energy balance is off by more than 1%. Writes OUT/reduced.csv (columns: docs/outputs.md).",
                        "run");
}

CLI::App* add_compare(CLI::App& app, Args& a) {
  CLI::App* compare = add_run_reader(app, a, "compare", "For each frequency of a coupled sweep: the response amplitude the DEM produced against the "
                                                        "continuum model's prediction from the DEM-derived C_b, M_b and e (the modal model with the bag's "
                                                        "impedance, the study's SDOF Eq. 7 and Eq. 20), with the errors. Writes OUT/compare.csv (also done at "
                                                        "the end of a sweep).",
                                     "sweep");
  compare->add_option("--form", a.form, "Eq. (7)/(20) form: consistent (default) or printed (the study's as-printed equations)")
      ->check(CLI::IsMember({"consistent", "printed"}));
  return compare;
}

CLI::App* add_peaks(CLI::App& app, Args& a) {
  return add_run_reader(app, a, "peaks", "Recompute each mode's peak reduction of a finished sweep from its recorded points "
                                         "(OUT/sweep.csv) and the case's bare structure: rewrites OUT/peaks.csv and the peaks of "
                                         "OUT/summary.json, and prints them. For a sweep run with an older bagdem, whose peak "
                                         "refinement differed (docs/outputs.md); refuses a case whose bare peaks are not the run's.",
                        "sweep");
}

CLI::App* add_modes(CLI::App& app, Args& a) {
  CLI::App* modes = app.add_subcommand("modes", "Write the modal table of the case's primary structure, the input of primary.kind = \"modal\" "
                                          "(columns: docs/case-schema.md): per mode its natural frequency, damping ratio and modal mass, "
                                          "the shapes at the cavity's attachment, the force and the response points, the slope and the "
                                          "curvature at the attachment, and whether it is a rigid-body mode; mass-normalised, to every "
                                          "digit, without primary.cavity_mass. Read back, it gives the same structure.");
  modes->add_option("case_dir", a.case_dir, "Case directory (holds case.toml)")->required();
  modes->add_option("--to", a.export_to, "Where to write the table (default CASE_DIR/out/modes.csv)");
  modes->add_option("--set", a.sets, "Override a key of case.toml (repeatable)");
  return modes;
}

CLI::App* add_drop(CLI::App& app, Args& a) {
  CLI::App* drop = app.add_subcommand("drop", "Drop test of the case's bag: its contents, settled as in the case, are launched against a wall of the "
                                        "resting cavity along the excitation direction; prints e_drop = rebound / approach speed of their "
                                        "centre of mass (in [0, 1], or an error that says why) and writes OUT/drop.csv and OUT/drop_result.csv; "
                                        "`bagdem reduce` then reports it beside the other two estimates (a run does the same by itself when a "
                                        "row has neither of the others).");
  drop->add_option("case_dir", a.case_dir, "Case directory (holds case.toml)")->required();
  drop->add_option("--out", a.out_dir, "Output directory (default CASE_DIR/out)");
  drop->add_option("--set", a.sets, "Override a key of case.toml (repeatable)");
  add_fidelity(drop, a.fidelity);
  drop->add_option("--speed", a.drop_speed,
                   "Launch speed in m/s, > 0 (default: the case's expected impact speed; where the impact at that speed does not "
                   "stand out of the sliding friction, twice as fast, up to 16 times, said in the output)")
      ->check(CLI::Validator(
          [](std::string& v) {
            char* end = nullptr;
            const double x = std::strtod(v.c_str(), &end);
            return end != v.c_str() && *end == '\0' && x > 0 && std::isfinite(x) ? std::string()
                                                                                  : "'" + v + "' is not a launch speed: give a number > 0 (m/s)";
          },
          "SPEED > 0"));
  drop->add_option("--threads", a.threads, "OpenMP threads")->check(CLI::Range(1, 1024));
  return drop;
}

CLI::App* add_export(CLI::App& app, Args& a) {
  CLI::App* exporter = app.add_subcommand("export", "Export the reduced-parameter table of a run or a study (C_b, M_b, e, loss factor against "
                                               "frequency, amplitude and Gamma, with the swept design parameters) as CSV, JSON and HDF5 with "
                                               "units, for FE and continuum codes (columns: docs/outputs.md).");
  exporter->add_option("dir", a.out_dir, "A run's output directory or a study's (holds reduced.csv)")->required();
  exporter->add_option("--formats", a.formats, "Any of csv json h5 (default all)")->check(CLI::IsMember({"csv", "json", "h5"}));
  exporter->add_option("--to", a.export_to, "Path of the exported files without extension (default DIR/export)");
  return exporter;
}

CLI::App* add_bench(CLI::App& app, Args& a) {
  CLI::App* bench = app.add_subcommand("bench", "Benchmark: ns per particle-step on the PD-box vibrating bed (the scene of LIGGGHTS/LAMMPS peers), the candidate pairs per ball (and the share of them across the threads' ranges), the contacts per ball and the stages' shares of the step (clocked on the staged step: a run with its stages clocked runs them one after the other, not in the one parallel region of an untimed step).");
  bench->add_option("--sizes", a.bench.sizes, "Particle counts (default 100 1000 10000)");
  bench->add_option("--threads", a.bench.threads, "Thread counts (default 1 2)");
  bench->add_option("--methods", a.bench.methods, "Broad phases (default hash kdtree)");
  bench->add_option("--repeats", a.bench.repeats, "Runs per point; the median is reported (default 3)");
  bench->add_option("--steps", a.bench.step_scale, "Scale of the timed step counts (default 1)");
  bench->add_option("--energy", a.bench.energy, "Energy budget tallies on/off (default true; LIGGGHTS/LAMMPS compute none)");
  bench->add_flag("--bag", a.bench.bag, "The bagged scene (cases/box-beanbag) instead: cost per step, its split between balls and film, and the film's cost against its node count");
  bench->add_option("--film-triangles", a.bench.film_triangles, "Film resolutions of the bagged scene (default 200 800 3200)");
  bench->add_flag("--growth", a.bench.growth,
                  "Growth instead: the settled N = 1000 bed tiled k x k (N = 1000 k^2), 10000 steps each (x --steps); "
                  "cost per particle-step, one neighbour build of each broad phase and peak memory against N, and their fitted exponents; "
                  "the --repeats run in rounds over the sizes, so that the machine's drifting speed weighs on every size alike");
  bench->add_option("--tiles", a.bench.tiles, "Tiles k per side of the growth benchmark (default 1 2 4 7 10: N = 1e3 to 1e5)");
  bench->add_option("--peers", a.bench.peers_dir, "The peers' directory with runs/N*.vib1.data (default: ../shared/peers beside the source)");
  bench->add_option("--case", a.bench.case_dir, "Case of the benchmark (default cases/pdbox, or cases/box-beanbag with --bag)");
  bench->add_option("--format", a.bench.format,
                    "Output: table (default: a Markdown table with a title and notes) or csv (on stdout a header row of "
                    "`name [unit]` entries, e.g. `ns_per_particle_step [ns]`, then one row per measured configuration with the "
                    "table's figures at full precision; the title and notes on stderr)")
      ->check(CLI::IsMember({"table", "csv"}));
  return bench;
}

// A run that did not finish: its message and exit code (128 + the signal that stopped it, or the
// run error's); 0 for a finished run.
int unfinished(bool complete, int signal, const std::string& message) {
  if (signal) {
    std::cerr << "interrupted: " << message << "\n";
    return 128 + signal;
  }
  if (!complete) {
    std::cerr << "error: " << message << "\n";
    return kExitRunError;
  }
  return 0;
}

// `bagdem run` of a case with a stepped-sine excitation: the frequency sweep.
int sweep_case(const Args& a, const Scene& s, const RunOptions& o) {
  if (!a.quiet) std::cerr << "bagdem run " << a.case_dir << ": stepped-sine sweep, " << s.primary->sweep->frequencies.size()
                        << " frequencies, N = " << s.particles.size() << ", dt = " << s.dt << " s -> " << o.out_dir << "\n";
  const SweepReport r = run_sweep(s, o);
  if (const int code = unfinished(r.complete, r.signal, r.message)) return code;
  std::printf("sweep complete: %zu frequencies, %.1f s wall\n", r.points.size(), r.wall_seconds);
  for (const ModePeak& m : r.peaks) std::printf("%s\n", describe_peak(m).c_str());
  for (const std::string& why : missing_peaks(*s.primary, r.points)) std::printf("%s\n", why.c_str());
  std::printf("the bag's effective parameters per frequency (reduced.csv):\n%s", describe_reduced(r.reduced).c_str());
  std::printf("%s", describe_compare(r.compare, continuum::Form::consistent).c_str());
  return 0;
}

// `bagdem run` of any other case.
int run_case(const Args& a, const Scene& s, const RunOptions& o) {
  if (!a.quiet) std::cerr << "bagdem run " << a.case_dir << ": N = " << s.particles.size() << ", dt = " << s.dt
                        << " s, " << s.total_steps() << " steps -> " << o.out_dir << "\n";
  const RunReport r = run_scene(s, o);
  if (const int code = unfinished(r.complete, r.signal, r.message)) return code;
  if (!r.reduced.empty()) std::printf("the contents' effective parameters (reduced.csv):\n%s", describe_reduced(r.reduced).c_str());
  if (!r.reduce_message.empty())
    std::fprintf(stderr, "%s%s\n", r.reduced.empty() ? "reduction skipped: " : "note: ", r.reduce_message.c_str());
  if (s.models.energy)
    std::printf("run complete: %.2f s wall, %.1f ns per particle-step, energy balance error %.2e\n", r.wall_seconds,
                r.ns_per_particle_step, r.energy_balance_error);
  else
    std::printf("run complete: %.2f s wall, %.1f ns per particle-step (energy budget off: output.energy = false)\n",
                r.wall_seconds, r.ns_per_particle_step);
  if (r.cycles > 0)
    std::printf("energy dissipated per cycle: %.4e J (over %.1f measured cycles)\n", r.dissipated_per_cycle, r.cycles);
  if (r.structure) {
    std::printf("structure: RMS response %.4e m, RMS acceleration %.4e m/s^2 at response_at\n", r.response_rms,
                r.acceleration_rms);
    if (r.decay_time > 0)
      std::printf("decay: damping ratio %.4g, time to fall by 20 dB %.4g s\n", r.decay_zeta, r.decay_time);
    if (s.primary->random_hi > 0)
      std::printf("structure: RMS response in the force's band %.4e m (after %.4g s; the RMS above holds every frequency, a hung "
                  "structure's swing too)\n", r.band_response_rms, s.primary->random_skip);
  }
  return 0;
}

int run_command(const Args& a) {
  if (a.seeds > 1) {
    if (a.resume) throw InputError("--resume", "", "", "an ensemble resumes by itself: run the same command again (done starts are kept)");
    return study::run_ensemble(a.case_dir, a.sets, a.seeds, a.out_dir, a.threads);
  }
  const Scene s = load_case(a.case_dir, a.sets);
  for (const auto& w : s.warnings) std::cerr << "warning: " << w << "\n";
  RunOptions o;
  o.out_dir = a.out();
  o.threads = a.threads;
  o.quiet = a.quiet;
  o.resume = a.resume;
  return s.primary && s.primary->sweep ? sweep_case(a, s, o) : run_case(a, s, o);
}

int reduce_command(const Args& a) {
  const Scene s = load_case(a.case_dir, a.sets);
  std::vector<ReducedRow> rows = reduce_run(s, a.out());
  attach_drop_result(rows, a.out());
  std::printf("%s%s", describe_reduced(rows).c_str(), describe_restitution(rows).c_str());
  return 0;
}

int compare_command(const Args& a) {
  const Scene s = load_case(a.case_dir, a.sets);
  if (!s.primary || !s.primary->sweep)
    throw InputError(s.case_file, "excitation.kind", "", "compare needs a coupled stepped-sine sweep (a primary structure with excitation.kind = \"stepped-sine\")");
  const continuum::Form f = a.form == "printed" ? continuum::Form::printed : continuum::Form::consistent;
  const std::vector<CompareRow> rows = compare_with_continuum(*s.primary, s.primary->amplitude, reduce_run(s, a.out()), f);
  write_compare_csv(std::filesystem::path(a.out()) / "compare.csv", rows);
  std::printf("%s", describe_compare(rows, f).c_str());
  return 0;
}

int peaks_command(const Args& a) {
  const Scene s = load_case(a.case_dir, a.sets);
  if (!s.primary || !s.primary->sweep)
    throw InputError(s.case_file, "excitation.kind", "", "peaks needs a coupled stepped-sine sweep (a primary structure with excitation.kind = \"stepped-sine\")");
  const OutputLock lock(a.out());
  for (const ModePeak& m : recompute_sweep_peaks(*s.primary, a.out())) std::printf("%s\n", describe_peak(m).c_str());
  return 0;
}

int modes_command(const Args& a) {
  const Scene s = load_case(a.case_dir, a.sets);
  if (!s.primary) throw InputError(s.case_file, "primary.kind", "", "modes needs a primary structure (sdof, beam, fe-beam or modal)");
  const std::filesystem::path to = a.export_to.empty() ? std::filesystem::path(a.out()) / "modes.csv" : std::filesystem::path(a.export_to);
  if (to.has_parent_path()) std::filesystem::create_directories(to.parent_path());
  write_modal_table(to, *s.primary);
  std::printf("wrote %s: %zu modes of %s\n", to.string().c_str(), s.primary->size(), s.primary->description.c_str());
  return 0;
}

int drop_command(const Args& a) {
  if (a.threads > 0) omp_set_num_threads(a.threads);
  const Scene s = load_case(a.case_dir, a.sets);
  const OutputLock lock(a.out());
  const DropResult d = run_drop_test(s, a.drop_speed, a.out(), false);
  write_drop_result(std::filesystem::path(a.out()) / "drop_result.csv", d);
  std::printf("e_drop = %.4f (launched at %.4g m/s: approach %.4g m/s, rebound %.4g m/s, peak force %.4g N, contact %.4g ms)\n",
              d.restitution, d.speed, d.v_before, d.v_after, d.peak_force, 1e3 * d.duration);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bagdem " BAGDEM_VERSION
               ": discrete-element simulation of granular and bean-bag impact dampers.\n"
               "A case is a directory with case.toml (schema: docs/case-schema.md).\n"
               "Exit codes: 0 success, 1 system error (I/O, a full disk), 2 bad input (case or command line), 3 the run "
               "went unstable, 130/143 a run stopped by SIGINT/SIGTERM (checkpoint written: continue with --resume)."};
  app.require_subcommand(1);
  app.set_version_flag("--version", BAGDEM_VERSION);

  Args a;
  CLI::App* check = add_check(app, a);
  CLI::App* run = add_run(app, a);
  CLI::App* reduce = add_reduce(app, a);
  CLI::App* compare = add_compare(app, a);
  CLI::App* peaks = add_peaks(app, a);
  CLI::App* drop = add_drop(app, a);
  CLI::App* modes = add_modes(app, a);
  CLI::App* exporter = add_export(app, a);
  CLI::App* bench = add_bench(app, a);
  // sweep: parameter studies over a case (src/study; MPI starts there, and only there).
  CLI::App* sweep = study::add_sweep_command(app, a.sweep);
  // trade: the speed/accuracy trade of a case (src/study/trade.cpp).
  CLI::App* trade = study::add_trade_command(app, a.trade);
  // calibrate: a case key fitted to measured peak reductions (src/study/calibrate.cpp).
  CLI::App* calibrate = study::add_calibrate_command(app, a.calibrate);
  // characterize: the damper's effective-field map over amplitude x frequency (src/study/characterize.cpp).
  CLI::App* characterize = study::add_characterize_command(app, a.characterize);
  // predict: a structure's response with a map's damper, without DEM (src/study/predict_command.cpp).
  CLI::App* predict = study::add_predict_command(app, a.predict);
  // design: the bag searched through maps and predictions, the best checked by DEM (src/study/design.cpp).
  CLI::App* design = study::add_design_command(app, a.design);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // A first word that names no subcommand: said so, with the subcommands (CLI11 would say "A
    // subcommand is required").
    if (argc > 1 && argv[1][0] != '-') {
      std::string names;
      bool known = false;
      for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
        names += (names.empty() ? "" : ", ") + sub->get_name();
        known = known || sub->get_name() == argv[1];
      }
      if (!known) {
        std::cerr << "unknown subcommand '" << argv[1] << "': the subcommands are " << names << " (bagdem --help)\n";
        return kExitInputError;
      }
    }
    // CLI11 prints its message (or the help and version, which succeed); a command-line error is
    // bad input like any other: exit code 2, not CLI11's own codes.
    return app.exit(e) == 0 ? 0 : kExitInputError;
  }
  if ((run->parsed() || drop->parsed()) && a.threads > 0) warn_threads_above_cores({a.threads});
  if (bench->parsed()) warn_threads_above_cores(a.bench.threads);
  if (sweep->parsed()) return study::sweep_command(a.sweep);
  if (trade->parsed()) return study::trade_command(a.trade);
  if (calibrate->parsed()) return study::calibrate_command(a.calibrate);
  if (characterize->parsed()) return study::characterize_command(a.characterize);
  if (predict->parsed()) return study::predict_command(a.predict);
  if (design->parsed()) return study::design_command(a.design);
  try {
    if (!a.fidelity.empty()) {
      const auto more = study::fidelity_sets(a.case_dir, a.sets, a.fidelity);
      a.sets.insert(a.sets.end(), more.begin(), more.end());
    }
    if (check->parsed()) {
      const Scene s = load_case(a.case_dir, a.sets);
      std::cout << describe_scene(s);
      for (const auto& w : s.warnings) std::cout << "warning: " << w << "\n";
      return 0;
    }
    if (run->parsed()) return run_command(a);
    if (reduce->parsed()) return reduce_command(a);
    if (compare->parsed()) return compare_command(a);
    if (peaks->parsed()) return peaks_command(a);
    if (drop->parsed()) return drop_command(a);
    if (modes->parsed()) return modes_command(a);
    if (exporter->parsed()) {
      for (const std::string& p : export_reduced(a.out_dir, a.export_to, a.formats)) std::printf("wrote %s\n", p.c_str());
      return 0;
    }
    if (bench->parsed())
      return a.bench.growth ? run_growth_bench(a.bench) : a.bench.bag ? run_bag_bench(a.bench) : run_bench(a.bench);
  } catch (const InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitInputError;
  } catch (const RunError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitRunError;
  } catch (const std::exception& e) {  // I/O and other system failures
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
