// `bagdem bench`: the PD-box benchmark, the bagged scene's or the growth with N (command.hpp).
#include "bagdem/run/bench.hpp"
#include "command.hpp"

namespace bagdem::cli {

CLI::App* add_bench(CLI::App& app, Args& a) {
  CLI::App* bench = app.add_subcommand("bench", "Benchmark: ns per particle-step on the PD-box vibrating bed (the scene of LIGGGHTS/LAMMPS peers), the candidate pairs per ball (and the share of them across the threads' ranges), the contacts per ball and the stages' shares of the step (clocked on the staged step: a run with its stages clocked runs them one after the other, not in the one parallel region of an untimed step).");
  bench->add_option("--sizes", a.bench.sizes, "Particle counts (default 100 1000 10000)");
  bench->add_option("--threads", a.bench.threads, "Thread counts (default 1 2)");
  bench->add_option("--methods", a.bench.methods, "Broad phases (default hash kdtree)");
  bench->add_option("--repeats", a.bench.repeats, "Runs per point; the median is reported (default 3)");
  bench->add_option("--steps", a.bench.step_scale, "Scale of the timed step counts (default 1)")->check(finite_range(1e-12, 1e6));
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

int run_bench_command(Args& a) {
  warn_threads_above_cores(a.bench.threads);
  return a.bench.growth ? run_growth_bench(a.bench) : a.bench.bag ? run_bag_bench(a.bench) : run_bench(a.bench);
}

}  // namespace bagdem::cli
