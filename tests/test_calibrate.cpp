// Calibration (`bagdem calibrate`, study/calibrate.hpp):
//  - the search on known functions: every root of a non-monotone reduction bracketed in the bounds
//    (10 + 5 sin v against 12 dB: the four roots asin(0.4) + k pi, each within 0.1 dB / |slope| of
//    the value found, the tolerance's own resolution); the stop when the seeds' interval holds the
//    target; no root in the bounds said so, with no solution; two targets fitted by least squares
//    (two lines in log v: the analytic minimum within the reported half-width, the residuals as
//    computed there), and a value run that matches both preferred to an unmatched least-squares one;
//  - the half-width's coverage with noisy ensembles: 5 seeds of normal noise (sd 1 dB) on a
//    reduction falling as 4 ln(1/v); over 400 calibrations the true root lies inside the reported
//    95% interval in at least 90% of them;
//  - through the binary, on an impact damper's SDOF sweep (one ball, deterministic; one seed, so
//    each value's interval is its run's own): the reduction run at 0.06 N is found again from the
//    bounds 0.03 to 0.2 N, between 0.045 and 0.07 N where the reduction falls through it; the scan
//    log-spaced, calibrate.csv's residuals the means minus the target, the matched row within its
//    interval (or 0.1 dB); the same command again runs nothing and writes the same answer. Bad
//    targets, bounds, modes and keys exit 2 with nothing written.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "bagdem/study/calibrate.hpp"
#include "bagdem/study/study.hpp"
#include "support.hpp"
#include "stepped_sine_support.hpp"

using namespace bagdem;
using namespace bagdem::study;
namespace fs = std::filesystem;

namespace {

// An evaluator from a function of the value, with a fixed interval; counts the values run.
Evaluate exact(double (*f)(double), double ci95, std::size_t* runs = nullptr, std::size_t* batches = nullptr) {
  return [=](const std::vector<double>& values) {
    if (batches) ++*batches;
    std::vector<std::vector<Estimate>> out;
    for (double v : values) {
      if (runs) ++*runs;
      out.push_back({Estimate{f(v), ci95, 5}});
    }
    return out;
  };
}

double wavy(double v) { return 10 + 5 * std::sin(v); }

// Two targets' reductions, lines in u = ln v: 20 - 5 u and 17 - 4 u, known to ci1 and ci2 dB.
Evaluate two_lines(double ci1, double ci2) {
  return [=](const std::vector<double>& values) {
    std::vector<std::vector<Estimate>> out;
    for (double v : values) out.push_back({Estimate{20 - 5 * std::log(v), ci1, 5}, Estimate{17 - 4 * std::log(v), ci2, 5}});
    return out;
  };
}

}  // namespace

TEST(CalibrateSearch, FindsEveryRootOfANonMonotoneReduction) {
  SearchOptions o;
  o.lo = 0, o.hi = 10, o.scan = 6, o.rounds = 12, o.tolerance = 0.1;
  ASSERT_FALSE(search_in_log(o.lo, o.hi));
  std::size_t batches = 0;
  const SearchResult r = calibrate_search({12.0}, o, exact(wavy, 0.0, nullptr, &batches));
  const double a = std::asin(0.4), pi = std::numbers::pi;
  const std::vector<double> roots = {a, pi - a, 2 * pi + a, 3 * pi - a};
  ASSERT_EQ(r.solutions.size(), roots.size()) << r.note;
  for (std::size_t i = 0; i < roots.size(); ++i) {
    const Solution& s = r.solutions[i];
    const double slope = 5 * std::cos(roots[i]);
    EXPECT_TRUE(s.matched);
    EXPECT_LE(std::abs(s.residual[0]), 0.1);
    EXPECT_NEAR(s.value, roots[i], 0.1 / std::abs(slope) * 1.05) << "root " << i;
    // The half-width: the tolerance through the slope, plus the distance to the line's root.
    EXPECT_NEAR(s.spread, 0.1 / std::abs(slope), 0.25 * 0.1 / std::abs(slope)) << "root " << i;
    EXPECT_GE(s.half_width, std::abs(s.value - roots[i])) << "root " << i;
  }
  // The brackets are refined side by side: one batch per round.
  EXPECT_LE(batches, 1u + static_cast<std::size_t>(o.rounds));
}

