// The speed/accuracy trade (`bagdem trade`, study/trade.hpp) and the fidelity presets:
//  - the ladder of a case: the reference (every knob at its most accurate), the noise floor (the
//    reference with another seed), one knob changed per rung, the presets; knobs a case does not
//    use are left out;
//  - a trade run through the binary on one ball shaken in a box: trade.csv has a row per rung, the
//    reference's errors are zero, the speed-up is the reference's wall time over the rung's (from
//    point.done), the softened rungs' Hertz contact duration scales as E^(-2/5) (Johnson 1985,
//    11.24), and each error is recomputed from the rung's own reduced.csv;
//  - --fidelity fast halves the steps per contact: a contact-limited step doubles.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/study/study.hpp"
#include "bagdem/study/trade.hpp"
#include "case_texts.hpp"
#include "support.hpp"

using namespace bagdem;
using bagdem::testing::CmdResult;
using bagdem::testing::run_bagdem;
using bagdem::testing::TempDir;
namespace fs = std::filesystem;

namespace {

// One 4-mm steel ball in a 10-mm box shaken at 2 mm, 30 Hz under gravity: it hits the side walls
// twice a cycle. Three whole cycles are reduced.
const std::string kOneBall = bagdem::testing::steel_scene("0.1 s")
                                .set("simulation", {{"settle", "0.01 s"}, {"seed", 3}})
                                .box("steel", bagdem::testing::vec("0 mm", "0 mm", "0 mm"),
                                     bagdem::testing::vec("10 mm", "10 mm", "10 mm"))
                                .harmonic("2 mm", "30 Hz", "[1, 0, 0]")
                                .placed("balls", "steel", "4 mm", "[[0.005, 0.005, 0.002]]")
                                .set("output", {{"frame_interval", "10 ms"}, {"cavity_interval", "0.1 ms"}});

std::string write_case(const TempDir& t) {
  const fs::path dir = t.path / "case";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << kOneBall;
  return dir.string();
}

double number_in(const std::string& cell) { return cell.empty() ? NAN : std::stod(cell); }

std::size_t column(const study::Table& t, const std::string& name) {
  for (std::size_t c = 0; c < t.columns.size(); ++c)
    if (t.columns[c] == name) return c;
  ADD_FAILURE() << "no column " << name;
  return 0;
}

}  // namespace

TEST(Trade, LadderChangesOneKnobAtATimeFromTheReference) {
  TempDir t;
  const std::string dir = write_case(t);
  const auto ladder = study::trade_ladder(dir, {}, {});
  std::vector<std::string> names;
  for (const auto& r : ladder) names.push_back(r.name);
  // No bag (no film knob), no rolling resistance, no sweep (no steady knob).
  EXPECT_EQ(names, (std::vector<std::string>{"reference", "reference, seed+1", "timestep x1", "timestep x2", "stiffness x0.1",
                                             "stiffness x0.01", "tangential off", "output x4", "preset balanced", "preset fast"}));
  const std::vector<std::string> ref = {"simulation.timestep_safety=0.1", "simulation.steps_per_contact=80",
                                        "materials.steel.youngs_modulus=2e+11", "output.cavity_interval=0.0001"};
  const Scene base = load_case(dir);
  EXPECT_DOUBLE_EQ(base.output.cavity_interval, 1e-4);
  EXPECT_EQ(ladder[0].sets, ref);
  EXPECT_EQ(ladder[1].sets.back(), "simulation.seed=4");
  EXPECT_EQ(ladder[4].sets, (std::vector<std::string>{"simulation.timestep_safety=0.1", "simulation.steps_per_contact=80",
                                                      "materials.steel.youngs_modulus=2e+10", "output.cavity_interval=0.0001"}));
  EXPECT_EQ(ladder[6].sets, (std::vector<std::string>{"simulation.timestep_safety=0.1", "simulation.steps_per_contact=80",
                                                      "materials.steel.youngs_modulus=2e+11", "interactions.default.friction=0",
                                                      "output.cavity_interval=0.0001"}));
  EXPECT_TRUE(ladder[8].sets.empty()) << "balanced is the case as written";
  // --knobs restricts the ladder; an unknown knob is refused.
  EXPECT_EQ(study::trade_ladder(dir, {}, {"stiffness"}).size(), 6u);
  const auto presets_only = study::trade_ladder(dir, {}, {"none"});  // reference, seed+1, balanced, fast
  ASSERT_EQ(presets_only.size(), 4u);
  EXPECT_EQ(presets_only[2].name, "preset balanced");
  EXPECT_THROW(study::trade_ladder(dir, {}, {"mesh"}), InputError);
  EXPECT_THROW(study::fidelity_sets(dir, {}, "fastest"), InputError);
}

