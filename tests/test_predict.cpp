// Prediction from an effective-field map (reduce/predict.hpp):
// 1. A constant map (fixed M_eff, C_eff) is a linear mass and dashpot: the single-harmonic balance
//    has one solution at every frequency and gives the linear FRF exactly, on an SDOF and on the
//    pipe's beam (four modes).
// 2. An amplitude-dependent map whose damping collapses above a threshold folds the response:
//    three solutions at the frequencies of the fold, each a fixed point of the balance.
// 3. A response outside the map is refused (below, above, or a frequency outside its band), and
//    map.csv is read back with its grid checked.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/reduce/predict.hpp"
#include "case_texts.hpp"
#include "support.hpp"

using namespace bagdem;

namespace {

// The SDOF of case_texts.hpp's ball_on_sdof_floor (1 kg, 20 Hz, damping ratio 0.02, along x).
Scene sdof_scene(const bagdem::testing::TempDir& t) {
  std::ofstream(t.path / "case.toml") << bagdem::testing::ball_on_sdof_floor();
  return load_case(t.path.string());
}

// A map over Gamma [lo, hi] x frequencies, with M_eff and C_eff given by functions of (Gamma, f).
template <class M, class C>
EffectiveMap make_map(std::vector<double> gamma, std::vector<double> freq, M m, C c) {
  EffectiveMap map;
  map.gamma = gamma, map.frequency = freq;
  for (double G : gamma)
    for (double f : freq) {
      map.M_eff.push_back(m(G, f)), map.C_eff.push_back(c(G, f));
      map.M_eff_ci95.push_back(0), map.C_eff_ci95.push_back(0);
    }
  return map;
}

// |Y| at x_a of the linear structure with a point mass M and dashpot C at the cavity.
double linear_response(const Primary& p, double F, double f, double M, double C) {
  const double w = 2 * std::numbers::pi * f;
  const Eigen::VectorXcd Q = p.steady_amplitudes(F, w, std::complex<double>(-w * w * M, w * C));
  return std::abs(p.at_response.cast<std::complex<double>>().dot(Q));
}

}  // namespace

TEST(Predict, AConstantMapGivesTheLinearResponseExactly) {
  bagdem::testing::TempDir t;
  const Scene s = sdof_scene(t);
  ASSERT_TRUE(s.primary);
  const EffectiveMap map = make_map({1e-4, 1e-2, 1, 100}, {15, 20, 25}, [](double, double) { return 0.08; },
                                    [](double, double) { return 3.0; });
  double worst = 0;
  for (double f = 15; f <= 25; f += 0.05) {
    const FrequencyPrediction p = predict_at(*s.primary, map, 0.5, f);
    ASSERT_EQ(p.solutions.size(), 1u) << f << " Hz: " << p.outside;
    const double exact = linear_response(*s.primary, 0.5, f, 0.08, 3.0);
    worst = std::max(worst, std::abs(p.solutions[0].response / exact - 1));
  }
  std::printf("  SDOF: largest relative difference from the linear FRF %.2e\n", worst);
  EXPECT_LT(worst, 1e-12);

  // The pipe's free-free beam (four elastic modes and the rigid ones) at mid-span.
  const Scene pipe = load_case(std::string(BAGDEM_SOURCE_DIR) + "/cases/pipe-beanbag");
  ASSERT_TRUE(pipe.primary);
  const EffectiveMap pipe_map = make_map({1e-4, 1e-2, 1, 100}, {70, 100}, [](double, double) { return 0.026; },
                                         [](double, double) { return 2.0; });
  worst = 0;
  for (double f = 70; f <= 100; f += 0.1) {
    const FrequencyPrediction p = predict_at(*pipe.primary, pipe_map, 0.2, f);
    ASSERT_EQ(p.solutions.size(), 1u) << f << " Hz: " << p.outside;
    worst = std::max(worst, std::abs(p.solutions[0].response / linear_response(*pipe.primary, 0.2, f, 0.026, 2.0) - 1));
  }
  std::printf("  pipe: largest relative difference from the linear FRF %.2e\n", worst);
  EXPECT_LT(worst, 1e-12);
}

