// The extremes of the parameter space (docs/verification.md): each point of the matrix either runs
// stably or is refused before running with a message that names the limit and what to change.
//
// "Runs stably" is checked through the command line (`bagdem run`, its summary.json):
//  - the run completes (exit 0): no NaN, no ball out of the cavity or through the film, no overlap
//    beyond simulation.max_overlap (the run guards stop the run otherwise, exit 3);
//  - the energy is bounded by the work put in: every dissipation channel >= 0 and the budget closes,
//    W_cavity + W_gravity = (K + U) - (K0 + U0) + D, within 1% of the work (energy_balance_error);
//  - a rerun at half the time step gives the same total dissipation D and cavity work W within a
//    stated tolerance (the runs are short, so chaos has not yet decorrelated them).
// "Refused" means exit 2 before any output, with a message holding the key and the limit.
//
// Suite Extremes runs the cheap points in tools/test (each a few balls for 10-30 ms); suite
// ExtremesHeavy (disabled here) the expensive ones, run by tools/extremes: 20 000 balls, and the
// pipe with its bag at Gamma 50 and at a 50% mass ratio.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "bagdem/reduce/summary.hpp"
#include "bag_support.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using bagdem::testing::CmdResult;
using bagdem::testing::run_bagdem;
using bagdem::testing::slurp;
using bagdem::testing::TempDir;
using namespace bagdem::testing;