TEST(Trade, FastPresetDoublesAContactLimitedStep) {
  TempDir t;
  const std::string dir = write_case(t);
  const Scene base = load_case(dir);
  const Scene fast = load_case(dir, study::fidelity_sets(dir, {}, "fast"));
  const Scene ref = load_case(dir, study::fidelity_sets(dir, {}, "reference"));
  ASSERT_NE(base.dt_reason.find("contact time limits"), std::string::npos) << base.dt_reason;
  EXPECT_NEAR(fast.dt / base.dt, 2.0, 1e-9);
  EXPECT_NEAR(ref.dt / base.dt, 0.5, 1e-9);
  // Through the command line: check --fidelity prints the fast step.
  const CmdResult r = run_bagdem({"check", dir, "--fidelity", "fast"}, t.path);
  EXPECT_EQ(r.code, 0) << r.err;
  char expect[64];
  std::snprintf(expect, sizeof expect, "time step   %.4g s", fast.dt);
  EXPECT_NE(r.out.find(expect), std::string::npos) << expect << "\n" << r.out;
}

TEST(Trade, RunsTheLadderAndComparesEachRungWithTheReference) {
  TempDir t;
  const std::string dir = write_case(t);
  const fs::path out = t.path / "trade";
  const CmdResult r = run_bagdem({"trade", dir, "--knobs", "stiffness", "--out", out.string(), "--jobs", "2"}, t.path);
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("trade complete: 6 runs"), std::string::npos) << r.out;
  const study::Table tr = study::read_csv((out / "trade.csv").string());
  ASSERT_EQ(tr.rows.size(), 6u);
  const std::size_t c_rung = column(tr, "rung"), c_wall = column(tr, "wall_time [s]"), c_up = column(tr, "speedup [1]"),
                    c_tc = column(tr, "contact_time [s]"), c_e = column(tr, "energy_per_cycle [J]"),
                    c_ee = column(tr, "energy_per_cycle_error [1]"), c_cb = column(tr, "Cb_over_Mbw [1]"),
                    c_cbe = column(tr, "Cb_over_Mbw_error [1]"), c_m = column(tr, "M_eff_ratio [1]");
  EXPECT_EQ(tr.rows[0][c_rung], "reference");
  EXPECT_EQ(number_in(tr.rows[0][c_ee]), 0.0);
  EXPECT_EQ(number_in(tr.rows[0][c_cbe]), 0.0);
  const double wall0 = number_in(tr.rows[0][c_wall]), tc0 = number_in(tr.rows[0][c_tc]);
  const double e0 = number_in(tr.rows[0][c_e]), cb0 = number_in(tr.rows[0][c_cb]), m0 = number_in(tr.rows[0][c_m]);
  ASSERT_GT(e0, 0) << "the ball dissipates energy every cycle";
  const std::map<std::string, double> stiffness = {{"stiffness x0.1", 0.1}, {"stiffness x0.01", 0.01}};
  for (std::size_t k = 0; k < tr.rows.size(); ++k) {
    const auto& row = tr.rows[k];
    const std::string point = (out / ("point-00" + std::to_string(k))).string();
    // Speed-up from the runs' own wall times.
    std::ifstream done(point + "/point.done");
    std::string line;
    double wall = NAN;
    while (std::getline(done, line))
      if (line.rfind("wall_time = ", 0) == 0) wall = std::stod(line.substr(12));
    EXPECT_NEAR(number_in(row[c_wall]), wall, 1e-6 * wall) << row[c_rung];
    EXPECT_NEAR(number_in(row[c_up]), wall0 / wall, 1e-6) << row[c_rung];
    // Errors recomputed from the rung's reduced.csv (prescribed motion: its first row).
    const study::Table red = study::read_csv(point + "/reduced.csv");
    ASSERT_FALSE(red.rows.empty()) << row[c_rung];
    const double e = number_in(red.rows[0][column(red, "energy_per_cycle [J]")]);
    const double cb = number_in(red.rows[0][column(red, "Cb_over_Mbw [1]")]);
    EXPECT_NEAR(number_in(row[c_ee]), std::abs(e - e0) / e0, 1e-6) << row[c_rung];
    EXPECT_NEAR(number_in(row[c_cbe]), std::abs(cb - cb0) / std::hypot(cb0, m0), 1e-6) << row[c_rung];
    if (stiffness.count(row[c_rung])) {
      EXPECT_NEAR(number_in(row[c_tc]) / tc0, std::pow(stiffness.at(row[c_rung]), -0.4), 1e-6) << row[c_rung];
    }
  }
}

TEST(Trade, SweepFidelityPresetReachesEveryPoint) {
  TempDir t;
  const std::string dir = write_case(t);
  study::SweepArgs a;
  a.dir = dir;
  a.vary = {"interactions.default.restitution=0.4,0.6"};
  a.fidelity = "fast";
  const study::Plan plan = study::make_plan(study::read_spec(a));
  ASSERT_EQ(plan.points.size(), 2u);
  for (const study::Point& p : plan.points) {
    EXPECT_NE(std::find(p.sets.begin(), p.sets.end(), "simulation.steps_per_contact=20"), p.sets.end()) << p.name;
    EXPECT_NE(std::find(p.sets.begin(), p.sets.end(), "simulation.timestep_safety=0.4"), p.sets.end()) << p.name;
  }
  // study.toml takes it too, and refuses another name.
  std::ofstream(t.path / "study.toml") << "case = \"case\"\nfidelity = \"fastest\"\n[vary]\n\"simulation.seed\" = [1, 2]\n";
  study::SweepArgs b;
  b.dir = t.path.string();
  EXPECT_THROW(study::read_spec(b), InputError);
}