TEST(Predict, AFoldedResponseGivesEverySolution) {
  bagdem::testing::TempDir t;
  const Scene s = sdof_scene(t);
  // Heavy damping at small amplitude that collapses above Gamma 0.2: near resonance the lightly
  // damped branch (large X) and the heavily damped one (small X) coexist, with an unstable one between.
  std::vector<double> gamma;
  for (double G = 1e-3; G <= 100 * (1 + 1e-9); G *= std::pow(10.0, 0.05)) gamma.push_back(G);
  const EffectiveMap map = make_map(gamma, {15, 25}, [](double, double) { return 0.0; },
                                    [](double G, double) { return G < 0.2 ? 40.0 : 0.0; });
  std::size_t most = 0;
  for (double f = 18; f <= 22; f += 0.02) {
    const FrequencyPrediction p = predict_at(*s.primary, map, 0.5, f);
    most = std::max(most, p.solutions.size());
    for (const HarmonicSolution& h : p.solutions) {  // each a fixed point: X = |U(Z(X))|
      const auto mc = map.at(h.cavity_amplitude, f);
      ASSERT_TRUE(mc);
      EXPECT_NEAR(linear_response(*s.primary, 0.5, f, mc->first, mc->second), h.response, 1e-9 * h.response) << f << " Hz";
      EXPECT_NEAR(h.response, h.cavity_amplitude, 1e-9 * h.response) << "on an SDOF the cavity is the response point";
    }
  }
  EXPECT_EQ(most, 3u) << "the fold's three branches";
}

TEST(Predict, RefusesWhatLiesOutsideTheMap) {
  bagdem::testing::TempDir t;
  const Scene s = sdof_scene(t);
  const EffectiveMap map = make_map({0.5, 20}, {18, 22}, [](double, double) { return 0.08; }, [](double, double) { return 3.0; });
  EXPECT_EQ(predict_at(*s.primary, map, 0.5, 25).outside, "band");
  EXPECT_EQ(predict_at(*s.primary, map, 1e-6, 20).outside, "below");  // a tiny force: X far below Gamma 0.5
  EXPECT_EQ(predict_at(*s.primary, map, 1e4, 20).outside, "above");
  // map.csv read back: its grid and its columns.
  std::ofstream(t.path / "map.csv") << "gamma [1],frequency [Hz],M_eff [kg],M_eff_ci95 [kg],C_eff [N s/m],C_eff_ci95 [N s/m]\n"
                                       "0.5,18,0.08,nan,3,0.1\n0.5,22,0.08,nan,3,0.1\n20,18,0.07,nan,2,0.1\n20,22,0.07,nan,2,0.1\n";
  const EffectiveMap back = read_effective_map(t.path / "map.csv");
  EXPECT_EQ(back.gamma, (std::vector<double>{0.5, 20}));
  EXPECT_EQ(back.frequency, (std::vector<double>{18, 22}));
  EXPECT_TRUE(std::isnan(back.M_eff_ci95[0])) << "one start: its interval is not known";
  EXPECT_TRUE(back.at(5e-4, 20)) << "the means are";
  EXPECT_FALSE(back.at(5e-4, 20, 1, 1)) << "a corner of the interval is not";
  // Two bands (as characterize maps excitation.around_modes = [1, 3]): nothing between them.
  const EffectiveMap bands = make_map({0.5, 20}, {18, 19, 20, 40, 45, 50}, [](double, double) { return 0.08; }, [](double, double) { return 3.0; });
  EXPECT_TRUE(bands.covers(19.5));
  EXPECT_TRUE(bands.covers(47));
  EXPECT_TRUE(bands.covers(20) && bands.covers(40));
  EXPECT_FALSE(bands.covers(30)) << "between the bands";
  EXPECT_EQ(predict_at(*s.primary, bands, 0.5, 30).outside, "band");
  const EffectiveMap two = make_map({0.5, 20}, {18, 20, 26, 30}, [](double, double) { return 0.08; }, [](double, double) { return 3.0; });
  EXPECT_FALSE(two.covers(23)) << "a gap wider than the spacing on either side";
  const EffectiveMap dense = make_map({0.5, 20}, {18, 20, 21, 30}, [](double, double) { return 0.08; }, [](double, double) { return 3.0; });
  EXPECT_TRUE(dense.covers(20.5)) << "a gap no wider than a spacing beside it";
  // Bands of two lines each beside one of another spacing fool the spacing (40-70 and 75-135 Hz,
  // as characterize --frequencies 2 maps them): the bands characterize records decide.
  EffectiveMap recorded = make_map({0.5, 20}, {40, 70, 75, 135}, [](double, double) { return 0.08; }, [](double, double) { return 3.0; });
  EXPECT_FALSE(recorded.covers(80)) << "told by the spacing alone: wrongly refused";
  recorded.bands = {{40, 70}, {75, 135}};
  EXPECT_TRUE(recorded.covers(80));
  EXPECT_FALSE(recorded.covers(72));
  EXPECT_TRUE(recorded.covers(70) && recorded.covers(75) && recorded.covers(40) && recorded.covers(135));
  std::ofstream(t.path / "bad.csv") << "gamma [1],frequency [Hz],M_eff [kg],M_eff_ci95 [kg],C_eff [N s/m]\n0.5,18,1,0,1\n";
  try {
    read_effective_map(t.path / "bad.csv");
    ADD_FAILURE() << "read a map without C_eff_ci95";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("C_eff_ci95"), std::string::npos) << e.what();
  }
}