namespace {

// A box of 4-mm steel balls shaken along x at 1 mm, 30 Hz (Gamma 3.6) under gravity: the PD-box
// scene, small; `balls` are the [particles.balls] keys beside material and diameter.
CaseText box_scene(const CaseText::Keys& balls) {
  return steel_scene("0.02 s")
      .set("simulation", {{"settle", "0.01 s"}, {"seed", 7}})
      .box("steel", vec("0 mm", "0 mm", "0 mm"), vec("21 mm", "21 mm", "30 mm"))
      .harmonic("1 mm", "30 Hz", "[1, 0, 0]")
      .set("output", {{"frame_interval", "5 ms"}, {"energy", "true"}})
      .set("particles.balls", {{"material", quoted("steel")}, {"diameter", "4 mm"}})
      .set("particles.balls", balls);
}
const std::string kBox = box_scene({{"count", 8}, {"fill", quoted("lattice")}});
// The box with balls at given positions ([particles.balls] positions = ...).
std::string box_with(const std::string& positions) { return box_scene({{"positions", positions}}); }

// The same balls (20 GPa) on a mass-spring primary (20 Hz, 0.1 kg) driven at resonance.
const std::string kSdof = box_scene({{"count", 8}, {"fill", quoted("lattice")}})
                              .set("simulation", "duration", "0.05 s")
                              .steel("20 GPa")
                              .erase("cavity.motion")
                              .sdof("0.1 kg", "1579 N/m", 0.02)
                              .set("primary", {{"direction", "[1, 0, 0]"}, {"axis", "[0, 1, 0]"}})
                              .set("excitation", {{"kind", quoted("harmonic")}, {"amplitude", "1 N"}, {"frequency", "20 Hz"}});

// A bag of 20 balls in a box shaken at 2 mm, 20 Hz (cases/box-beanbag, small), with the bag
// suites' materials.
const std::string kBag = bagdem::testing::bag_scene("0.02 s", 7)
                             .set("simulation", "settle", "0.01 s")
                             .interactions("steel-ldpe", 0.3, 0.4)
                             .box("steel", vec("-20 mm", "-12 mm", "-12 mm"), vec("20 mm", "12 mm", "12 mm"))
                             .harmonic("2 mm", "20 Hz", "[0, 1, 0]")
                             .capsule_bag("9 mm", 200, 20)
                             .set("bag.film", {{"damping_ratio", 0.05}, {"mass_scaling", 10}})
                             .bag_string("tail", vec("-20 mm", "0 mm", "0 mm"), "200 N/m", "0.05 N s/m")
                             .bag_string("head", vec("20 mm", "0 mm", "0 mm"), "200 N/m", "0.05 N s/m")
                             .set("output", {{"frame_interval", "5 ms"}, {"energy", "true"}});

// What each check reads of summary.json: the step, the balance, the cavity's work, the dissipation.
struct Figures {
  double dt = NAN, balance = NAN, work = NAN, dissipated = 0;
  std::vector<double> channels;
};

Figures read_figures(const fs::path& out) {
  const bagdem::Summary s = bagdem::read_summary(out / "summary.json");
  Figures r;
  r.dt = s.dt, r.balance = s.energy_balance_error;
  if (!s.energy) return r;  // no channels: the checks below fail
  r.work = s.energy->work_cavity;
  for (double d : {s.energy->dissipated_normal, s.energy->dissipated_tangential, s.energy->dissipated_rolling, s.energy->dissipated_damping}) {
    r.channels.push_back(d);
    if (!std::isnan(d)) r.dissipated += d;
  }
  return r;
}

struct Extreme {
  std::string name;
  std::string base;
  std::vector<std::string> sets;
  std::string refused;     // empty: must run; else the refusal names this key
  std::string limit = "";  // ... and this text (the limit)
  double tolerance = 0.05; // of D and W against the rerun at half the step
};

std::string describe(const Extreme& x) {
  std::string s = x.name + " (";
  for (const std::string& k : x.sets) s += " --set " + k;
  return s + " )";
}

// Runs one point and checks it as the header says; prints a summary line for tools/extremes.
void check_extreme(const Extreme& x) {
  TempDir tmp;
  const fs::path dir = tmp.path / "case";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << x.base;
  auto run = [&](const fs::path& out, std::vector<std::string> sets) {
    std::vector<std::string> args = {"run", dir.string(), "--out", out.string(), "--quiet", "--threads", "1"};
    for (const std::string& s : sets) args.insert(args.end(), {"--set", s});
    return run_bagdem(args, tmp.path);
  };
  const fs::path out = tmp.path / "out";
  const CmdResult r = run(out, x.sets);
  if (!x.refused.empty()) {
    EXPECT_EQ(r.code, 2) << describe(x) << " must be refused\n" << r.err;
    EXPECT_NE(r.err.find("key '" + x.refused + "'"), std::string::npos) << describe(x) << ": " << r.err;
    EXPECT_NE(r.err.find(x.limit), std::string::npos) << describe(x) << ": the message lacks '" << x.limit << "': " << r.err;
    EXPECT_FALSE(fs::exists(out / "results.h5")) << describe(x) << ": a refused run writes nothing";
    std::printf("extreme %-28s refused: %s", x.name.c_str(), r.err.c_str());
    return;
  }
  ASSERT_EQ(r.code, 0) << describe(x) << " must run stably\n" << r.err;
  const Figures a = read_figures(out);
  // Every channel is in summary.json and none is negative (a missing or NaN one fails here).
  EXPECT_EQ(a.channels.size(), 4u) << describe(x) << ": no energy budget";
  for (double d : a.channels) EXPECT_GE(d, 0) << describe(x) << ": a dissipation channel is negative or missing";
  EXPECT_LT(std::abs(a.balance), 1e-2) << describe(x) << ": the energy budget does not close";

  std::vector<std::string> finer = x.sets;
  char dt[64];
  std::snprintf(dt, sizeof dt, "simulation.timestep=%.6e", 0.5 * a.dt);
  finer.emplace_back(dt);
  const fs::path out2 = tmp.path / "out-half-step";
  const CmdResult r2 = run(out2, finer);
  ASSERT_EQ(r2.code, 0) << describe(x) << " at half the step\n" << r2.err;
  const Figures b = read_figures(out2);
  // Differences on the scale of the energy exchanged (a bag barely shaken does little net work).
  const double scale = std::max(std::abs(b.work), b.dissipated);
  ASSERT_GT(scale, 0) << describe(x);
  EXPECT_LT(std::abs(a.dissipated - b.dissipated) / scale, x.tolerance)
      << describe(x) << ": dissipation " << a.dissipated << " J against " << b.dissipated << " J at half the step";
  EXPECT_LT(std::abs(a.work - b.work) / scale, x.tolerance)
      << describe(x) << ": cavity work " << a.work << " J against " << b.work << " J at half the step";
  std::printf("extreme %-28s runs: dt %.3g s, balance %.1e, D %.4g J (half step: %+.2f%%), W %.4g J (%+.2f%%)\n",
              x.name.c_str(), a.dt, a.balance, a.dissipated, 100 * (a.dissipated / b.dissipated - 1), a.work,
              100 * (a.work / b.work - 1));
}

}  // namespace

TEST(Extremes, RestitutionNearZeroAndNearOne) {
  check_extreme({"restitution 0.01", kBox, {"interactions.default.restitution=0.01", "particles.balls.count=3"}, ""});
  check_extreme({"restitution 0.999", kBox, {"interactions.default.restitution=0.999"}, ""});
  check_extreme({"restitution 0", kBox, {"interactions.default.restitution=0"}, "interactions.default.restitution", "(0, 1]"});
}

TEST(Extremes, YoungsModulusFrom1MPaTo400GPa) {
  check_extreme({"E 1 MPa", kBox, {"materials.steel.youngs_modulus=\"1 MPa\""}, ""});
  check_extreme({"E 400 GPa", kBox, {"materials.steel.youngs_modulus=\"400 GPa\""}, ""});
}

TEST(Extremes, BallDiameterFromHalfAMillimetreTo20mm) {
  check_extreme({"d 0.5 mm", kBox, {"particles.balls.diameter=\"0.5 mm\"", "particles.balls.count=20"}, ""});
  check_extreme({"d 20 mm, one ball", kBox, {"particles.balls.diameter=\"20 mm\"", "particles.balls.count=1"}, ""});
}

