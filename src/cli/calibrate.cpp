// `bagdem calibrate`: a case key fitted to measured peak reductions (command.hpp).
#include "bagdem/study/calibrate.hpp"
#include "command.hpp"

namespace bagdem::cli {

CLI::App* add_calibrate(CLI::App& app, Args& args) {
  auto& a = args.calibrate;
  CLI::App* c = app.add_subcommand(
      "calibrate",
      "Find the value of a case key (the force amplitude by default) at which the peak reduction of a coupled sweep "
      "matches measured ones: each value run with N seeds, a scan of the bounds, then every root of one target (or the "
      "least-squares value of several) refined until a value matches (|mean - target| within the seeds' 95% interval or "
      "the tolerance). Each round is a study in OUT/round-RR (resumable: the same command goes on where it stopped; "
      "runs side by side within the cores; under mpirun the ranks share each round). Writes OUT/calibrate.csv and OUT/calibration.json; tools/plot draws "
      "calibrate.png. Exit codes: 0 a value matches, 2 bad input (nothing run), 3 a run failed or no value matched. "
      "See docs/calibrate.md.");
  c->add_option("dir", a.dir, "CASE_DIR (holds case.toml; a coupled stepped-sine sweep)")->required();
  c->add_option("--target", a.targets, "mode=M,reduction_db=R: the measured peak reduction of elastic mode M (repeatable: several fit one value by least squares)")
      ->allow_extra_args(false);
  c->add_option("--targets", a.targets_file,
                "A CSV of measured peak reductions instead of --target: columns mode, reduction_db and optionally one case key "
                "(e.g. bag.balls.mass_ratio) whose value per row is that figure's configuration; every configuration is run at "
                "every value tried (docs/calibrate.md)");
  c->add_option("--key", a.keys,
                "The case key to calibrate (default excitation.amplitude; e.g. primary.damping_ratio). Repeatable with --maps: "
                "several keys fitted at once; KEY@M fits the element of elastic mode M of an array key (primary.damping_ratio@3)")
      ->allow_extra_args(false);
  c->add_option("--bounds", a.bounds,
                "lo,hi, read as --set reads values: --bounds '\"0.05 N\",\"2 N\"' (default: the case's value / 4 and x 4); with "
                "several --key, one --bounds per key in their order")
      ->allow_extra_args(false);
  CLI::Option* maps = c->add_option(
      "--maps", a.maps,
      "Effective-field maps (bagdem characterize's OUT), one per configuration of the targets, matched by their "
      "damper.toml: fit the keys through the prediction from the maps instead of coupled DEM, in minutes rather than "
      "core-days (check the answer with coupled DEM)");
  c->add_option("--points", a.points, "With --maps: frequencies per mode's band of each prediction (default 400, as bagdem predict)")
      ->check(CLI::Range(2, 1000000))
      ->needs(maps);
  c->add_option("--set", a.sets, "Override a key of case.toml in every run (repeatable)")->allow_extra_args(false);
  // Options of the coupled-DEM calibration only: a fit on maps runs no simulation, so they are refused with --maps
  // rather than ignored.
  std::vector<CLI::Option*> dem_only;
  dem_only.push_back(c->add_option("--seeds", a.seeds, "Starts per value (simulation.seed = 1..N; default 3)")->check(CLI::Range(1, 1000)));
  c->add_option("--scan", a.scan, "Values of the first round, the bounds included (default 5)")->check(CLI::Range(3, 1000));
  dem_only.push_back(c->add_option("--rounds", a.rounds, "Refinement rounds after the scan, at most (default 6)")->check(CLI::Range(0, 100)));
  c->add_option("--tolerance", a.tolerance, "dB: a value matches within max(the seeds' 95% half-width, this) (default 0.1)")
      ->check(finite_range(1e-12, 1e3));
  add_budget_options(c, a.jobs, a.threads, a.cores, "calibration", "this machine's");
  for (const char* name : {"--jobs", "--threads", "--cores"}) dem_only.push_back(c->get_option(name));
  for (CLI::Option* o : dem_only) o->excludes(maps);
  c->add_option("--out", a.out, "Output directory (default CASE_DIR/calibrate)");
  return c;
}

int run_calibrate(Args& a) {
  return study::holding_interrupts("bagdem calibrate", [&] { return study::calibrate_command(a.calibrate); });
}

}  // namespace bagdem::cli