// A corner of the map's interval that leaves the map near the peak (its damping 0.1 of the mean's:
// the response climbs above the map's Gamma 1) has no peak over the band, and the interval is then
// not known: NaN, not the range of the corners left (which narrows as the map's intervals widen).
TEST(Predict, ACornerThatLeavesTheMapLeavesTheIntervalUnknown) {
  bagdem::testing::TempDir t;
  const Scene s = sdof_scene(t);
  EffectiveMap map = make_map({1e-4, 1e-2, 1}, {15, 25}, [](double, double) { return 0.08; }, [](double, double) { return 3.0; });
  for (double& ci : map.C_eff_ci95) ci = 2.9;
  const auto modes = predict_modes(*s.primary, map, 0.5, {18, 20, 22}, 400, Checks::interval);
  ASSERT_EQ(modes.size(), 1u);
  const PredictedMode& m = modes[0];
  ASSERT_TRUE(m.outside.empty()) << m.outside_why;
  std::printf("  %.4f dB, range %.4f to %.4f over %d corners\n", m.reduction_db, m.reduction_db_lo, m.reduction_db_hi, m.corners);
  EXPECT_EQ(m.corners, 2) << "the two corners of less damping leave the map at the peak";
  EXPECT_TRUE(std::isnan(m.reduction_db_lo) && std::isnan(m.reduction_db_hi));
  EXPECT_TRUE(std::isfinite(m.reduction_db));
  for (double& ci : map.C_eff_ci95) ci = 0.3;  // every corner inside: the range
  const PredictedMode n = predict_modes(*s.primary, map, 0.5, {18, 20, 22}, 400, Checks::interval)[0];
  EXPECT_EQ(n.corners, 4);
  EXPECT_LT(n.reduction_db_lo, n.reduction_db);
  EXPECT_GT(n.reduction_db_hi, n.reduction_db);
}

