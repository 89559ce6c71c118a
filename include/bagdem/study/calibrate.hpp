// Calibration: `bagdem calibrate CASE --target mode=1,reduction_db=14.9 [--target ...]` finds the
// value of one case key (the force amplitude by default) at which the ensemble's peak reduction
// matches measured ones. `--targets FILE` reads them from a CSV (columns mode, reduction_db, and
// optionally one more named by a case key: each target's configuration, such as the mass ratio of
// each figure of a measured table); each configuration is run at every value tried.
//
// The search (calibrate_search.cpp) works on ensemble means, never on one start: a bed is chaotic,
// so each value of the key is run with N seeds and gives, per target, the mean reduction and its
// 95% half-width over the seeds (reduce/interval.hpp, independent_interval; with one seed, that
// run's own interval over its cycles, peaks.csv's reduction_dB_ci95). A value *matches* a
// target when |mean - target| <= max(ci95, tolerance) (the tolerance, 0.1 dB by default, stands in
// for the interval of a deterministic case whose seeds agree).
//   - The first round scans the bounds at `scan` values, equally spaced in log(value) when both
//     bounds are positive and at least 3 apart, else in the value.
//   - One target: every sign change of (mean - target) between neighbours of the scan is a root,
//     refined by regula falsi kept at least a fifth of the bracket from its ends, all brackets side
//     by side, until a value matches or the rounds are spent. The reduction need not rise steadily
//     with the key: each root bracketed inside the bounds is a solution, and a scan value that
//     matches is one (neighbouring scan values that all match are one, its half-width covering
//     them). Without either, the scan's closest value is the one solution, not matched,
//     and the note says whether it lies at a bound (widen them) or inside (the reduction turns:
//     this key cannot reach the target).
//   - Several targets (modes 1 and 3, say): one value for all, the least-squares minimum of
//     J(v) = sum_k (mean_k(v) - target_k)^2 (dB^2): the scan's smallest J, then the two values half
//     a spacing either side of the best, the spacing halved each round, until it is below the
//     value's own uncertainty or the rounds are spent. The residuals are reported per target.
//   - Uncertainty of a solution (95%), by inverse prediction to first order (e.g. Draper & Smith,
//     Applied Regression Analysis, 3rd ed., 1998, sec. 3.2): with the local slopes s_k = d mean_k /
//     d value (secant of the bracket, or the neighbours') and w_k = max(ci95_k, tolerance), the
//     lines through the estimates put the best value at v - sum_k s_k r_k / sum_k s_k^2 (r_k the
//     residuals) with a spread sqrt(sum_k s_k^2 w_k^2) / sum_k s_k^2 (for one target v - r/s and
//     w/|s|). The reported half-width, centred on the evaluated v, covers that interval: |sum_k s_k
//     r_k| / sum_k s_k^2 + the spread. Infinite where the reduction does not change with the key.
// Every reported value was run: a solution is an evaluated value, never an interpolation.
#pragma once
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace bagdem::study {

// An ensemble figure at one value of the key: the mean over the done seeds, its 95% half-width
// (NaN with fewer than 2 seeds) and the seeds behind it.
struct Estimate {
  double mean = NAN, ci95 = NAN;
  int n = 0;
  int at_band_edge = 0;  // of the n runs, those whose peak lay at the band's edge (a reduction that is only a bound)
};

struct SearchOptions {
  double lo = 0, hi = 0;      // bounds of the key, lo < hi (the unit of --bounds)
  bool log = false;           // the search coordinate is log(value) (set by search_in_log)
  int scan = 5;               // values of the first round, the bounds included (at least 3)
  int rounds = 6;             // refinement rounds after the scan, at most
  double tolerance = 0.1;     // dB: a match needs |mean - target| <= max(ci95, tolerance)
};

// How far an estimate's mean may lie from its target and still match: max(ci95, tolerance), the
// tolerance alone when there is no interval.
double allowance(const Estimate& e, double tolerance);

// True when lo and hi are both positive and at least 3 apart: the scan is then log-spaced.
bool search_in_log(double lo, double hi);

// What the search asks for: a batch of values of the key, run side by side, and per value the
// estimate of each target (in the targets' order).
using Evaluate = std::function<std::vector<std::vector<Estimate>>(const std::vector<double>& values)>;

struct Evaluation {
  double value = NAN;
  int round = 0;              // 0: the scan
  std::vector<Estimate> at;   // per target
};

struct Solution {
  double value = NAN;              // an evaluated value of the key
  double half_width = NAN;         // its 95% uncertainty (infinite where the slope is 0)
  double spread = NAN;             // the part of it from the estimates' intervals alone
  bool matched = false;            // every target matched at `value`
  std::vector<Estimate> at;        // per target, at `value`
  std::vector<double> residual;    // mean - target per target (dB)
  std::vector<double> slope;       // d mean / d value per target (dB per unit of the key)
};

struct SearchResult {
  std::vector<Evaluation> evaluated;  // in the order run
  std::vector<Solution> solutions;    // ascending in value
  std::string note;                   // what else the search saw (no root in the bounds, values the intervals cannot tell apart, another minimum)
};

// The search above, over `targets` (dB, one per estimate of an evaluation). Throws
// std::invalid_argument for bad options (lo >= hi, scan < 3, no target).
SearchResult calibrate_search(const std::vector<double>& targets, const SearchOptions& opt, const Evaluate& evaluate);

// ---- calibrate.cpp: the command ------------------------------------------------------------------

struct CalibrateArgs {
  std::string dir;                        // CASE_DIR
  std::vector<std::string> targets;       // "mode=1,reduction_db=14.9"
  std::string targets_file;               // --targets: a CSV of them (mode, reduction_db[, a case key])
  std::vector<std::string> keys;          // --key: the keys fitted (empty: excitation.amplitude); several with maps only
  std::vector<std::string> bounds;        // --bounds per key, in order: "lo,hi" as --set reads values; none: the case's value / 4 and x 4
  std::vector<std::string> maps;          // --maps: fit on these effective-field maps (calibrate_maps.cpp), one per configuration
  int points = 400;                       // with maps: frequencies per mode's band of each prediction (as predict's --points)
  std::vector<std::string> sets;
  int seeds = 3, scan = 5, rounds = 6;
  double tolerance = 0.1;
  int jobs = 0, threads = 0, cores = 0;
  std::string out;                        // default CASE_DIR/calibrate
  std::string executable = "/proc/self/exe";
};

// Runs the calibration: each round a study in OUT/round-RR (point-NNN per value and seed,
// resumable: the same command goes on where it stopped), then OUT/calibrate.csv (every value run,
// per target), OUT/calibration.json (the solutions) and the summary on stdout. Exit codes: 0 a
// value matches, 2 bad input (nothing run), 3 a run failed or no value matched (the note says why).
int calibrate_command(const CalibrateArgs& args);

// ---- calibrate_maps.cpp: with --maps -------------------------------------------------------------
// The keys (several; KEY@M for mode M's element of an array key) fitted to the targets by weighted
// least squares through the prediction from effective-field maps, one per configuration (matched by
// its damper.toml), not coupled DEM: OUT/calibrate.csv (per target: the prediction at the fit, its
// range, the residual) and OUT/calibration.json (the keys with their 95% intervals, the MAE per
// mode). Exit codes: 0 fitted, 2 bad input (a configuration without its map, a key of the damper, a
// response outside a map at every value). The method is in calibrate_maps.cpp's header.
int calibrate_on_maps(const CalibrateArgs& args);

}  // namespace bagdem::study
