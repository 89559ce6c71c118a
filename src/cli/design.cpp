// `bagdem design`: the bag searched through maps and predictions (command.hpp).
#include "bagdem/study/design.hpp"
#include "command.hpp"

namespace bagdem::cli {

CLI::App* add_design(CLI::App& app, Args& args) {
  auto& a = args.design;
  auto* c = app.add_subcommand(
      "design",
      "Search the bag (ball size, fill, bag size: any keys, --vary) and its position for the largest peak reduction of the "
      "chosen modes under a mass budget: each candidate characterized once by DEM (bagdem characterize; maps already built "
      "are reused), every candidate at every position predicted by harmonic balance (bagdem predict) and ranked by its worst "
      "mode, the best run coupled with several starts. Writes OUT/design.csv (ranked, the Pareto front of reduction against "
      "added mass marked, the coupled check beside), OUT/chosen (a ready case directory) and tools/plot draws design.png. "
      "Resumable; under mpirun the ranks share each map's runs and the check's. See docs/bag-design.md.");
  c->add_option("dir", a.dir, "CASE_DIR (holds case.toml; a coupled stepped-sine sweep) or STUDY_DIR (holds study.toml: its [vary] "
                              "are the candidates, its set every run's)")
      ->required();
  c->add_option("--vary", a.vary,
                "A key of the bag and its candidate values, as bagdem sweep's (repeatable; the candidates are the grid). Default: "
                "bag.balls.diameter at the case's x 1, 1.5, 2 and bag.balls.mass_ratio at 0.3, 0.6 and 0.95 of the budget (the film takes the rest)")
      ->allow_extra_args(false);
  c->add_option("--set", a.sets, "Override a key of case.toml in every run (repeatable)")->allow_extra_args(false);
  c->add_option("--budget", a.budget, "The added mass (balls and film) over the structure's mass, at most (default 0.1)")
      ->check(finite_range(1e-6, 10.0));
  c->add_option("--positions", a.positions, "x/L of the bag on a beam (default 0.05,0.1,...,0.95)")->delimiter(',');
  c->add_option("--modes", a.modes, "The modes whose worst peak reduction is maximized (default: the case's evaluated modes)")->delimiter(',');
  c->add_option("--gamma", a.map.gamma, "The maps' Gamma range lo,hi (default 0.02,20)")->delimiter(',')->expected(2);
  c->add_option("--amplitudes", a.map.amplitudes, "The maps' amplitudes (default 6)");
  c->add_option("--frequencies", a.map.frequencies, "The maps' frequencies per mode's band (default 4)");
  c->add_option("--seeds", a.map.seeds, "The maps' starts per cell (default 3)")->check(CLI::Range(1, 100000));
  c->add_option("--cycles", a.map.cycles, "The maps' runs: cycles reduced, at least (default 20)")->check(CLI::Range(4, 100000));
  c->add_option("--skip", a.map.skip, "The maps' runs: start-up cycles left out, at least (default 5)")->check(CLI::Range(0, 100000));
  c->add_option("--window-time", a.map.window_time, "The maps' runs: seconds reduced, at least (default 0.25)")->check(finite_range(0.0, 1e4));
  c->add_option("--skip-time", a.map.skip_time, "The maps' runs: seconds of start-up left out, at least (default 0.1)")->check(finite_range(0.0, 1e4));
  c->add_option("--dampers", a.dampers,
                "1: place one bag; 2: also a pair of bags at two places of a beam, their added masses together within --budget, "
                "the worst chosen mode maximized (OUT/design-pairs.csv, OUT/chosen-pair; --verify checks the best pairs too)")
      ->check(CLI::Range(1, 2));
  c->add_option("--verify", a.verify, "Candidates run coupled, each at its best position, best first (default 3; 0: none)")->check(CLI::Range(0, 1000));
  c->add_option("--verify-seeds", a.verify_seeds, "Starts of each coupled check (default 3)")->check(CLI::Range(1, 1000));
  add_budget_options(c, a.jobs, a.threads, a.cores, "design", "this machine's");
  c->add_option("--out", a.out, "Output directory (default CASE_DIR/design)");
  c->add_flag("--check", a.check, "List the candidates, their added mass and whether their map is built, then exit; runs nothing");
  return c;
}

int run_design(Args& a) {
  return study::holding_interrupts("bagdem design", [&] { return study::design_command(a.design); });
}

}  // namespace bagdem::cli