TEST(Predict, TheCommandGivesTheLinearPeakReductionOfAConstantMapAndRefusesWhatItDoesNotCover) {
  bagdem::testing::TempDir t;
  const Scene s = sdof_scene(t);
  // A constant map: 80 g and 3 N s/m over Gamma 1e-4 to 100 and 15-25 Hz.
  std::ofstream(t.path / "map.csv") << "gamma [1],frequency [Hz],M_eff [kg],M_eff_ci95 [kg],C_eff [N s/m],C_eff_ci95 [N s/m]\n"
                                       "0.0001,15,0.08,0.01,3,0.5\n0.0001,25,0.08,0.01,3,0.5\n100,15,0.08,0.01,3,0.5\n100,25,0.08,0.01,3,0.5\n";
  const auto r = bagdem::testing::run_bagdem({"predict", t.path.string(), "--map", t.path.string(), "--amplitude", "0.5 N", "--points", "2001",
                                              "--out", (t.path / "p").string()},
                                             t.path);
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  // The exact linear peaks over the sweep's band (18-22 Hz), on a fine scan.
  auto peak = [&](double M, double C) {
    double best = 0;
    for (double f = 18; f <= 22; f += 1e-4) best = std::max(best, linear_response(*s.primary, 0.5, f, M, C));
    return best;
  };
  const double bare = peak(0, 0), exact = 20 * std::log10(bare / peak(0.08, 3));
  const TextTable p = read_text_table(t.path / "p" / "predict_peaks.csv");
  ASSERT_EQ(p.rows.size(), 1u);
  const double db = std::stod(p.rows[0][p.find("reduction_dB")]);
  std::printf("  predicted %.5f dB, linear %.5f dB\n", db, exact);
  EXPECT_NEAR(db, exact, 1e-3);
  // Its range over the map's intervals holds the corners' linear reductions.
  const double lo = std::stod(p.rows[0][p.find("reduction_dB_lo")]), hi = std::stod(p.rows[0][p.find("reduction_dB_hi")]);
  EXPECT_NEAR(hi, 20 * std::log10(bare / peak(0.07, 3.5)), 2e-3);  // lighter and more damped: the most reduction
  EXPECT_LT(lo, db);
  EXPECT_GT(hi, db);
  // A force whose response leaves the map: refused, naming the command that would cover it.
  const auto far = bagdem::testing::run_bagdem({"predict", t.path.string(), "--map", t.path.string(), "--amplitude", "1e-9 N", "--out",
                                                (t.path / "q").string()},
                                               t.path);
  EXPECT_EQ(far.code, 2);
  EXPECT_NE(far.err.find("bagdem characterize"), std::string::npos) << far.err;
  EXPECT_FALSE(std::filesystem::exists(t.path / "q" / "predict_peaks.csv"));
  // --out: a file, or a directory holding a file of the user's by a table's name, is refused before
  // anything is computed (exit 2), the file unchanged; an earlier predict's tables are its own.
  std::ofstream(t.path / "notes.txt") << "mine\n";
  std::filesystem::create_directories(t.path / "mine");
  std::ofstream(t.path / "mine" / "predict.csv") << "my own table\n";
  for (const std::string out : {"notes.txt", "mine"}) {
    const auto r2 = bagdem::testing::run_bagdem({"predict", t.path.string(), "--map", t.path.string(), "--amplitude", "0.5 N", "--out",
                                                 (t.path / out).string()},
                                                t.path);
    EXPECT_EQ(r2.code, 2) << out << r2.err;
    EXPECT_NE(r2.err.find("--out"), std::string::npos) << r2.err;
    EXPECT_EQ(r2.out.find("peak reduction"), std::string::npos) << "refused before computing";
  }
  EXPECT_EQ(bagdem::testing::slurp(t.path / "notes.txt"), "mine\n");
  EXPECT_EQ(bagdem::testing::slurp(t.path / "mine" / "predict.csv"), "my own table\n");
  const auto again = bagdem::testing::run_bagdem({"predict", t.path.string(), "--map", t.path.string(), "--amplitude", "0.5 N", "--out",
                                                  (t.path / "p").string()},
                                                 t.path);
  EXPECT_EQ(again.code, 0) << again.err;
}