TEST(CalibrateSearch, StopsWhenTheTargetIsInsideTheInterval) {
  SearchOptions o;
  o.lo = 0.1, o.hi = 10, o.scan = 5, o.rounds = 10;
  ASSERT_TRUE(search_in_log(o.lo, o.hi));
  o.log = true;
  std::size_t loose = 0, tight = 0;
  auto falling = [](double v) { return 12 - 4 * std::log(v) - 0.5 * std::log(v) * std::log(v); };  // curved in ln v
  calibrate_search({13.3}, o, exact(+falling, 1.0, &loose));
  const SearchResult r = calibrate_search({13.3}, o, exact(+falling, 0.0, &tight));
  EXPECT_LT(loose, tight) << "a wider interval matches sooner";
  ASSERT_EQ(r.solutions.size(), 1u);
  // Within the tolerance / slope in ln v of the root u* = -4 + sqrt(13.4) (slope 4 + u* there).
  const double u_star = -4 + std::sqrt(13.4);
  EXPECT_NEAR(std::log(r.solutions[0].value), u_star, 0.1 / (4 + u_star) * 1.05);
  // The scan is log-spaced from bound to bound.
  EXPECT_DOUBLE_EQ(r.evaluated[0].value, 0.1);
  EXPECT_NEAR(r.evaluated[1].value, std::sqrt(0.1), 1e-12);
  EXPECT_DOUBLE_EQ(r.evaluated[4].value, 10);
}

TEST(CalibrateSearch, SaysSoWhenNoValueReachesTheTarget) {
  SearchOptions o;
  o.lo = 1, o.hi = 2;
  const SearchResult r = calibrate_search({30.0}, o, exact(wavy, 0.2));
  ASSERT_EQ(r.solutions.size(), 1u) << "the closest value, not matched";
  EXPECT_FALSE(r.solutions[0].matched);
  EXPECT_NEAR(r.solutions[0].value, 1.5, 1e-12) << "10 + 5 sin v is largest at pi/2 on [1, 2]: the scan's 1.5";
  EXPECT_NE(r.note.find("no value between 1 and 2 reaches the target"), std::string::npos) << r.note;
  EXPECT_NE(r.note.find("inside the bounds: a wider range will not reach it"), std::string::npos) << r.note;
  EXPECT_EQ(r.evaluated.size(), 5u) << "the scan only";
  // A target beyond the bound the reduction is heading to: widen the bounds.
  o.lo = 2, o.hi = 3;
  const SearchResult w = calibrate_search({30.0}, o, exact(wavy, 0.2));
  EXPECT_NE(w.note.find("nearest at the bound 2: widen --bounds"), std::string::npos) << w.note;
  EXPECT_THROW(calibrate_search({}, o, exact(wavy, 0.2)), std::invalid_argument);
  o.hi = 1;
  EXPECT_THROW(calibrate_search({1.0}, o, exact(wavy, 0.2)), std::invalid_argument);
}

TEST(CalibrateSearch, NeighboursThatAllMatchAreOneSolutionCoveringThemAll) {
  // 12 - 0.5 v against 10 dB with intervals of 3 dB: every scan value of [0, 10] matches. One
  // solution, the scan's nearest (5: -0.5 dB), its half-width covering the whole range.
  SearchOptions o;
  o.lo = 0, o.hi = 10;
  auto gentle = [](double v) { return 12 - 0.5 * v; };
  const SearchResult r = calibrate_search({10.0}, o, exact(+gentle, 3.0));
  ASSERT_EQ(r.solutions.size(), 1u) << r.note;
  EXPECT_DOUBLE_EQ(r.solutions[0].value, 5.0);
  EXPECT_TRUE(r.solutions[0].matched);
  EXPECT_GE(r.solutions[0].half_width, 5.0);
  EXPECT_NE(r.note.find("more --seeds narrow them"), std::string::npos) << r.note;
}

