// `bagdem design` (study/design.hpp):
// 1. The ranking: a design's objective is its worst mode's reduction (with that mode's range); the
//    rows are ranked best first and the Pareto front of objective against added mass is marked.
// 2. Through the binary, on an analytic reference: a steel ball rolling without slip on the floor of
//    a box carried by a light SDOF (20 Hz) adds (2/7) m of mass and no damping (tests/
//    test_characterize.cpp), so the structure's peak rises: with the damping c = 2 zeta sqrt(k M)
//    fixed, the ratio becomes zeta' = zeta sqrt(M / (M + 2m/7)) and the peak |H| = 1 / (2 zeta' k
//    sqrt(1 - zeta'^2)), a reduction of 20 log10(zeta' sqrt(1 - zeta'^2) / (zeta sqrt(1 - zeta^2)))
//    dB, below zero and the lower the heavier the ball. Three ball sizes, the largest over the mass
//    budget: design builds two maps, ranks the lighter ball first, runs it coupled, and writes the
//    chosen case, which loads with that ball.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "bagdem/case/load_case.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/structure/response.hpp"
#include "bagdem/study/design.hpp"
#include "case_texts.hpp"
#include "support.hpp"

using namespace bagdem;
using namespace bagdem::study;
namespace fs = std::filesystem;

namespace {
// A design.csv column's index by its name (without the unit); a missing one fails the test.
std::size_t column(const TextTable& t, const std::string& name) {
  const std::size_t k = t.find(name);
  EXPECT_LT(k, t.names.size()) << "design.csv has no column " << name;
  return k;
}

DesignRow row(std::vector<double> db, double mass) {
  DesignRow r;
  r.db = db, r.db_lo = db, r.db_hi = db, r.added_mass = mass;
  for (double& x : r.db_lo) x -= 1;
  for (double& x : r.db_hi) x += 2;
  set_objective(r);
  return r;
}
}  // namespace

TEST(DesignRank, TheWorstModeRanksAndTheParetoFrontIsMarked) {
  const DesignRow a = row({12, 9}, 0.03);
  EXPECT_EQ(a.objective, 9);
  EXPECT_EQ(a.objective_lo, 8);
  EXPECT_EQ(a.objective_hi, 11);
  std::vector<DesignRow> rows = {row({5, 6}, 0.01), a, row({10, 11}, 0.03), row({4, 20}, 0.005), row({7, 7}, 0.05)};
  rows[1].given = {"b"}, rows[2].given = {"c"};
  rows.push_back(row({30, 30}, 0.001));
  rows.back().status = {bagdem::study::Standing::over_budget, ""};
  EXPECT_EQ(rows.back().status.text(), "over budget");
  rank_rows(rows);
  // By objective: 10 (0.03), 9 (0.03), 7 (0.05), 5 (0.01), 4 (0.005); the refused row last, unranked.
  ASSERT_EQ(rows.size(), 6u);
  const std::vector<double> objective = {10, 9, 7, 5, 4};
  for (std::size_t k = 0; k < objective.size(); ++k) {
    EXPECT_EQ(rows[k].objective, objective[k]);
    EXPECT_EQ(rows[k].rank, static_cast<int>(k + 1));
  }
  EXPECT_EQ(rows[5].rank, 0);
  EXPECT_FALSE(rows[5].pareto) << "a refused row is not on the front";
  // The front: 10 dB at 0.03, 5 dB at 0.01, 4 dB at 0.005 (9 dB at 0.03 and 7 at 0.05 are dominated).
  const std::vector<bool> front = {true, false, false, true, true};
  for (std::size_t k = 0; k < front.size(); ++k) EXPECT_EQ(rows[k].pareto, front[k]) << "row ranked " << k + 1;
  const std::vector<double> fills = default_fills(0.1), diameters = default_diameters(0.004);
  ASSERT_EQ(fills.size(), 3u);
  ASSERT_EQ(diameters.size(), 3u);
  const double f[] = {0.03, 0.06, 0.095}, d[] = {0.004, 0.006, 0.008};
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(fills[k], f[k], 1e-15);
    EXPECT_NEAR(diameters[k], d[k], 1e-15);
  }
}