TEST(Predict, RandomForceOnAConstantMapGivesTheLinearRms) {
  // Equal lines of a band-limited random force: with a constant map the equivalent-linear
  // iteration is the linear structure with a point mass and dashpot, whose RMS is the lines' sum.
  bagdem::testing::TempDir t;
  const Scene s = sdof_scene(t);
  const EffectiveMap map = make_map({1e-4, 1e-2, 1, 100}, {15, 25}, [](double, double) { return 0.08; },
                                    [](double, double) { return 3.0; });
  const RandomPrediction r = predict_random(*s.primary, map, 0.3, 16, 24, 200);
  ASSERT_TRUE(r.outside.empty()) << r.outside;
  EXPECT_TRUE(r.converged);
  double y2 = 0, b2 = 0;
  const double a = 0.3 * std::sqrt(2.0 / 200);
  for (int k = 0; k < 200; ++k) {
    const double f = 16 + 8.0 * k / 199;
    y2 += 0.5 * std::pow(linear_response(*s.primary, a, f, 0.08, 3.0), 2);
    b2 += 0.5 * std::pow(linear_response(*s.primary, a, f, 0, 0), 2);
  }
  std::printf("  RMS %.6e m with the damper (bare %.6e m) in %d iterations\n", r.response_rms, r.bare_response_rms, r.iterations);
  EXPECT_NEAR(r.response_rms, std::sqrt(y2), 1e-12 * std::sqrt(y2));
  EXPECT_NEAR(r.bare_response_rms, std::sqrt(b2), 1e-12 * std::sqrt(b2));
  EXPECT_LT(r.response_rms, r.bare_response_rms);
  // A map whose damping falls with the amplitude: the iteration settles where the RMS it reads the
  // map at is the RMS it produces.
  const EffectiveMap soft = make_map({1e-4, 1e-2, 1, 100}, {15, 25}, [](double, double) { return 0.08; },
                                     [](double G, double) { return 3.0 / (1 + 10 * G); });
  const RandomPrediction n = predict_random(*s.primary, soft, 0.3, 16, 24, 200);
  ASSERT_TRUE(n.converged);
  const double A = std::sqrt(2.0) * n.cavity_rms;
  double u2 = 0;
  for (int k = 0; k < 200; ++k) {
    const double f = 16 + 8.0 * k / 199;
    const auto mc = soft.at(A, f);
    ASSERT_TRUE(mc);
    u2 += 0.5 * std::pow(linear_response(*s.primary, a, f, mc->first, mc->second), 2);  // SDOF: x_a is the cavity
  }
  EXPECT_NEAR(n.cavity_rms, std::sqrt(u2), 1e-8 * n.cavity_rms);
  EXPECT_EQ(predict_random(*s.primary, map, 0.3, 10, 24, 200).outside, "band");
}

// A damaged map header (a column in another unit) or cell is refused, naming the file, the column
// and what is allowed: the rule modes.csv follows (TextTable::column), one for both. A map whose
// M_eff column read [g] used to be taken as kilograms.
TEST(Predict, ADamagedMapIsRefusedByTheRuleOfEveryTable) {
  bagdem::testing::TempDir t;
  const std::string good = "gamma [1],frequency [Hz],M_eff [kg],M_eff_ci95 [kg],C_eff [N s/m],C_eff_ci95 [N s/m]\n";
  const std::string rows = "0.5,18,0.08,0,3,0.1\n0.5,22,0.08,0,3,0.1\n20,18,0.07,0,2,0.1\n20,22,0.07,0,2,0.1\n";
  struct Case {
    std::string header, rows;
    std::vector<std::string> expect;
  };
  std::string in_grams = good, in_mm = good;
  in_grams.replace(in_grams.find("M_eff [kg]"), 10, "M_eff [g]");
  in_mm.replace(in_mm.find("frequency [Hz]"), 14, "frequency [rad/s]");
  std::string word = rows, infinite = rows;
  word.replace(word.find("0.07"), 4, "fast");
  infinite.replace(infinite.find("0.08,0,3"), 8, "0.08,0,inf");
  for (const Case& c : {Case{in_grams, rows, {"key 'M_eff' = [g]", "must be in [kg]"}},
                        Case{in_mm, rows, {"key 'frequency' = [rad/s]", "must be in [Hz]"}},
                        Case{good, word, {"key 'M_eff' = 'fast'", "must be a finite number or nan", "row 3"}},
                        Case{good, infinite, {"key 'C_eff' = 'inf'", "must be a finite number or nan", "row 1"}},
                        Case{good.substr(0, good.find(",C_eff_ci95")) + "\n", "0.5,18,0.08,0,3\n", {"C_eff_ci95 [N s/m]", "column missing"}}}) {
    std::ofstream(t.path / "map.csv", std::ios::trunc) << c.header << c.rows;
    try {
      read_effective_map(t.path / "map.csv");
      ADD_FAILURE() << "read a damaged map:\n" << c.header << c.rows;
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find((t.path / "map.csv").string()), std::string::npos) << m;
      for (const std::string& part : c.expect) EXPECT_NE(m.find(part), std::string::npos) << part << " not in: " << m;
    }
  }
}