TEST(CalibrateSearch, TwoTargetsFitOneValueByLeastSquares) {
  // r1 = 20 - 5 u - 14.9 and r2 = 17 - 4 u - 14.5 (u = ln v) are least squares at
  // u* = (5 * 5.1 + 4 * 2.5) / 41.
  SearchOptions o;
  o.lo = 0.1, o.hi = 10, o.log = true, o.scan = 5, o.rounds = 12;
  const SearchResult r = calibrate_search({14.9, 14.5}, o, two_lines(0.05, 0.05));
  ASSERT_EQ(r.solutions.size(), 1u);
  const Solution& s = r.solutions[0];
  const double u_star = (5 * 5.1 + 4 * 2.5) / 41, v_star = std::exp(u_star);
  EXPECT_LE(std::abs(s.value - v_star), s.half_width) << s.value << " against " << v_star;
  EXPECT_LT(s.half_width, 0.05 * v_star);
  const double u = std::log(s.value);
  EXPECT_NEAR(s.residual[0], 5.1 - 5 * u, 1e-12);
  EXPECT_NEAR(s.residual[1], 2.5 - 4 * u, 1e-12);
  EXPECT_FALSE(s.matched) << "the two lines cannot both pass through their targets";
}

TEST(CalibrateSearch, AMatchedValueIsPreferredToAnUnmatchedLeastSquaresOne) {
  // The same two lines, the first known to 0.3 dB and the second to 2 dB: both match for u in
  // [0.96, 1.08], the least-squares u* = 0.866 does not (r1 = 0.77). The scan (u = -1 ... 3) runs
  // u = 1 (r1 = 0.1, r2 = -1.5), which is given instead, with a note.
  SearchOptions o;
  o.lo = std::exp(-1.0), o.hi = std::exp(3.0), o.log = true, o.scan = 5, o.rounds = 12;
  const SearchResult r = calibrate_search({14.9, 14.5}, o, two_lines(0.3, 2.0));
  ASSERT_EQ(r.solutions.size(), 1u);
  const Solution& s = r.solutions[0];
  EXPECT_TRUE(s.matched);
  EXPECT_NEAR(std::log(s.value), 1.0, 1e-12);
  EXPECT_NE(r.note.find("matches every target"), std::string::npos) << r.note;
}

TEST(CalibrateSearch, HalfWidthCoversTheRootOfNoisyEnsembles) {
  // 5 seeds of N(0, 1 dB) around 12 - 4 ln v; the target 14 dB has its root at v = exp(-0.5).
  std::mt19937_64 rng(2026);
  std::normal_distribution<double> noise(0.0, 1.0);
  SearchOptions o;
  o.lo = 0.1, o.hi = 10, o.log = true, o.scan = 5, o.rounds = 6;
  const Evaluate ev = [&](const std::vector<double>& values) {
    std::vector<std::vector<Estimate>> out;
    for (double v : values) {
      std::vector<double> x;
      for (int s = 0; s < 5; ++s) x.push_back(12 - 4 * std::log(v) + noise(rng));
      double m = 0, ss = 0;
      for (double y : x) m += y / 5;
      for (double y : x) ss += (y - m) * (y - m);
      out.push_back({Estimate{m, 2.776 * std::sqrt(ss / 4 / 5), 5}});
    }
    return out;
  };
  const double root = std::exp(-0.5);
  int covered = 0, trials = 400;
  for (int t = 0; t < trials; ++t) {
    const SearchResult r = calibrate_search({14.0}, o, ev);
    if (r.solutions.empty()) continue;
    const Solution& s = r.solutions[0];
    covered += std::abs(s.value - root) <= s.half_width ? 1 : 0;
  }
  std::printf("  the root inside the reported interval in %d of %d calibrations\n", covered, trials);
  EXPECT_GE(covered, 0.9 * trials);
}

namespace {

double peak_reduction(const fs::path& out) {
  const Table p = read_csv((out / "peaks.csv").string());
  for (std::size_t c = 0; c < p.columns.size(); ++c)
    if (p.columns[c] == "reduction_dB [dB]" && !p.rows.empty()) return std::stod(p.rows[0][c]);
  return NAN;
}

std::size_t column(const Table& t, const std::string& name) {
  for (std::size_t c = 0; c < t.columns.size(); ++c)
    if (t.columns[c] == name) return c;
  ADD_FAILURE() << "no column " << name;
  return 0;
}

}  // namespace

