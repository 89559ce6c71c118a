// `bagdem design --dampers 2` (study/design.hpp, predict_pairs), through the binary, on an analytic
// reference: a 6-mm steel ball rolling without slip on the floor of a box adds (2/7) m of mass and
// no damping (tests/test_design.cpp), so two such boxes on a light pinned-pinned beam (modes 1 and
// 2 at 20 and 80 Hz) are two point masses of (2/7) m at their places. Each pair's predicted
// worst-mode reduction must be the linear beam's with those two masses (continuum::modal_receptance
// with two bags, written apart from the prediction), every pair within the mass budget and none
// over it; the best pair is run coupled, and the chosen pair's case loads with its two dampers.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "bagdem/case/load_case.hpp"
#include "bagdem/reduce/continuum_model.hpp"
#include "bagdem/structure/response.hpp"
#include "bagdem/study/design_files.hpp"
#include "case_texts.hpp"
#include "support.hpp"

using namespace bagdem;
using namespace bagdem::study;
using bagdem::testing::quoted;
namespace fs = std::filesystem;

namespace {

// The largest |H| F over [lo, hi] of the beam with point masses at the places (shapes), on a fine scan.
double peak(const Primary& P, const std::vector<continuum::BagAt>& bags, double lo, double hi) {
  continuum::ModalModel model;
  model.omega = P.stiffness.cwiseSqrt();
  model.zeta = (P.damping.array() / (2 * model.omega.array())).matrix();
  model.shape_at_force = P.at_force, model.shape_at_response = P.at_response, model.shape_at_bag = P.at_cavity;
  model.mass = P.mass;
  double best = 0;
  for (double f = lo; f <= hi; f += 1e-3 * (hi - lo) / 8) best = std::max(best, std::abs(continuum::modal_receptance(model, bags, 2 * std::numbers::pi * f)));
  return best * P.amplitude;
}

}  // namespace