// A damped peak at the band's edge is marked in predict_peaks.csv (at_band_edge) and said, as the
// sweep marks its own: the reduction is then only a bound. It used to be printed unmarked.
TEST(Predict, APeakAtTheBandsEdgeIsMarked) {
  bagdem::testing::TempDir t;
  sdof_scene(t);
  std::ofstream(t.path / "map.csv") << "gamma [1],frequency [Hz],M_eff [kg],M_eff_ci95 [kg],C_eff [N s/m],C_eff_ci95 [N s/m]\n"
                                       "0.0001,15,0.08,0.01,3,0.5\n0.0001,25,0.08,0.01,3,0.5\n100,15,0.08,0.01,3,0.5\n100,25,0.08,0.01,3,0.5\n";
  // The 80 g moves the damped peak from 20 Hz to 19.2 Hz: a band of 19.5-20.5 Hz holds the bare peak, not the damped one.
  for (const auto& [band, edge] : {std::pair{"[18, 20, 22]", 0}, std::pair{"[19.5, 20, 20.5]", 1}}) {
    const auto r = bagdem::testing::run_bagdem({"predict", t.path.string(), "--map", t.path.string(), "--amplitude", "0.5 N", "--set",
                                                std::string("excitation.frequencies=") + band, "--out", (t.path / "p").string()},
                                               t.path);
    ASSERT_EQ(r.code, 0) << r.err << r.out;
    const TextTable p = read_text_table(t.path / "p" / "predict_peaks.csv");
    ASSERT_EQ(p.rows.size(), 1u);
    EXPECT_EQ(p.rows[0][p.column({"at_band_edge", "1"})], std::to_string(edge)) << band;
    EXPECT_EQ(r.out.find("AT THE BAND'S EDGE") != std::string::npos, edge == 1) << r.out;
    EXPECT_EQ(r.err.find("widen excitation.span") != std::string::npos, edge == 1) << r.err;
  }
  // A band without a natural frequency: refused, saying so (it used to write empty tables, exit 0).
  const auto none = bagdem::testing::run_bagdem({"predict", t.path.string(), "--map", t.path.string(), "--amplitude", "0.5 N", "--set",
                                                 "excitation.frequencies=[17, 17.5, 18]", "--out", (t.path / "n").string()},
                                                t.path);
  EXPECT_EQ(none.code, 2) << none.err << none.out;
  EXPECT_NE(none.err.find("holds no natural frequency"), std::string::npos) << none.err;
  EXPECT_FALSE(std::filesystem::exists(t.path / "n" / "predict_peaks.csv"));
  // A force as --vary and calibrate's --bounds take it: quoted as TOML or bare (the quoted form used
  // to be refused).
  for (const char* force : {"\"0.5 N\"", "0.5 N", "0.5"}) {
    const auto r = bagdem::testing::run_bagdem({"predict", t.path.string(), "--map", t.path.string(), "--amplitude", force, "--out",
                                                (t.path / "q").string()},
                                               t.path);
    EXPECT_EQ(r.code, 0) << force << ": " << r.err;
    EXPECT_EQ(r.out.rfind("0.5 N, mode 1:", 0), 0u) << r.out;
  }
}