TEST(Calibrate, FindsTheForceOfAKnownReductionThroughTheBinary) {
  bagdem::testing::TempDir t;
  const fs::path dir = t.path / "case";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << bagdem::testing::impact_damper_sdof();
  // The reduction at the force to be found.
  const bagdem::testing::CmdResult ref =
      bagdem::testing::run_bagdem({"run", dir.string(), "--out", (t.path / "ref").string(), "--quiet", "--set", "excitation.amplitude=\"0.06 N\""}, t.path);
  ASSERT_EQ(ref.code, 0) << ref.err;
  const double target = peak_reduction(t.path / "ref");
  ASSERT_TRUE(std::isfinite(target) && target > 1) << "the ball must damp the peak";
  const fs::path out = t.path / "cal";
  char tgt[64];
  std::snprintf(tgt, sizeof tgt, "mode=1,reduction_db=%.12g", target);
  const bagdem::testing::CmdResult r = bagdem::testing::run_bagdem(
      {"calibrate", dir.string(), "--target", tgt, "--bounds", "\"0.03 N\",\"0.2 N\"", "--seeds", "1", "--out", out.string(), "--jobs", "2"}, t.path);
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("calibrated excitation.amplitude = "), std::string::npos) << r.out;
  // calibrate.csv: the scan log-spaced from bound to bound, residual = mean - target.
  const Table c = read_csv((out / "calibrate.csv").string());
  const std::size_t c_round = column(c, "round [1]"), c_v = column(c, "excitation.amplitude [kg m/s^2]"), c_m = column(c, "reduction_db_mean [dB]"),
                    c_r = column(c, "residual_db [dB]"), c_t = column(c, "target_db [dB]");
  EXPECT_EQ(c.columns[column(c, "at_band_edge [1]")], "at_band_edge [1]");
  ASSERT_GE(c.rows.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(c.rows[i][c_round], "0");
    EXPECT_NEAR(std::stod(c.rows[i][c_v]), 0.03 * std::pow(0.2 / 0.03, i / 4.0), 1e-9) << "scan value " << i;
  }
  for (const auto& row : c.rows) {
    EXPECT_NEAR(std::stod(row[c_t]), target, 1e-9);
    EXPECT_NEAR(std::stod(row[c_r]), std::stod(row[c_m]) - target, 1e-9);
  }
  // One solution, matched, where the reduction falls steadily through the target (the 0.06 N run,
  // between 0.045 and 0.07 N); its reduction is that of its own run, within that run's interval.
  const std::string js = bagdem::testing::slurp(out / "calibration.json");
  ASSERT_EQ(js.find("{\"value\": "), js.rfind("{\"value\": ")) << "one solution: " << js;
  const std::size_t at = js.find("{\"value\": ");
  ASSERT_NE(at, std::string::npos) << js;
  const double v = std::stod(js.substr(at + 10));
  EXPECT_NE(js.find("\"matched\": true"), std::string::npos) << js;
  EXPECT_GT(v, 0.045) << js;
  EXPECT_LT(v, 0.07) << js;
  const double hw = std::stod(js.substr(js.find("\"half_width\": ", at) + 14));
  EXPECT_GT(hw, 0) << js;
  EXPECT_LT(hw, 0.01) << "a few per cent of the value: " << js;
  bool found_row = false;
  for (const auto& row : c.rows)
    if (std::abs(std::stod(row[c_v]) - v) <= 1e-12 * v) {
      found_row = true;
      const double ci = std::stod(row[column(c, "reduction_db_ci95 [dB]")]);
      EXPECT_LE(std::abs(std::stod(row[c_m]) - target), std::max(ci, 0.1) + 1e-12);
      EXPECT_EQ(row[column(c, "matched [1]")], "1");
    }
  EXPECT_TRUE(found_row);
  // Run again: every round is done already, so nothing runs and the answer is the same.
  const bagdem::testing::CmdResult again = bagdem::testing::run_bagdem(
      {"calibrate", dir.string(), "--target", tgt, "--bounds", "\"0.03 N\",\"0.2 N\"", "--seeds", "1", "--out", out.string(), "--jobs", "2"}, t.path);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_EQ(bagdem::testing::slurp(out / "calibration.json"), js);
  EXPECT_NE(again.err.find("resum"), std::string::npos) << again.err;
}

