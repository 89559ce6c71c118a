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
#include "bagdem/error.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/structure/response.hpp"
#include "bagdem/study/design.hpp"
#include "bagdem/study/design_files.hpp"
#include "case_texts.hpp"
#include "support.hpp"

using namespace bagdem;
using namespace bagdem::study;
namespace fs = std::filesystem;

namespace {
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

  const DesignTable design = read_design_csv(out / "design.csv");
  ASSERT_EQ(design.rows.size(), 3u) << "a row per candidate (an SDOF: one place)";
  EXPECT_EQ(design.varied, std::vector<std::string>{"particles.ball.diameter"});
  EXPECT_EQ(design.modes, std::vector<int>{1});
  const double rho = 7800;
  for (const DesignRow& c : design.rows) {
    const std::string& given = c.given.at(0);
    const double d = given == "6 mm" ? 6e-3 : given == "8 mm" ? 8e-3 : 10e-3;
    const double m = rho * std::numbers::pi * d * d * d / 6;
    EXPECT_NEAR(c.added_mass, m, 1e-9 * m);
    if (d == 10e-3) {
      EXPECT_EQ(c.status.kind, Standing::over_budget) << "0.0041 kg is 20% of the structure";
      EXPECT_EQ(c.rank, 0);
      continue;
    }
    ASSERT_EQ(c.status.kind, Standing::ranked);
    EXPECT_EQ(c.at_band_edge, 0) << "the damped peak lies inside the band";
    const double z = zeta * std::sqrt(M / (M + 2 * m / 7));
    const double expected = 20 * std::log10(z * std::sqrt(1 - z * z) / (zeta * std::sqrt(1 - zeta * zeta)));
    std::printf("  %s ball: predicted %.4f dB, analytic %.4f dB\n", given.c_str(), c.objective, expected);
    // 0.01 dB: the damped peak is sampled at 400 frequencies over the band (0.01 Hz apart).
    EXPECT_NEAR(c.objective, expected, 0.01);
    EXPECT_EQ(c.rank, d == 6e-3 ? 1 : 2) << "the lighter ball raises the peak less";
  }
  EXPECT_EQ(design.rows[0].given.at(0), "6 mm");
  EXPECT_EQ(design.rows[0].dem_seeds, 2) << "the best pair run coupled with 2 starts";
  EXPECT_TRUE(std::isfinite(design.rows[0].dem_objective));
  EXPECT_EQ(design.rows[1].dem_seeds, 0);
  EXPECT_TRUE(std::isnan(design.rows[1].dem_objective));

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

  // A bad option of the maps is refused before anything is written (it used to end "design
  // complete", exit 0, with design.csv replaced by "does not load" rows and chosen/ deleted).
  std::vector<std::string> bad = args;
  std::find(bad.begin(), bad.end(), "0.02,0.5")[0] = "0.5,0.02";
  const bagdem::testing::CmdResult refused = bagdem::testing::run_bagdem(bad, t.path);
  EXPECT_EQ(refused.code, 2) << refused.err;
  EXPECT_NE(refused.err.find("--gamma"), std::string::npos) << refused.err;
  // Every map unreadable (each map's damper record damaged): nothing to rank, exit 2, and the
  // earlier design's files stay.
  for (const fs::directory_entry& m : fs::directory_iterator(out / "maps")) std::ofstream(m.path() / "damper.toml") << "garbage = [\n";
  const bagdem::testing::CmdResult none = bagdem::testing::run_bagdem(args, t.path);
  EXPECT_EQ(none.code, 2) << none.err << none.out;
  EXPECT_NE(none.err.find("no candidate's map could be built or read"), std::string::npos) << none.err;
  EXPECT_EQ(bagdem::testing::slurp(out / "design.csv"), before);
  EXPECT_TRUE(fs::exists(out / "chosen" / "case.toml"));
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
  const DesignTable design = read_design_csv(out / "design.csv");
  ASSERT_EQ(design.rows.size(), 2u);
  EXPECT_EQ(design.modes, std::vector<int>{0}) << "a random force's band (reduction_dB_random)";
  const int lines = 201;  // 200 intervals over the band
  auto sigma = [&](double mass) {
    double s2 = 0;
    for (int i = 0; i < lines; ++i) s2 += std::norm(sdof_receptance(mass, c, k, 2 * std::numbers::pi * (18 + 4.0 * i / (lines - 1))));
    return std::sqrt(s2 / 2 * 2.0 / lines);  // a = rms sqrt(2 / lines); the rms cancels in the ratio
  };
  for (const DesignRow& row : design.rows) {
    const std::string& given = row.given.at(0);
    const double d = given == "6 mm" ? 6e-3 : 8e-3, m = 7800 * std::numbers::pi * d * d * d / 6;
    const double expected = 20 * std::log10(sigma(M) / sigma(M + 2 * m / 7));
    std::printf("  %s ball: predicted %.6f dB, analytic %.6f dB\n", given.c_str(), row.objective, expected);
    // The map's M_eff is 2/7 m to 0.1%; the lines are the case's (201 over the band, ends included).
    EXPECT_NEAR(row.objective, expected, 1e-4);
  }
  // The heavier ball detunes the resonance toward the band's lower end: less RMS in the band.
  EXPECT_EQ(design.rows[0].given.at(0), "8 mm");
  EXPECT_TRUE(std::isfinite(design.rows[0].dem_objective)) << "the coupled run's in-band RMS";
}

