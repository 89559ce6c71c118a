// Prediction with several dampers on one structure (reduce/predict.hpp, predict_at with
// MappedDamper), on the shipped pair (cases/stepped-beam-pair: a bag at the tip, one at 0.335 m):
// 1. Constant maps are linear masses and dashpots: the balance gives the modal model of two bags
//    (continuum::modal_receptance, written apart) at every frequency of both modes' bands.
// 2. A second damper whose map is empty (no mass, no damping) leaves the one-damper prediction.
// 3. Two equal dampers at one place are one damper of twice their impedance, amplitude by amplitude
//    (a nonlinear map: the balance must find the shared amplitude).
// 4. A response below one damper's map is refused, naming that damper; `bagdem predict` takes a map
//    per damper (NAME=DIR), refuses a damper left without one, and writes every cavity's amplitude.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <tuple>

#include "bagdem/case/load_case.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/reduce/continuum_model.hpp"
#include "bagdem/reduce/predict.hpp"
#include "support.hpp"

using namespace bagdem;

namespace {

const Scene& pair_scene() {
  static const Scene s = load_case(std::string(BAGDEM_SOURCE_DIR) + "/cases/stepped-beam-pair");
  return s;
}

// A map over Gamma x frequency with M_eff and C_eff functions of Gamma.
template <class M, class C>
EffectiveMap make_map(M m, C c) {
  EffectiveMap map;
  for (double G = 1e-4; G <= 100 * (1 + 1e-9); G *= std::pow(10.0, 0.1)) map.gamma.push_back(G);
  map.frequency = {50, 100, 290, 480};
  for (double G : map.gamma)
    for (std::size_t j = 0; j < map.frequency.size(); ++j) {
      map.M_eff.push_back(m(G)), map.C_eff.push_back(c(G));
      map.M_eff_ci95.push_back(0.1 * std::abs(m(G))), map.C_eff_ci95.push_back(0.1 * std::abs(c(G)));
    }
  return map;
}

// Damping that collapses above Gamma 0.5 on a mass of 20 g: at 0.2 N the mass moves mode 1 and the
// response folds, its largest branch far above the bare structure's amplitude at that frequency.
EffectiveMap folding_map(double scale = 1) {
  return make_map([scale](double) { return scale * 0.02; }, [scale](double G) { return scale * 8.0 / (1 + std::pow(G / 0.5, 6)); });
}

// A bag whose damping peaks near Gamma 0.1 and whose mass is shed above Gamma 1 (the shape of
// reduced.csv on the pair): nonlinear wherever the pair's cavities move.
EffectiveMap nonlinear_map(double scale = 1) {
  return make_map([scale](double G) { return scale * 0.04 / (1 + G * G); },
                  [scale](double G) { return scale * 3.0 * G / (0.01 + G * G) * 0.1; });
}

void map_write(const std::filesystem::path& dir, const EffectiveMap& m) {
  std::filesystem::create_directories(dir);
  std::ofstream f(dir / "map.csv");
  f << "gamma [1],frequency [Hz],M_eff [kg],M_eff_ci95 [kg],C_eff [N s/m],C_eff_ci95 [N s/m]\n";
  f.precision(17);
  for (std::size_t i = 0; i < m.gamma.size(); ++i)
    for (std::size_t j = 0; j < m.frequency.size(); ++j) {
      const std::size_t k = i * m.frequency.size() + j;
      f << m.gamma[i] << "," << m.frequency[j] << "," << m.M_eff[k] << "," << m.M_eff_ci95[k] << "," << m.C_eff[k] << "," << m.C_eff_ci95[k] << "\n";
    }
}

}  // namespace