TEST(Extremes, OneBallAndGammaFifty) {
  check_extreme({"one ball", kBox, {"particles.balls.count=1"}, ""});
  // Gamma = X w^2 / g = 50: 13.8 mm at 30 Hz.
  check_extreme({"Gamma 50 (horizontal)", kBox, {"cavity.motion.amplitude=\"13.8 mm\""}, "", "", 0.1});
  check_extreme({"Gamma 50 (vertical)", kBox, {"cavity.motion.amplitude=\"13.8 mm\"", "cavity.motion.direction=[0,0,1]"}, "", "", 0.1});
}

TEST(Extremes, ZeroGravityAndZeroClearance) {
  check_extreme({"zero gravity", kBox, {"simulation.gravity=[0,0,0]"}, ""});
  // One ball touching both walls of a 4-mm box (no clearance along x; the box moves it rigidly).
  check_extreme({"zero clearance", box_with("[[0.002, 0.01, 0.002]]"), {"cavity.max=[\"4 mm\",\"21 mm\",\"30 mm\"]"}, ""});
}

TEST(Extremes, InitialOverlapsWithinTheToleranceRunBeyondAreRefused) {
  check_extreme({"initial overlap 0.05%", box_with("[[0.005, 0.01, 0.002], [0.008999, 0.01, 0.002]]"), {}, ""});
  check_extreme({"initial overlap 75%", box_with("[[0.005, 0.01, 0.002], [0.0075, 0.01, 0.002]]"), {},
                 "particles.balls.positions", "simulation.initial_overlap"});
}

TEST(Extremes, MassRatioFiftyPercent) {
  // 8 balls of 4 mm are 2.1 g; a 4.2-g primary makes the ratio 50%.
  check_extreme({"mass ratio 50%", kSdof, {"primary.mass=\"4.18 g\"", "primary.stiffness=\"66 N/m\""}, "", "", 0.1});
}

TEST(Extremes, BagClearanceZeroAndLargerThanTheBag) {
  // The bag's film at rest 1 mm from the box's side walls (radius 11 mm in a 24-mm box) ...
  check_extreme({"bag, clearance ~0", kBag, {"bag.radius=\"11 mm\""}, "", "", 0.1});
  // ... and a small bag (radius 5 mm, 2 balls across) in a box 5 times wider.
  check_extreme({"bag, clearance > bag", kBag,
                 {"bag.radius=\"5 mm\"", "bag.balls.count=6", "cavity.min=[\"-20 mm\",\"-30 mm\",\"-12 mm\"]",
                  "cavity.max=[\"20 mm\",\"30 mm\",\"12 mm\"]"},
                 "", "", 0.1});
  // A bag that does not fit is refused.
  check_extreme({"bag wider than the cavity", kBag, {"bag.radius=\"13 mm\""}, "bag", "does not fit the cavity"});
}

TEST(Extremes, FilmMuchStifferAndMuchSofter) {
  check_extreme({"film 100x stiffer", kBag, {"materials.ldpe.youngs_modulus=\"25 GPa\""}, "", "", 0.1});
  check_extreme({"film 100x softer", kBag, {"materials.ldpe.youngs_modulus=\"2.5 MPa\""}, "", "", 0.1});
}

// ---- tools/extremes: the expensive points (disabled in tools/test) ------------------------------

TEST(ExtremesHeavy, DISABLED_TwentyThousandBalls) {
  // 20 000 balls of 4 mm in a 200 x 200 mm box: the N = 10 000 PD-box bed, twice.
  check_extreme({"20 000 balls", kBox,
                 {"particles.balls.count=20000", "cavity.max=[\"200 mm\",\"200 mm\",\"60 mm\"]", "simulation.settle=\"0.01 s\"",
                  "simulation.duration=\"0.005 s\""},
                 "", "", 0.1});
}

TEST(ExtremesHeavy, DISABLED_BagAtGammaFifty) {
  // Gamma = X w^2 / g = 50 at 20 Hz: X = 31 mm, across the box.
  check_extreme({"bag at Gamma 50", kBag,
                 {"cavity.motion.amplitude=\"31 mm\"", "simulation.duration=\"0.05 s\""}, "", "", 0.1});
}

TEST(ExtremesHeavy, DISABLED_BagOfTwentyThousandBalls) {
  // 20 000 balls of 1 mm (82 g, 17 cm^3 of bed) in a bag of radius 18 mm and a box 6 mm wider
  // all round: the film's contact candidates at scale.
  check_extreme({"bag of 20 000 balls", kBag,
                 {"bag.balls.count=20000", "bag.balls.diameter=\"1 mm\"", "bag.radius=\"18 mm\"", "bag.triangles=2000",
                  "cavity.min=[\"-50 mm\",\"-24 mm\",\"-24 mm\"]", "cavity.max=[\"50 mm\",\"24 mm\",\"24 mm\"]",
                  "simulation.settle=\"0.002 s\"", "simulation.duration=\"0.003 s\""},
                 "", "", 0.1});
}
