// `bagdem bench`: ns per particle-step on the peers' PD-box scene (steel balls of 4 mm in a closed box
// shaken at 1 mm, 30 Hz, dt = 2e-7 s), so the figures compare with LIGGGHTS and LAMMPS
// (docs/performance.md, Method).
// The start state is the peers' settled bed after one vibration period (runs/N*.vib1.data) when
// present; otherwise the bed is generated on a lattice and settled first (slower; said so).
#pragma once
#include <string>
#include <vector>

namespace bagdem {

struct BenchOptions {
  std::vector<int> sizes{100, 1000, 10000};
  std::vector<int> threads{1, 2};
  std::vector<std::string> methods{"hash", "kdtree"};
  int repeats = 3;
  bool energy = true;       // energy budget tallies on (as `run` by default); peers compute none
  double step_scale = 1.0;  // multiplies the default timed step counts (1e6, 3e5, 4e4 for 1e2, 1e3, 1e4)
  std::string peers_dir;    // default: <source>/../shared/peers
  std::string case_dir;     // default: <source>/cases/pdbox
  // "table": the Markdown table with its title and notes (the default); "csv": the same figures as
  // CSV on stdout (a header row of `name [unit]` entries, then one row per measured configuration),
  // the title and notes on stderr.
  std::string format = "table";
  // The bagged scene instead (cases/box-beanbag at each film resolution): time per step and how it
  // splits between the balls and the film.
  bool bag = false;
  std::vector<int> film_triangles{200, 800, 3200};
  // Growth instead: the peers' settled N = 1000 bed tiled k x k across the floor (N = 1000 k^2,
  // the box widened to match), the same number of steps at every N; wall time per step and peak
  // memory against N, and the fitted exponents (bench.cpp). `tiles` gives the k.
  bool growth = false;
  std::vector<int> tiles{1, 2, 4, 7, 10};
};

int run_bench(const BenchOptions& options);
int run_bag_bench(const BenchOptions& options);
int run_growth_bench(const BenchOptions& options);

// Least-squares slope of log y against log x (the exponent a of y ~ x^a).
double log_log_slope(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace bagdem