// Targets measured at several configurations (--targets FILE with a case key's column): the
// impact damper above at two damping ratios of its primary, each target the reduction of its own
// ratio at 0.06 N. Reference: one force fits both (the two reduction curves cross the targets at
// the same force), so the least-squares value lies where the single target's does (0.045-0.07 N,
// between the scan's neighbours of 0.06 N), every value tried ran both configurations, and each
// figure's residual is small (mean absolute residual per mode below 0.5 dB, reported in
// calibration.json as mae_dB).
TEST(Calibrate, FitsTargetsMeasuredAtSeveralConfigurations) {
  bagdem::testing::TempDir t;
  const fs::path dir = t.path / "case";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << bagdem::testing::impact_damper_sdof();
  std::ofstream targets(t.path / "targets.csv");
  targets << "mode,reduction_db,primary.damping_ratio\n";
  double db[2];
  for (int k = 0; k < 2; ++k) {
    const std::string zeta = k == 0 ? "0.02" : "0.03", ref = (t.path / ("ref" + zeta)).string();
    const bagdem::testing::CmdResult r = bagdem::testing::run_bagdem(
        {"run", dir.string(), "--out", ref, "--quiet", "--set", "excitation.amplitude=\"0.06 N\"", "--set", "primary.damping_ratio=" + zeta}, t.path);
    ASSERT_EQ(r.code, 0) << r.err;
    db[k] = peak_reduction(ref);
    char row[96];
    std::snprintf(row, sizeof row, "1,%.12g,%s\n", db[k], zeta.c_str());
    targets << row;
  }
  targets.close();
  ASSERT_GT(std::abs(db[0] - db[1]), 0.3) << "the two configurations must differ for the test to mean anything";
  const fs::path out = t.path / "cal";
  const bagdem::testing::CmdResult r = bagdem::testing::run_bagdem(
      {"calibrate", dir.string(), "--targets", (t.path / "targets.csv").string(), "--bounds", "\"0.03 N\",\"0.2 N\"", "--seeds", "1",
       "--out", out.string(), "--jobs", "2"}, t.path);
  std::printf("%s", r.out.c_str());
  ASSERT_TRUE(r.code == 0 || r.code == 3) << r.err << r.out;
  const Table c = read_csv((out / "calibrate.csv").string());
  const std::size_t c_round = column(c, "round [1]"), c_conf = column(c, "configuration"), c_t = column(c, "target_db [dB]");
  std::size_t scan_rows = 0, first = 0, second = 0;
  for (const auto& row : c.rows) {
    scan_rows += row[c_round] == "0";
    const bool a = row[c_conf] == "primary.damping_ratio=0.02", b = row[c_conf] == "primary.damping_ratio=0.03";
    first += a, second += b;
    EXPECT_TRUE(a || b) << row[c_conf];
    EXPECT_NEAR(std::stod(row[c_t]), a ? db[0] : db[1], 1e-9);
  }
  EXPECT_EQ(scan_rows, 10u) << "5 values, each at both configurations";
  EXPECT_EQ(first, second);
  const std::string js = bagdem::testing::slurp(out / "calibration.json");
  const std::size_t at = js.find("{\"value\": ");
  ASSERT_NE(at, std::string::npos) << js;
  const double v = std::stod(js.substr(at + 10));
  EXPECT_GT(v, 0.045) << js;
  EXPECT_LT(v, 0.07) << js;
  const std::size_t mae = js.find("\"mae_dB\": [{\"mode\": 1, \"figures\": 2, \"mae_dB\": ");
  ASSERT_NE(mae, std::string::npos) << js;
  EXPECT_LT(std::stod(js.substr(js.find("\"mae_dB\": ", mae + 12) + 10)), 0.5) << js;
  EXPECT_NE(js.find("\"configuration\": \"primary.damping_ratio=0.03\""), std::string::npos) << js;
}