TEST(PredictSeveral, ConstantMapsGiveTheModalModelOfTwoBags) {
  const Scene& s = pair_scene();
  ASSERT_EQ(s.more_dampers.size(), 1u);
  const Primary& P = *s.primary;
  const Eigen::VectorXd& mid = s.more_dampers[0].scene->primary->at_cavity;
  const EffectiveMap tip_map = make_map([](double) { return 0.03; }, [](double) { return 2.0; });
  const EffectiveMap mid_map = make_map([](double) { return 0.02; }, [](double) { return 0.7; });
  const std::vector<MappedDamper> d = {{&tip_map, P.at_cavity, "tip"}, {&mid_map, mid, "mid"}};
  continuum::ModalModel model;  // the structure as compare.csv's modal model sees it
  model.omega = P.stiffness.cwiseSqrt();
  model.zeta = (P.damping.array() / (2 * model.omega.array())).matrix();
  model.shape_at_force = P.at_force, model.shape_at_response = P.at_response, model.shape_at_bag = P.at_cavity;
  model.mass = P.mass;
  const double F = 0.05;
  double worst = 0, worst_x = 0;
  int n = 0;
  for (double f : {55.0, 62.0, 68.0, 70.0, 72.0, 80.0, 300.0, 340.0, 370.0, 384.0, 400.0, 460.0}) {
    const FrequencyPrediction p = predict_at(P, d, F, f);
    ASSERT_EQ(p.solutions.size(), 1u) << f << " Hz: " << p.outside;
    const double w = 2 * std::numbers::pi * f;
    const double exact = std::abs(continuum::modal_receptance(model, {{P.at_cavity, 0.03, 2.0}, {mid, 0.02, 0.7}}, w)) * F;
    worst = std::max(worst, std::abs(p.solutions[0].response / exact - 1));
    // Each cavity's amplitude is that of the linear structure at its place.
    const Eigen::VectorXcd Q = P.steady_amplitudes(F, w, {P.at_cavity, mid}, {std::complex<double>(-w * w * 0.03, w * 2.0), std::complex<double>(-w * w * 0.02, w * 0.7)});
    for (std::size_t k = 0; k < 2; ++k)
      worst_x = std::max(worst_x, std::abs(p.solutions[0].cavities[k] / std::abs(d[k].at_cavity.cast<std::complex<double>>().dot(Q)) - 1));
    ++n;
  }
  std::printf("  %d frequencies: response against the modal model of two bags %.2e, the cavities' amplitudes %.2e\n", n, worst, worst_x);
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(worst_x, 1e-9);
}

TEST(PredictSeveral, AnEmptySecondMapLeavesTheOneDamperPrediction) {
  const Scene& s = pair_scene();
  const Primary& P = *s.primary;
  const EffectiveMap none = make_map([](double) { return 0.0; }, [](double) { return 0.0; });
  // A smooth map at the case's force, and a folding one at 0.2 N (its largest branch above the bare
  // amplitude: found only if the starts reach above it).
  for (const auto& [tip_map, F] : {std::pair{nonlinear_map(), P.amplitude}, std::pair{folding_map(), 0.2}}) {
    const std::vector<MappedDamper> d = {{&tip_map, P.at_cavity, "tip"}, {&none, s.more_dampers[0].scene->primary->at_cavity, "mid"}};
    const auto one = predict_modes(P, tip_map, F, P.stepped_sine->frequencies, 120, Checks::interval);
    const auto two = predict_modes(P, d, F, P.stepped_sine->frequencies, 120, Checks::interval);
    ASSERT_EQ(one.size(), 2u);
    ASSERT_EQ(two.size(), 2u);
    for (std::size_t m = 0; m < 2; ++m) {
      ASSERT_TRUE(one[m].outside.empty() && two[m].outside.empty()) << one[m].outside_why << " " << two[m].outside_why;
      std::printf("  %.3g N, mode %zu: one damper %.6f dB (%.3f to %.3f), with an empty second %.6f dB (%.3f to %.3f)\n", F, one[m].mode,
                  one[m].reduction_db, one[m].reduction_db_lo, one[m].reduction_db_hi, two[m].reduction_db, two[m].reduction_db_lo,
                  two[m].reduction_db_hi);
      EXPECT_GT(std::abs(one[m].reduction_db), 0.3) << "the map must act for the check to mean anything";
      EXPECT_NEAR(two[m].reduction_db, one[m].reduction_db, 1e-7);
      EXPECT_NEAR(two[m].reduction_db_lo, one[m].reduction_db_lo, 1e-7);
      EXPECT_NEAR(two[m].reduction_db_hi, one[m].reduction_db_hi, 1e-7);
      EXPECT_EQ(two[m].peak_frequency, one[m].peak_frequency);
      std::size_t branches = 0;
      for (std::size_t k = 0; k < one[m].points.size(); ++k) {
        ASSERT_EQ(two[m].points[k].solutions.size(), one[m].points[k].solutions.size()) << one[m].points[k].frequency << " Hz";
        branches = std::max(branches, one[m].points[k].solutions.size());
      }
      if (F == 0.2 && m == 0) EXPECT_EQ(branches, 3u) << "the folding map folds mode 1";
    }
  }
}

