// `bagdem characterize`: the effective-field map of a damper (command.hpp).
#include "bagdem/study/characterize.hpp"
#include "command.hpp"

namespace bagdem::cli {

CLI::App* add_characterize(CLI::App& app, Args& args) {
  auto& a = args.characterize;
  auto* c = app.add_subcommand(
      "characterize",
      "The effective field of a case's damper, once for all structures: its contents in the cavity under prescribed harmonic "
      "motion along the excitation direction (a coupled case drops its primary structure), over a grid of amplitude x "
      "frequency with several starts per cell, each run reduced; writes OUT/map.csv, map.json and map.h5 (M_eff, C_eff, "
      "C_b/(M_b w), the loss factor, e, each with its 95% interval over the starts), and OUT/damper.toml, the damper it "
      "characterised (predict and design refuse a case whose damper differs); tools/plot draws map.png. The runs "
      "are a study in OUT/point-NNN (resumable; J at once; MPI ranks share them, as bagdem sweep). Exit codes: 0 every "
      "run done, 2 bad input (nothing run), 3 a run failed. See docs/characterize.md.");
  c->add_option("dir", a.dir, "CASE_DIR (holds case.toml)")->required();
  c->add_option("--gamma", a.gamma, "lo,hi: the range of the acceleration ratio Gamma = X w^2 / g (default 0.5,20)")
      ->delimiter(',')
      ->expected(2);
  c->add_option("--amplitudes", a.amplitudes, "Amplitudes per frequency, log-spaced in Gamma (default 8)");
  c->add_option("--band", a.band, "lo,hi in Hz (default: each band of the case's stepped-sine sweep)")->delimiter(',')->expected(2);
  c->add_option("--frequencies", a.frequencies, "Frequencies per band, evenly spaced, the ends included (default 6)");
  c->add_option("--seeds", a.seeds, "Starts per cell (simulation.seed = 1..N; 1: once, with the case's own seed, no interval; default 5)")->check(CLI::Range(1, 100000));
  c->add_option("--cycles", a.cycles, "Cycles of each run that are reduced, at least (default 20)")->check(CLI::Range(4, 100000));
  c->add_option("--skip", a.skip, "Start-up cycles of each run left out before them, at least (default 5)")->check(CLI::Range(0, 100000));
  c->add_option("--window-time", a.window_time,
                "Seconds of each run that are reduced, at least (default 0.25): at a high frequency the cycles are more than --cycles")
      ->check(finite_range(0.0, 1e4));
  c->add_option("--skip-time", a.skip_time,
                "Seconds of start-up left out, at least (default 0.1): a bag settles into its motion in a time, not a number of cycles")
      ->check(finite_range(0.0, 1e4));
  c->add_option("--set", a.sets,
                "Override a key of case.toml in every run (repeatable; simulation.duration, output.skip_cycles and cavity.motion "
                "are the map's own and left out)")
      ->allow_extra_args(false);
  add_budget_options(c, a.jobs, a.threads, a.cores, "characterization", "this machine's, divided among the MPI ranks on it");
  c->add_option("--out", a.out, "Output directory (default CASE_DIR/map)");
  c->add_flag("--check", a.check, "Plan the grid and load every run's case, print the runs, then exit: 0 if every one loads, 2 if not");
  return c;
}

int run_characterize(Args& a) {
  return study::holding_interrupts("bagdem characterize", [&] { return study::characterize_command(a.characterize); });
}

}  // namespace bagdem::cli