TEST(Calibrate, RefusesBadTargetsBoundsAndModesBeforeRunning) {
  bagdem::testing::TempDir t;
  const fs::path dir = t.path / "case";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << bagdem::testing::impact_damper_sdof();
  const fs::path out = t.path / "cal";
  const std::vector<std::pair<std::vector<std::string>, std::string>> bad = {
      {{"--target", "mode=1"}, "both mode and reduction_db are needed"},
      {{"--target", "mode=1,reduction_db=abc"}, "is not a number"},
      {{"--target", "mode=2,reduction_db=10"}, "evaluates the peak of mode 1"},
      {{"--target", "mode=1,reduction_db=10", "--bounds", "\"2 N\",\"1 N\""}, "needs lo < hi"},
      {{"--target", "mode=1,reduction_db=10", "--bounds", "\"1 N\",\"2 m\""}, "must be in one unit"},
      {{"--target", "mode=1,reduction_db=10", "--key", "excitation.nonsense", "--bounds", "1,2"}, "excitation.nonsense"},
      {{"--bounds", "1,2"}, "either as --target"},
      {{"--target", "mode=1,reduction_db=10", "--targets", (t.path / "good.csv").string()}, "either as --target"},
      {{"--targets", (t.path / "absent.csv").string()}, "cannot be read"},
      {{"--targets", (t.path / "no-db.csv").string()}, "reduction_db"},
      {{"--targets", (t.path / "two-keys.csv").string()}, "is a second configuration column"},
      {{"--targets", (t.path / "two-figures.csv").string()}, "two-figures.csv: key 'reduction_db': is the header of two columns"},
      {{"--targets", (t.path / "bad-config.csv").string()}, "bad-config.csv: key 'row 2, primary.damping_ratio' = -0.01: is refused by the case"},
      {{"--targets", (t.path / "two-modes.csv").string()}, "two-modes.csv: key 'mode': is the header of two columns"},
      {{"--targets", (t.path / "repeat.csv").string()}, "repeats the target of mode 1 at primary.damping_ratio = 0.02"},
      {{"--targets", (t.path / "bad-mode.csv").string()}, "bad-mode.csv: key 'row 1, mode' = 1.5: must be a whole number"},
      {{"--targets", (t.path / "bad-db.csv").string()}, "bad-db.csv: key 'row 2, reduction_db' = high: is not a number"},
      {{"--targets", (t.path / "no-name.csv").string()}, "column 3"},
      {{"--targets", (t.path / "good.csv").string(), "--key", "primary.damping_ratio", "--bounds", "0.01,0.04"}, "is the key calibrated"},
      {{"--targets", (t.path / "bad-key.csv").string(), "--bounds", "\"0.03 N\",\"0.2 N\""}, "primary.nonsense"},
  };
  std::ofstream(t.path / "good.csv") << "mode,reduction_db,primary.damping_ratio\n1,5,0.02\n";
  std::ofstream(t.path / "no-db.csv") << "mode,reduction\n1,5\n";
  std::ofstream(t.path / "two-keys.csv") << "mode,reduction_db,primary.damping_ratio,primary.mass\n1,5,0.02,0.05\n";
  std::ofstream(t.path / "two-figures.csv") << "mode,reduction_db,reduction_db\n1,0.4,9\n";  // the last one used to win
  std::ofstream(t.path / "two-modes.csv") << "mode,reduction_db,mode\n1,0.4,3\n";
  std::ofstream(t.path / "bad-config.csv") << "mode,reduction_db,primary.damping_ratio\n1,5,0.02\n1,6,-0.01\n";  // named point-001's case.toml
  std::ofstream(t.path / "repeat.csv") << "mode,reduction_db,primary.damping_ratio\n1,5,0.02\n1,6,0.02\n";
  std::ofstream(t.path / "bad-mode.csv") << "mode,reduction_db\n1.5,5\n";
  std::ofstream(t.path / "bad-db.csv") << "\xEF\xBB\xBFmode, reduction_db\r\n1,5\r\n3,high\r\n";
  std::ofstream(t.path / "no-name.csv") << "mode,reduction_db,\n1,5,\n";
  std::ofstream(t.path / "bad-key.csv") << "mode,reduction_db,primary.nonsense\n1,5,0.02\n";
  for (const auto& [args, says] : bad) {
    std::vector<std::string> a = {"calibrate", dir.string(), "--out", out.string()};
    a.insert(a.end(), args.begin(), args.end());
    const bagdem::testing::CmdResult r = bagdem::testing::run_bagdem(a, t.path);
    EXPECT_EQ(r.code, 2) << args.back() << ": " << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << "nothing written for " << args.back();
  }
}