TEST(Design, ARollingBallAddsTwoSeventhsOfItsMassTheLighterWinsAndTheChosenCaseLoads) {
  bagdem::testing::TempDir t;
  const fs::path dir = t.path / "case";
  fs::create_directories(dir);
  // A 0.02-kg SDOF of 20 Hz: the balls' 2/7 weigh 1-3% of it. 2 mN keeps Gamma below 0.3 at
  // the peak (rolling without slip needs Gamma < 3.5 mu).
  const double M = 0.02, k = M * std::pow(2 * std::numbers::pi * 20, 2), zeta = 0.02;
  std::ofstream(dir / "case.toml") << bagdem::testing::ball_on_sdof_floor();
  const fs::path out = t.path / "design";
  const std::vector<std::string> args = {
      "design", dir.string(), "--vary", "particles.ball.diameter=\"6 mm\",\"8 mm\",\"10 mm\"", "--budget", "0.15",
      "--set", "primary.mass=\"" + std::to_string(M) + " kg\"", "--set", "primary.stiffness=\"" + std::to_string(k) + " N/m\"",
      "--set", "excitation.amplitude=\"2 mN\"", "--gamma", "0.02,0.5", "--amplitudes", "3", "--frequencies", "2", "--seeds", "2",
      "--cycles", "6", "--skip", "2", "--window-time", "0", "--skip-time", "0", "--verify", "1", "--verify-seeds", "2",
      "--out", out.string(), "--jobs", "2"};
  const bagdem::testing::CmdResult r = bagdem::testing::run_bagdem(args, t.path);
  ASSERT_EQ(r.code, 0) << r.err << r.out;

  const TextTable design = read_text_table(out / "design.csv");
  const auto& cells = design.rows;
  ASSERT_EQ(cells.size(), 3u) << "a row per candidate (an SDOF: one place)";
  auto col = [&](const std::string& name) { return column(design, name); };
  const std::size_t status = col("status"), rank = col("rank"), diameter = col("particles.ball.diameter"), mass = col("added_mass"),
                    objective = col("objective_dB"), dem = col("dem_objective_dB"), seeds = col("dem_seeds");
  col("reduction_dB_mode1");
  col("pareto");
  const std::size_t edge = col("at_band_edge");
  const double rho = 7800;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const auto& c = cells[i];
    const double d = c[diameter] == "6 mm" ? 6e-3 : c[diameter] == "8 mm" ? 8e-3 : 10e-3;
    const double m = rho * std::numbers::pi * d * d * d / 6;
    EXPECT_NEAR(std::stod(c[mass]), m, 1e-9 * m);
    if (d == 10e-3) {
      EXPECT_EQ(c[status], "over budget") << "0.0041 kg is 20% of the structure";
      EXPECT_EQ(c[rank], "");
      continue;
    }
    ASSERT_EQ(c[status], "ranked");
    EXPECT_EQ(c[edge], "0") << "the damped peak lies inside the band";
    const double z = zeta * std::sqrt(M / (M + 2 * m / 7));
    const double expected = 20 * std::log10(z * std::sqrt(1 - z * z) / (zeta * std::sqrt(1 - zeta * zeta)));
    std::printf("  %s ball: predicted %s dB, analytic %.4f dB\n", c[diameter].c_str(), c[objective].c_str(), expected);
    // 0.01 dB: the damped peak is sampled at 400 frequencies over the band (0.01 Hz apart).
    EXPECT_NEAR(std::stod(c[objective]), expected, 0.01);
    EXPECT_EQ(c[rank], d == 6e-3 ? "1" : "2") << "the lighter ball raises the peak less";
  }
  EXPECT_EQ(cells[0][diameter], "6 mm");
  EXPECT_EQ(cells[0][seeds], "2") << "the best pair run coupled with 2 starts";
  EXPECT_TRUE(std::isfinite(std::stod(cells[0][dem])));
  EXPECT_EQ(cells[1][seeds], "0");
  EXPECT_EQ(cells[1][dem], "");

  // The chosen case: the 6-mm ball, ready to run.
  const Scene chosen = load_case((out / "chosen").string());
  ASSERT_EQ(chosen.particles.size(), 1u);
  EXPECT_NEAR(chosen.particles[0].radius, 3e-3, 1e-12);
  EXPECT_NEAR(chosen.primary->structure_mass, M, 1e-12);

  // Again: every map and the check are reused (nothing runs), the same table.
  const auto before = bagdem::testing::slurp(out / "design.csv");
  const bagdem::testing::CmdResult again = bagdem::testing::run_bagdem(args, t.path);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_EQ(bagdem::testing::slurp(out / "design.csv"), before);
  EXPECT_NE(again.out.find("map built"), std::string::npos) << again.out;
}