TEST(DesignPairs, TwoRollingBallsAreTwoPointMassesAndTheChosenPairLoads) {
  bagdem::testing::TempDir t;
  const fs::path dir = t.path / "case";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << bagdem::testing::rolling_balls_on_beam();
  const fs::path out = t.path / "design";
  const std::vector<std::string> args = {
      "design", dir.string(), "--vary", "particles.ball.diameter=\"6 mm\"", "--positions", "0.2,0.35,0.7", "--dampers", "2",
      "--budget", "0.1", "--gamma", "0.002,0.5", "--amplitudes", "4", "--frequencies", "2", "--seeds", "2", "--cycles", "6", "--skip", "2",
      "--window-time", "0", "--skip-time", "0", "--verify", "1", "--verify-seeds", "2", "--out", out.string(), "--jobs", "2"};
  const bagdem::testing::CmdResult r = bagdem::testing::run_bagdem(args, t.path);
  ASSERT_EQ(r.code, 0) << r.err << r.out;

  const DesignTable singles = read_design_csv(out / "design.csv");
  const DesignTable pairs = read_design_csv(out / "design-pairs.csv");
  ASSERT_EQ(singles.rows.size(), 3u);
  ASSERT_TRUE(pairs.pairs);
  ASSERT_EQ(pairs.rows.size(), 3u) << "three places, two at a time";
  EXPECT_EQ(pairs.modes, (std::vector<int>{1, 2}));
  const double m = 7800 * std::numbers::pi * std::pow(6e-3, 3) / 6;
  const Scene base = load_case(dir.string());
  const Primary& P = *base.primary;
  for (const DesignRow& row : pairs.rows) {
    ASSERT_EQ(row.status.kind, Standing::ranked) << row.status.text();
    EXPECT_LT(row.position, row.position2);
    EXPECT_NEAR(row.added_mass, 2 * m, 1e-9 * m);
    // The linear beam with (2/7) m at each place: each mode's reduction, the worst the objective.
    std::vector<continuum::BagAt> bags;
    for (double x : {row.position, row.position2})
      bags.push_back({load_case(dir.string(), {"primary.attach=\"" + std::to_string(x) + " m\""}).primary->at_cavity, 2 * m / 7, 0.0});
    double worst = INFINITY;
    for (const auto& [lo, hi] : {std::pair{17.0, 23.0}, std::pair{68.0, 92.0}})
      worst = std::min(worst, 20 * std::log10(peak(P, {}, lo, hi) / peak(P, bags, lo, hi)));
    std::printf("  balls at x/L %.2f and %.2f: predicted %.4f dB (%.4f to %.4f), two point masses %.4f dB\n", row.position, row.position2,
                row.objective, row.objective_lo, row.objective_hi, worst);
    EXPECT_NEAR(row.objective, worst, 0.01);
    EXPECT_LT(worst, 0) << "added mass alone raises a peak";
  }
  EXPECT_EQ(pairs.rows[0].dem_seeds, 2) << "the best pair run coupled with 2 starts";
  EXPECT_TRUE(std::isfinite(pairs.rows[0].dem_objective));
  // The chosen pair: the case with its second damper, ready to run.
  const Scene chosen = load_case((out / "chosen-pair").string());
  ASSERT_EQ(chosen.more_dampers.size(), 1u);
  EXPECT_NEAR(chosen.primary->attach, pairs.rows[0].attach, 1e-12);
  EXPECT_NEAR(chosen.more_dampers[0].scene->primary->attach, pairs.rows[0].attach2, 1e-12);
  EXPECT_NE(r.out.find("pair of bags"), std::string::npos) << r.out;

  // Again in the same OUT with a budget for one ball only: no pair, and the earlier chosen pair is
  // gone (the map is reused). Places whose boxes overlap on the beam (20 mm long, 10 mm apart) are
  // no pair either.
  auto again = [&](const std::string& positions, const std::string& budget) {
    return bagdem::testing::run_bagdem({"design", dir.string(), "--vary", "particles.ball.diameter=\"6 mm\"", "--positions", positions,
                                        "--dampers", "2", "--budget", budget, "--gamma", "0.002,0.5", "--amplitudes", "4", "--frequencies", "2",
                                        "--seeds", "2", "--cycles", "6", "--skip", "2", "--window-time", "0", "--skip-time", "0", "--verify", "0",
                                        "--out", out.string(), "--jobs", "2"},
                                       t.path);
  };
  const auto tight = again("0.2,0.35", "0.06");
  ASSERT_EQ(tight.code, 0) << tight.err;
  EXPECT_EQ(read_design_csv(out / "design-pairs.csv").rows.size(), 0u);
  EXPECT_FALSE(fs::exists(out / "chosen-pair")) << "an earlier design's pair is not this one's";
  EXPECT_NE(tight.out.find("no pair of bags ranked"), std::string::npos) << tight.out;
  const auto overlap = again("0.2,0.21", "0.1");
  ASSERT_EQ(overlap.code, 0) << overlap.err;
  EXPECT_EQ(read_design_csv(out / "design-pairs.csv").rows.size(), 0u);
  EXPECT_NE(overlap.out.find("1 pairs of places left out: their cavities overlap"), std::string::npos) << overlap.out;
  // A candidate key no damper may change: refused before anything runs.
  const auto key = bagdem::testing::run_bagdem({"design", dir.string(), "--vary", "excitation.amplitude=\"1 mN\",\"2 mN\"", "--dampers", "2",
                                                "--out", (t.path / "key").string()},
                                               t.path);
  EXPECT_EQ(key.code, 2);
  EXPECT_NE(key.err.find("excitation.amplitude"), std::string::npos) << key.err;
  EXPECT_FALSE(fs::exists(t.path / "key"));
  // --dampers 2 on a structure that is no beam: refused.
  std::ofstream(dir / "case.toml") << bagdem::testing::ball_on_sdof_floor();
  const auto sdof = bagdem::testing::run_bagdem({"design", dir.string(), "--vary", "particles.ball.diameter=\"6 mm\"", "--dampers", "2"}, t.path);
  EXPECT_EQ(sdof.code, 2);
  EXPECT_NE(sdof.err.find("--dampers"), std::string::npos) << sdof.err;
}