TEST(PredictSeveral, TwoEqualDampersAtOnePlaceAreOneOfTwiceTheImpedance) {
  const Scene& s = pair_scene();
  const Primary& P = *s.primary;
  std::size_t solutions = 0;
  for (const auto& [single, doubled, F] : {std::tuple{nonlinear_map(), nonlinear_map(2), P.amplitude}, std::tuple{folding_map(), folding_map(2), 0.8}}) {
  const std::vector<MappedDamper> twins = {{&single, P.at_cavity, "a"}, {&single, P.at_cavity, "b"}};
  const auto one = predict_modes(P, doubled, F, P.stepped_sine->frequencies, 120, Checks::none);
  const auto two = predict_modes(P, twins, F, P.stepped_sine->frequencies, 120, Checks::none);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t m = 0; m < one.size(); ++m) {
    std::printf("  %.3g N, mode %zu: twice the impedance %.6f dB, two twins %.6f dB\n", F, one[m].mode, one[m].reduction_db, two[m].reduction_db);
    EXPECT_NEAR(two[m].reduction_db, one[m].reduction_db, 1e-7);
    ASSERT_EQ(one[m].points.size(), two[m].points.size());
    for (std::size_t k = 0; k < one[m].points.size(); ++k) {
      ASSERT_EQ(two[m].points[k].solutions.size(), one[m].points[k].solutions.size()) << one[m].points[k].frequency << " Hz";
      for (std::size_t b = 0; b < one[m].points[k].solutions.size(); ++b, ++solutions) {
        const HarmonicSolution &x = one[m].points[k].solutions[b], &y = two[m].points[k].solutions[b];
        EXPECT_NEAR(y.cavities[0], x.cavity_amplitude, 1e-9 * x.cavity_amplitude);
        EXPECT_NEAR(y.cavities[1], x.cavity_amplitude, 1e-9 * x.cavity_amplitude);
      }
    }
  }
  }
  EXPECT_GT(solutions, 400u);
}

TEST(PredictSeveral, TheCommandTakesAMapPerDamperAndRefusesWhatItDoesNotCover) {
  bagdem::testing::TempDir t;
  const std::string pair = std::string(BAGDEM_SOURCE_DIR) + "/cases/stepped-beam-pair";
  map_write(t.path / "tip", nonlinear_map());
  map_write(t.path / "mid", nonlinear_map(0.5));
  const auto r = bagdem::testing::run_bagdem({"predict", pair, "--map", "tip=" + (t.path / "tip").string(), "--map",
                                              "mid=" + (t.path / "mid").string(), "--points", "60", "--out", (t.path / "p").string()},
                                             t.path);
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const TextTable p = read_text_table(t.path / "p" / "predict.csv");
  ASSERT_NE(p.find("cavity_amplitude_mid"), p.names.size()) << "every cavity's amplitude";
  EXPECT_EQ(read_text_table(t.path / "p" / "predict_peaks.csv").rows.size(), 2u) << "modes 1 and 2";
  // One map for both, and a damper left without one.
  EXPECT_EQ(bagdem::testing::run_bagdem({"predict", pair, "--map", (t.path / "tip").string(), "--points", "20", "--out", (t.path / "q").string()}, t.path).code, 0);
  const auto none = bagdem::testing::run_bagdem({"predict", pair, "--map", "tip=" + (t.path / "tip").string(), "--out", (t.path / "r").string()}, t.path);
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("damper mid has no map"), std::string::npos) << none.err;
  const auto wrong = bagdem::testing::run_bagdem({"predict", pair, "--map", "tail=" + (t.path / "tip").string(), "--out", (t.path / "r").string()}, t.path);
  EXPECT_EQ(wrong.code, 2);
  EXPECT_NE(wrong.err.find("names no damper of the case (its dampers: tip, mid)"), std::string::npos) << wrong.err;
  // The mid bag's map starting above where it moves: refused, naming it, nothing written.
  EffectiveMap high = nonlinear_map(0.5);
  const std::size_t nf = high.frequency.size(), keep = high.gamma.size() - 8;
  high.gamma.erase(high.gamma.begin(), high.gamma.begin() + static_cast<long>(keep));
  for (auto* v : {&high.M_eff, &high.C_eff, &high.M_eff_ci95, &high.C_eff_ci95}) v->erase(v->begin(), v->begin() + static_cast<long>(keep * nf));
  map_write(t.path / "high", high);
  const auto below = bagdem::testing::run_bagdem({"predict", pair, "--map", (t.path / "tip").string(), "--map", "mid=" + (t.path / "high").string(),
                                                  "--points", "20", "--out", (t.path / "r").string()},
                                                 t.path);
  EXPECT_EQ(below.code, 2);
  EXPECT_NE(below.err.find("damper mid's cavity's amplitude is below its map's"), std::string::npos) << below.err;
  EXPECT_FALSE(std::filesystem::exists(t.path / "r" / "predict_peaks.csv"));
}