// The resolution check (reduce/predict.hpp): the interpolation's bounds |f''| h^2 / 8 per node,
// exact for a quadratic; NaN where an axis (a band) has fewer than 3 lines.
TEST(Predict, TheInterpolationBoundIsThatOfAQuadratic) {
  // C = ln(Gamma)^2 on lines 1 apart in ln Gamma: f'' = 2, h = 1, bound 1/4 at every node; along f
  // (two bands of 3 lines 10 Hz apart) M = f^2: f'' = 2, h = 10, bound 25.
  std::vector<double> gamma;
  for (int k = 0; k < 5; ++k) gamma.push_back(std::exp(double(k)));
  const EffectiveMap map = make_map(gamma, {80, 90, 100, 400, 410, 420}, [](double, double f) { return f * f; },
                                    [](double G, double) { return std::pow(std::log(G), 2); });
  const EffectiveMap b = map.interpolation_bounds();
  for (std::size_t k = 0; k < b.C_eff_ci95.size(); ++k) {
    EXPECT_NEAR(b.C_eff_ci95[k], 0.25, 1e-9) << k;
    EXPECT_NEAR(b.M_eff_ci95[k], 25, 1e-6) << k;
  }
  // Values that zigzag by 0.1 about 3 with 95% half-widths of 0.3: a curvature the cells' scatter
  // could make, not the map's shape: no bound. With no scatter given, the same zigzag is curvature.
  EffectiveMap zigzag = make_map(gamma, {80, 90, 100}, [](double, double) { return 1.0; },
                                 [](double G, double) { return 3 + 0.1 * std::cos(std::numbers::pi * std::round(std::log(G))); });
  EXPECT_GT(zigzag.interpolation_bounds().C_eff_ci95[5], 0.01);
  for (double& c : zigzag.C_eff_ci95) c = 0.3;
  for (double x : zigzag.interpolation_bounds().C_eff_ci95) EXPECT_EQ(x, 0) << "scatter taken for curvature";
  const auto one = [](double, double) { return 1.0; };
  const EffectiveMap two = make_map({0.1, 10}, {80, 90, 100, 450, 510}, one, one).interpolation_bounds();
  for (double x : two.C_eff_ci95) EXPECT_TRUE(std::isnan(x)) << "2 amplitudes, 2 frequencies in the upper band: no curvature to see";
}

// A map whose damping has a bump in log Gamma across the peak's amplitude: the estimated
// interpolation error bounds the map's actual error (its difference from a map 16 times finer) and
// falls as the map is refined; a map of a constant figure estimates 0.
TEST(Predict, TheEstimatedInterpolationErrorBoundsTheMapsActualOne) {
  bagdem::testing::TempDir t;
  const Scene s = sdof_scene(t);
  auto damping = [](double G, double) { return 2 + 6 * std::exp(-0.5 * std::pow(std::log(G), 2)); };
  auto grid = [](int n) {
    std::vector<double> G;
    for (int k = 0; k < n; ++k) G.push_back(1e-2 * std::pow(1e4, double(k) / (n - 1)));
    return G;
  };
  auto mass = [](double, double) { return 0.05; };
  auto reduction = [&](int n) { return predict_modes(*s.primary, make_map(grid(n), {15, 20, 25}, mass, damping), 0.5, {18, 20, 22}).at(0); };
  const double truth = reduction(129).reduction_db;
  double last = INFINITY;
  for (int n : {5, 9, 17, 33}) {
    const PredictedMode m = reduction(n);
    const double actual = std::abs(m.reduction_db - truth);
    std::printf("  %3d amplitudes: %.4f dB (129: %.4f), actual error %.4f dB, estimated %.4f dB\n", n, m.reduction_db, truth, actual,
                m.interpolation_db);
    EXPECT_GE(m.interpolation_db, actual) << n;
    EXPECT_LT(m.interpolation_db, last) << "a finer map, a smaller estimate";
    last = m.interpolation_db;
  }
  EXPECT_LT(last, 0.05);
  EXPECT_EQ(predict_modes(*s.primary, make_map(grid(5), {15, 20, 25}, mass, [](double, double) { return 3.0; }), 0.5, {18, 20, 22})
                .at(0)
                .interpolation_db,
            0);
  // 2 amplitudes: nothing to estimate the curvature from.
  EXPECT_TRUE(std::isnan(predict_modes(*s.primary, make_map(grid(2), {15, 20, 25}, mass, damping), 0.5, {18, 20, 22}).at(0).interpolation_db));
}