// The same balls under a band-limited random force (18-22 Hz, 2 mN RMS): the objective is the
// in-band RMS response's reduction, and with (2/7) m added and no damping it is the multisine's
// analytic 20 log10(sigma_bare / sigma), sigma^2 = sum over the lines of a^2 |H(w_k)|^2 / 2
// (tests/test_structure.cpp), H the SDOF's receptance with the mass M or M + 2m/7 and the damping
// c = 2 zeta sqrt(k M). The best is run coupled once: its summary gives an in-band RMS.
TEST(Design, ARandomForceRanksByTheInBandRms) {
  bagdem::testing::TempDir t;
  const fs::path dir = t.path / "case";
  fs::create_directories(dir);
  const double M = 0.02, k = M * std::pow(2 * std::numbers::pi * 20, 2), zeta = 0.02, c = 2 * zeta * std::sqrt(k * M);
  std::ofstream(dir / "case.toml") << bagdem::testing::ball_on_sdof_floor();
  const fs::path out = t.path / "design";
  const std::vector<std::string> args = {
      "design", dir.string(), "--vary", "particles.ball.diameter=\"6 mm\",\"8 mm\"", "--budget", "0.15", "--set",
      "primary.mass=\"" + std::to_string(M) + " kg\"", "--set", "primary.stiffness=\"" + std::to_string(k) + " N/m\"", "--set",
      "excitation={kind=\"random\", rms=\"2 mN\", band=[18, 22], skip=\"0.5 s\"}", "--set", "simulation.duration=\"2 s\"", "--gamma",
      "0.02,0.5", "--amplitudes", "3", "--seeds", "2", "--cycles", "6", "--skip", "2", "--window-time", "0", "--skip-time", "0",
      "--verify", "1", "--verify-seeds", "1", "--out", out.string(), "--jobs", "2"};
  const bagdem::testing::CmdResult r = bagdem::testing::run_bagdem(args, t.path);
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const TextTable design = read_text_table(out / "design.csv");
  const auto& cells = design.rows;
  ASSERT_EQ(cells.size(), 2u);
  auto col = [&](const std::string& name) { return column(design, name); };
  const std::size_t diameter = col("particles.ball.diameter"), objective = col("objective_dB"), dem = col("dem_objective_dB");
  col("reduction_dB_random");
  const int lines = 201;  // 200 intervals over the band
  auto sigma = [&](double mass) {
    double s2 = 0;
    for (int i = 0; i < lines; ++i) s2 += std::norm(sdof_receptance(mass, c, k, 2 * std::numbers::pi * (18 + 4.0 * i / (lines - 1))));
    return std::sqrt(s2 / 2 * 2.0 / lines);  // a = rms sqrt(2 / lines); the rms cancels in the ratio
  };
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const double d = cells[i][diameter] == "6 mm" ? 6e-3 : 8e-3, m = 7800 * std::numbers::pi * d * d * d / 6;
    const double expected = 20 * std::log10(sigma(M) / sigma(M + 2 * m / 7));
    std::printf("  %s ball: predicted %s dB, analytic %.6f dB\n", cells[i][diameter].c_str(), cells[i][objective].c_str(), expected);
    // The map's M_eff is 2/7 m to 0.1%; the lines are the case's (201 over the band, ends included).
    EXPECT_NEAR(std::stod(cells[i][objective]), expected, 1e-4);
  }
  // The heavier ball detunes the resonance toward the band's lower end: less RMS in the band.
  EXPECT_EQ(cells[0][diameter], "8 mm");
  EXPECT_TRUE(std::isfinite(std::stod(cells[0][dem]))) << "the coupled run's in-band RMS";
}

// Bad input is refused before anything runs (exit 2), naming the option or key: a mode the sweep
// does not evaluate, a budget no candidate fits, the default search on a case without a bag, a
// sweep whose band holds no mode (the 0.02-kg SDOF of this stiffness rings at 141 Hz, not 18-22).
TEST(Design, RefusesWhatItCannotSearch) {
  bagdem::testing::TempDir t;
  const fs::path dir = t.path / "case";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << bagdem::testing::ball_on_sdof_floor();
  const std::string vary = "particles.ball.diameter=\"6 mm\",\"8 mm\"";
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"design", dir.string(), "--vary", vary, "--modes", "3"}, "--modes"},
      {{"design", dir.string(), "--vary", vary, "--budget", "0.0001"}, "no candidate is within the budget"},
      {{"design", dir.string()}, "bag.balls"},
      {{"design", dir.string(), "--vary", vary, "--set", "primary.mass=\"0.02 kg\""}, "holds no natural frequency"},
  };
  for (const auto& [args, expected] : cases) {
    const bagdem::testing::CmdResult r = bagdem::testing::run_bagdem(args, t.path);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "design" / "design.csv")) << "nothing written";
}

// The shipped example plans as docs/bag-design.md says: 9 candidates, 7 of them fit the 80-mm bore
// with every start, the fullest 8-mm and 6-mm bags do not (listed, not built).
TEST(Design, TheShippedExamplePlansSevenOfNineCandidates) {
  bagdem::testing::TempDir t;
  const bagdem::testing::CmdResult r = bagdem::testing::run_bagdem(
      {"design", std::string(BAGDEM_CASES_DIR) + "/studies/design", "--budget", "0.1", "--frequencies", "3", "--amplitudes", "5",
       "--out", (t.path / "design").string(), "--check"},
      t.path);
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  std::size_t ranked = 0, refused = 0;
  for (std::size_t at = 0; (at = r.out.find("ranked, map to build", at)) != std::string::npos; ++at) ++ranked;
  for (std::size_t at = 0; (at = r.out.find("does not load", at)) != std::string::npos; ++at) ++refused;
  EXPECT_EQ(ranked, 7u) << r.out;
  EXPECT_EQ(refused, 2u) << r.out;
  EXPECT_NE(r.out.find("9 candidates x 19 positions, modes 1 3, budget 0.1"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(t.path / "design")) << "--check writes nothing";
}
