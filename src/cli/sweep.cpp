// `bagdem sweep`: a parameter study (command.hpp).
#include "bagdem/study/study.hpp"
#include "command.hpp"

namespace bagdem::cli {

CLI::App* add_sweep(CLI::App& app, Args& args) {
  auto& a = args.sweep;
  auto* s = app.add_subcommand(
      "sweep",
      "Parameter study: run a case at every point of a grid (or zip) of values of its keys, J runs at once, each in "
      "OUT/point-NNN/ (default CASE_DIR/study, or STUDY_DIR/out for a study.toml); merges the points' tables "
      "(sweep.csv, ...) into OUT/<table>.csv and OUT/study.h5. Resumable: done points are skipped. Under mpirun the "
      "ranks share the points. Exit codes: 0 all points done, 2 bad input (nothing run), 3 a point failed. "
      "See docs/studies.md.");
  s->add_option("dir", a.dir, "CASE_DIR (holds case.toml) or STUDY_DIR (holds study.toml)")->required();
  s->add_option("--vary", a.vary,
                "A key of case.toml and its values, comma-separated TOML values: --vary primary.damping_ratio=0.02,0.05 "
                "--vary 'bag.balls.diameter=\"4 mm\",\"8 mm\"' (repeatable; the grid of all keys)")
      ->allow_extra_args(false);  // one value per --vary: the directory may follow
  s->add_flag("--zip", a.zip, "Take the --vary lists together (equal lengths) instead of their grid");
  s->add_option("--set", a.sets, "Override a key of case.toml in every point: --set simulation.duration=\"0.2 s\" (repeatable)")
      ->allow_extra_args(false);
  s->add_option("--seeds", a.seeds, "Ensemble: run each point with simulation.seed = 1..N; adds <table>_ensemble.csv")
      ->check(CLI::Range(1, 100000));
  add_budget_options(s, a.jobs, a.threads, a.cores, "sweep", "this machine's, divided among the MPI ranks on it");
  s->add_option("--out", a.out, "Output directory (default CASE_DIR/study, or STUDY_DIR/out)");
  s->add_option("--fidelity", a.fidelity, "A preset of the speed/accuracy trade for every point: fast, balanced or reference (bagdem trade)")
      ->check(CLI::IsMember({"fast", "balanced", "reference"}));
  s->add_flag("--check", a.check,
              "Plan the study and load every point's case (as the sweep does before it runs), print the points and "
              "whether each is done, then exit: 0 if every point loads, 2 if not. Writes nothing");
  return s;
}

int run_sweep_command(Args& a) {
  return study::holding_interrupts("bagdem sweep", [&] { return study::sweep_command(a.sweep); });
}

}  // namespace bagdem::cli