// design.csv is one type: every status and figure comes back as written (an empty cell as NaN), and
// a damaged table is refused naming the file, the column and the cell.
TEST(DesignTable, ComesBackAsWrittenAndRefusesADamagedOne) {
  bagdem::testing::TempDir t;
  DesignTable a{{"bag.balls.diameter", "bag.radius"}, {1, 3}, {}};
  const std::vector<Status> statuses = {{Standing::ranked, ""},
                                        {Standing::over_budget, ""},
                                        {Standing::does_not_load, "bag.radius = 1 mm: too small, \"quoted\", with a comma"},
                                        {Standing::no_map, ""},
                                        {Standing::other_damper, "8 mm balls"},
                                        {Standing::outside_map, "above Gamma 20"},
                                        {Standing::mode_not_in_stepped_sine, "3"}};
  for (std::size_t i = 0; i < statuses.size(); ++i) {
    DesignRow r = row({10.5 + i, 7.25}, 0.01 * (i + 1));
    r.status = statuses[i], r.given = {"\"8 mm\"", std::to_string(i) + " mm"};
    r.position = 0.1 * i, r.attach = NAN, r.mass_ratio = 0.05, r.rank = statuses[i].ranked() ? 1 : 0, r.pareto = i == 0;
    r.at_band_edge = 1, r.interpolation_db = i == 0 ? NAN : 0.25, r.dem_seeds = 3, r.dem_db = {11, NAN}, r.dem_db_ci95 = {0.5, NAN};
    r.dem_objective = 11, r.dem_objective_ci95 = 0.5, r.map = "map-00" + std::to_string(i);
    a.rows.push_back(r);
  }
  const fs::path path = t.path / "design.csv";
  write_design_csv(path, a);
  const DesignTable b = read_design_csv(path);
  EXPECT_EQ(b.varied, a.varied);
  EXPECT_EQ(b.modes, a.modes);
  ASSERT_EQ(b.rows.size(), a.rows.size());
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    const DesignRow &x = a.rows[i], &y = b.rows[i];
    EXPECT_EQ(y.status.kind, x.status.kind) << i;
    EXPECT_EQ(y.status.why, x.status.why) << i;
    EXPECT_EQ(y.given, x.given);
    EXPECT_EQ(y.rank, x.rank);
    EXPECT_EQ(y.pareto, x.pareto);
    EXPECT_EQ(y.db, x.db);
    EXPECT_EQ(y.db_hi, x.db_hi);
    EXPECT_EQ(y.objective_lo, x.objective_lo);
    EXPECT_NEAR(y.position, x.position, 1e-9);
    EXPECT_TRUE(std::isnan(y.attach));
    EXPECT_EQ(std::isnan(y.interpolation_db), std::isnan(x.interpolation_db));
    EXPECT_EQ(y.dem_db[0], 11);
    EXPECT_TRUE(std::isnan(y.dem_db[1]));
    EXPECT_EQ(y.map, x.map);
  }
  // A table of pairs of bags (--dampers 2): the second bag's columns come back too.
  DesignTable p = a;
  p.pairs = true;
  for (std::size_t i = 0; i < p.rows.size(); ++i) {
    DesignRow& r = p.rows[i];
    r.pair = true, r.given2 = {"\"6 mm\"", "9 mm"}, r.position2 = 0.9, r.attach2 = 0.54, r.map2 = "map-9" + std::to_string(i);
  }
  p.rows[3].status = {Standing::screened, "100 frequencies a band, not among the best 20"};
  write_design_csv(t.path / "design-pairs.csv", p);
  const DesignTable q = read_design_csv(t.path / "design-pairs.csv");
  ASSERT_TRUE(q.pairs);
  EXPECT_EQ(q.varied, p.varied);
  ASSERT_EQ(q.rows.size(), p.rows.size());
  for (std::size_t i = 0; i < p.rows.size(); ++i) {
    EXPECT_TRUE(q.rows[i].pair);
    EXPECT_EQ(q.rows[i].given2, p.rows[i].given2);
    EXPECT_EQ(q.rows[i].position2, 0.9);
    EXPECT_EQ(q.rows[i].attach2, 0.54);
    EXPECT_EQ(q.rows[i].map2, p.rows[i].map2);
    EXPECT_EQ(q.rows[i].status.text(), p.rows[i].status.text());
    EXPECT_EQ(q.rows[i].db, p.rows[i].db);
  }
  // Damaged: a cell that is not a number, a status design never writes, a column missing.
  const std::string good = bagdem::testing::slurp(path);
  auto refused = [&](const std::string& text, const std::string& column) {
    std::ofstream(path) << text;
    try {
      (void)read_design_csv(path);
      ADD_FAILURE() << "read without a word:\n" << text;
    } catch (const bagdem::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(column), std::string::npos) << e.what();
    }
  };
  std::string text = good;
  refused(text.replace(text.find("0.01,"), 5, "lots,"), "added_mass");
  text = good;
  refused(text.replace(text.find("over budget"), 11, "over bud"), "status");
  text = good;
  refused(text.replace(text.find("pareto [1],"), 11, ""), "design.csv");
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
