// The automatic time step (src/case/timestep.cpp) against its documented rule, recomputed here
// from the formulas of include/bagdem/contact/hertz_theory.hpp:
//   dt = min( timestep_safety x Rayleigh time of the smallest particle of each material,
//             Hertz contact time at the expected speed / (steps_per_contact max(1, 1.5 a)),
//             a = sqrt(5)|beta| (the damping time is resolved too when damping dominates),
//             half the critical step of the stiffest contact (normal; tangential with 2/7 m*) )
// over every pair that can occur (particle-particle between materials with particles, particle-wall
// with the wall materials); expected speed (auto) = 2 x cavity peak speed + free-fall speed over the
// cavity's extent along gravity + the largest initial particle speed (at least 0.01 m/s).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "bagdem/case/load_case.hpp"
#include "bagdem/contact/hertz_theory.hpp"
#include "bagdem/contact/restitution.hpp"
#include "bagdem/error.hpp"

#include "case_texts.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using bagdem::testing::CaseText;
using bagdem::testing::quoted;
using bagdem::testing::TempDir;

namespace {

constexpr double kPi = std::numbers::pi;


// load_case() on a temporary case directory holding `toml`.
bagdem::Scene load(const std::string& toml, const std::vector<std::string>& overrides = {}) {
  TempDir tmp;
  std::ofstream(tmp.path / "case.toml") << toml;
  return bagdem::load_case(tmp.path.string(), overrides);
}

// ---- the rule, independently --------------------------------------------------------------------

struct Mat {
  double rho, E, nu;
};

// The Hertz formulas, typed again from hertz_theory.hpp's header comment.
double contact_time(double m, double R, double Es, double v) {
  return 2.87 * std::pow(m * m / (R * Es * Es * v), 0.2);
}
double max_overlap(double m, double R, double Es, double v) {
  return std::pow(15.0 * m * v * v / (16.0 * Es * std::sqrt(R)), 0.4);
}
double rayleigh_time(double R, const Mat& a) {
  const double G = a.E / (2 * (1 + a.nu));
  return kPi * R * std::sqrt(a.rho / G) / (0.1631 * a.nu + 0.8766);
}
// Critical step of velocity Verlet with the dashpot on the end-of-step (predicted) velocity: the
// half-step formula 2/w (sqrt(1+z^2) - z) with the damping ratio doubled (linear stability analysis).
double critical_step(double w, double z) { return 2.0 / w * (std::sqrt(1 + 4 * z * z) - 2 * z); }
double e_star(const Mat& a, const Mat& b) {
  return 1.0 / ((1 - a.nu * a.nu) / a.E + (1 - b.nu * b.nu) / b.E);
}
double g_star(const Mat& a, const Mat& b) {
  return 1.0 / (2.0 * (2 - a.nu) * (1 + a.nu) / a.E + 2.0 * (2 - b.nu) * (1 + b.nu) / b.E);
}
double sphere_mass(const Mat& a, double r) { return a.rho * 4.0 / 3.0 * kPi * r * r * r; }

struct Expected {
  double rayleigh = 1e300;  // smallest Rayleigh time (not yet x safety)
  double contact = 1e300;   // smallest contact time / steps_per_contact
  double critical = 1e300;  // smallest critical step
  double dt(double safety) const { return std::min({safety * rayleigh, contact, 0.5 * critical}); }
};

// rmin[a] = smallest radius of material a's particles (0: none); walls of material `wall`;
// every pair with restitution e; friction > 0 anywhere -> tangential on.
Expected expected(const std::vector<Mat>& mats, const std::vector<double>& rmin, int wall, double e,
                  bool tangential, double per_contact, double v) {
  Expected x;
  const double zeta = 0.5 * 2.0 * std::sqrt(5.0 / 6.0) * bagdem::clamped_beta(e);
  auto consider = [&](const Mat& a, const Mat& b, double R, double m) {
    const double Es = e_star(a, b), Gs = g_star(a, b);
    // Heavily damped contacts resolve the viscous time too: a = sqrt(5)|beta| = sqrt(6)/2 * zeta * 2.
    const double damp = std::sqrt(5.0) * bagdem::clamped_beta(e);
    x.contact = std::min(x.contact, contact_time(m, R, Es, v) / (per_contact * std::max(1.0, 1.5 * damp)));
    const double delta = max_overlap(m, R, Es, v);
    x.critical = std::min(x.critical, critical_step(std::sqrt(2 * Es * std::sqrt(R * delta) / m), zeta));
    if (tangential)
      x.critical = std::min(x.critical, critical_step(std::sqrt(3.5 * 8 * Gs * std::sqrt(R * delta) / m),
                                                      std::sqrt(3.5) * zeta));  // tangential mass 2/7 m*
  };
  for (std::size_t a = 0; a < mats.size(); ++a) {
    if (rmin[a] == 0) continue;
    const double ra = rmin[a], ma = sphere_mass(mats[a], ra);
    x.rayleigh = std::min(x.rayleigh, rayleigh_time(ra, mats[a]));
    for (std::size_t b = 0; b < mats.size(); ++b) {
      if (rmin[b] > 0) {
        const double rb = rmin[b], mb = sphere_mass(mats[b], rb);
        consider(mats[a], mats[b], ra * rb / (ra + rb), ma * mb / (ma + mb));
      }
      if (static_cast<int>(b) == wall) consider(mats[a], mats[b], ra, ma);
    }
  }
  return x;
}

// A double as TOML text that reads back to the same value.
std::string exact(double v) {
  std::ostringstream s;
  s << std::setprecision(17) << v;
  return s.str();
}

void expect_rel(double got, double want, const char* what) {
  EXPECT_NEAR(got, want, 1e-12 * std::abs(want)) << what << ": got " << got << ", want " << want;
}

// ---- cases ----------------------------------------------------------------------------------

const Mat kSteel{7800, 200e9, 0.3};

// Steel balls of 4 mm in a 20 mm box (one material), gravity -z; `sim` are more [simulation] keys.
// (Restitution and friction are written as std::to_string writes them: 0.500000.)
std::string steel_case(const CaseText::Keys& sim = {}, double restitution = 0.5, double friction = 0.0,
                       const std::string& gravity = "[0, 0, -9.81]") {
  return CaseText()
      .simulation("0.01", gravity)
      .set("simulation", sim)
      .material("steel", 7800, "200e9", 0.3)
      .interactions(std::to_string(restitution), std::to_string(friction))
      .box("steel", "[0, 0, 0]", "[0.02, 0.02, 0.02]")
      .balls("balls", "steel", "0.004", 5)
      .set("particles.balls", "seed", 1);
}

TEST(Timestep, HertzFormulasAsInHeader) {
  // The formulas typed in this file are those of hertz_theory.hpp.
  const double m = 2.6e-4, R = 1e-3, Es = 1.1e11, v = 0.7;
  expect_rel(contact_time(m, R, Es, v), bagdem::hertz::contact_time(m, R, Es, v), "contact time");
  expect_rel(max_overlap(m, R, Es, v), bagdem::hertz::max_overlap(m, R, Es, v), "max overlap");
  expect_rel(rayleigh_time(2e-3, kSteel), bagdem::hertz::rayleigh_time(2e-3, 7800, 200e9, 0.3), "Rayleigh");
  expect_rel(critical_step(3e6, 0.2), bagdem::hertz::critical_step(3e6, 0.2), "critical step");
  // Rayleigh time of a 4 mm steel ball, a textbook number (~2.16 us).
  EXPECT_NEAR(rayleigh_time(2e-3, kSteel), 2.1618e-6, 1e-9);
}

TEST(Timestep, ContactTimeLimitsUnderGravity) {
  const bagdem::Scene s = load(steel_case());
  // Expected speed: free fall over the 20 mm height (nothing else moves).
  const double v = std::sqrt(2 * 9.81 * 0.02);
  expect_rel(s.expected_speed, v, "expected speed");
  const Expected x = expected({kSteel}, {2e-3}, 0, 0.5, false, 40, v);
  expect_rel(s.dt, x.dt(0.2), "dt");
  expect_rel(s.dt_critical, x.critical, "critical step");
  ASSERT_EQ(x.dt(0.2), x.contact) << "test set-up: the contact time should limit here";
  EXPECT_NE(s.dt_reason.find("contact time limits"), std::string::npos) << s.dt_reason;
}

TEST(Timestep, RayleighLimitsAtRestAndFollowsSafety) {
  // No gravity, no motion, no initial speed: the expected speed is its floor, 0.01 m/s, and the
  // Rayleigh term limits.
  const bagdem::Scene s = load(steel_case({}, 0.5, 0.0, "[0, 0, 0]"));
  expect_rel(s.expected_speed, 0.01, "expected speed floor");
  const Expected x = expected({kSteel}, {2e-3}, 0, 0.5, false, 40, 0.01);
  ASSERT_EQ(x.dt(0.2), 0.2 * x.rayleigh) << "test set-up: Rayleigh should limit here";
  expect_rel(s.dt, 0.2 * x.rayleigh, "dt");
  EXPECT_NE(s.dt_reason.find("Rayleigh limits"), std::string::npos) << s.dt_reason;

  // dt is proportional to the safety factor while Rayleigh limits...
  const bagdem::Scene half = load(steel_case({{"timestep_safety", 0.1}}, 0.5, 0.0, "[0, 0, 0]"));
  expect_rel(half.dt, 0.5 * s.dt, "dt at safety 0.1");
  // ...and steps_per_contact does not move it.
  const bagdem::Scene spc = load(steel_case({{"steps_per_contact", 60}}, 0.5, 0.0, "[0, 0, 0]"));
  expect_rel(spc.dt, s.dt, "dt at 60 steps per contact");
  // With safety 1 the contact time (now smaller) takes over.
  const bagdem::Scene one = load(steel_case({{"timestep_safety", 1}}, 0.5, 0.0, "[0, 0, 0]"));
  expect_rel(one.dt, x.dt(1.0), "dt at safety 1");
  EXPECT_EQ(x.dt(1.0), x.contact);
  EXPECT_LT(one.dt, 1.0 * x.rayleigh);
}

TEST(Timestep, StepsPerContactAndExpectedSpeed) {
  const bagdem::Scene s = load(steel_case());
  // Contact-limited: dt ~ 1 / steps_per_contact.
  const bagdem::Scene s80 = load(steel_case({{"steps_per_contact", 80}}));
  expect_rel(s80.dt, 0.5 * s.dt, "dt at 80 steps per contact");
  // ...and the safety factor does not move it.
  const bagdem::Scene safe = load(steel_case({{"timestep_safety", 0.3}}));
  expect_rel(safe.dt, s.dt, "dt at safety 0.3");

  // An explicit expected speed replaces the auto one; dt ~ v^(-1/5) while the contact time limits:
  // 32 times the speed halves the step.
  const bagdem::Scene v05 = load(steel_case({{"expected_speed", "0.5 m/s"}}));
  const bagdem::Scene v16 = load(steel_case({{"expected_speed", 16}}));
  expect_rel(v05.expected_speed, 0.5, "explicit expected speed");
  expect_rel(v16.expected_speed, 16, "explicit expected speed");
  const Expected x05 = expected({kSteel}, {2e-3}, 0, 0.5, false, 40, 0.5);
  const Expected x16 = expected({kSteel}, {2e-3}, 0, 0.5, false, 40, 16);
  ASSERT_EQ(x05.dt(0.2), x05.contact);
  ASSERT_EQ(x16.dt(0.2), x16.contact);
  expect_rel(v05.dt, x05.dt(0.2), "dt at 0.5 m/s");
  expect_rel(v16.dt, x16.dt(0.2), "dt at 16 m/s");
  expect_rel(v16.dt, 0.5 * v05.dt, "dt(16 m/s) / dt(0.5 m/s)");
  // "auto" is the same as leaving the key out.
  const bagdem::Scene a = load(steel_case({{"expected_speed", quoted("auto")}}));
  EXPECT_EQ(a.dt, s.dt);
}

TEST(Timestep, CriticalStepLimitsWithFrictionAndHeavyDamping) {
  // Friction (tangential spring, 2/7 m*, damping ratio sqrt(3.5) times the normal one), restitution
  // 0.05 (heavy damping), 10 steps per contact, safety 1: half the critical step is the smallest
  // term (the end-of-step dashpot doubles the effective damping ratio in the stability limit).
  const CaseText::Keys extra = {{"timestep_safety", 1}, {"steps_per_contact", 10}};
  const bagdem::Scene s = load(steel_case(extra, 0.05, 0.3));
  ASSERT_TRUE(s.models.tangential);
  const double v = std::sqrt(2 * 9.81 * 0.02);
  const Expected x = expected({kSteel}, {2e-3}, 0, 0.05, true, 10, v);
  ASSERT_EQ(x.dt(1.0), 0.5 * x.critical) << "test set-up: the critical step should limit here";
  expect_rel(s.dt, 0.5 * x.critical, "dt");
  expect_rel(s.dt_critical, x.critical, "critical step");
  EXPECT_NE(s.dt_reason.find("critical step limits"), std::string::npos) << s.dt_reason;
  // The tangential spring is what limits: without friction the critical step is longer.
  const bagdem::Scene nf = load(steel_case(extra, 0.05, 0.0));
  const Expected xn = expected({kSteel}, {2e-3}, 0, 0.05, false, 10, v);
  expect_rel(nf.dt_critical, xn.critical, "critical step without friction");
  EXPECT_GT(nf.dt_critical, 1.5 * s.dt_critical);
  // The critical step depends neither on steps_per_contact nor on the safety factor, and while it
  // limits neither moves dt.
  const bagdem::Scene s12 = load(steel_case({{"timestep_safety", 0.9}, {"steps_per_contact", 12}}, 0.05, 0.3));
  expect_rel(s12.dt_critical, s.dt_critical, "critical step at 12 steps per contact, safety 0.9");
  expect_rel(s12.dt, s.dt, "dt at 12 steps per contact, safety 0.9");
}

TEST(Timestep, AutoExpectedSpeedSumsMotionFallAndInitialSpeed) {
  // Harmonic motion 1.5 mm at 40 Hz, a 30 mm tall box, one ball thrown at (0.3, 0.4, 0) m/s.
  const std::string toml = CaseText()
                               .simulation("0.01", "[0, 0, -9.81]")
                               .material("steel", 7800, "200e9", 0.3)
                               .interactions(0.7, 0.2)
                               .box("steel", "[0, 0, 0]", "[0.02, 0.02, 0.03]")
                               .harmonic("1.5 mm", "40 Hz", "[0, 0, 1]")
                               .placed("balls", "steel", "0.004", "[[0.01, 0.01, 0.01], [0.005, 0.005, 0.02]]",
                                       "[[0.3, 0.4, 0], [0, 0, 0.1]]");
  const bagdem::Scene s = load(toml);
  const double v = 2 * 1.5e-3 * 2 * kPi * 40 + std::sqrt(2 * 9.81 * 0.03) + 0.5;
  expect_rel(s.expected_speed, v, "expected speed");
  const Expected x = expected({kSteel}, {2e-3}, 0, 0.7, true, 40, v);
  expect_rel(s.dt, x.dt(0.2), "dt");
  expect_rel(s.dt_critical, x.critical, "critical step");
}

TEST(Timestep, SeveralMaterialsTakeTheSmallestOverPairs) {
  // Steel balls of 4 mm, glass balls of 3 mm, an aluminium box (a material only walls use).
  const std::string toml = CaseText()
                               .simulation("0.01", "[0, 0, -9.81]")
                               .material("steel", 7800, "200e9", 0.3)
                               .material("glass", 2500, "63e9", 0.22)
                               .material("alu", 2700, "70e9", 0.33)
                               .interactions(0.6, 0.25)
                               .box("alu", "[0, 0, 0]", "[0.03, 0.03, 0.03]")
                               .balls("big", "steel", "0.004", 4)
                               .set("particles.big", "seed", 3)
                               .balls("small", "glass", "0.003", 4)
                               .set("particles.small", "seed", 4);
  const bagdem::Scene s = load(toml);
  ASSERT_EQ(s.materials.size(), 3u);
  // The material index order is the engine's (it need not be the file's): look each up by name.
  const std::map<std::string, Mat> by_name = {
      {"steel", kSteel}, {"glass", {2500, 63e9, 0.22}}, {"alu", {2700, 70e9, 0.33}}};
  const std::map<std::string, double> radius = {{"steel", 2e-3}, {"glass", 1.5e-3}, {"alu", 0}};
  std::vector<Mat> mats;
  std::vector<double> rmin;
  int wall = -1;
  for (std::size_t k = 0; k < s.materials.size(); ++k) {
    const std::string& name = s.materials[k].name;
    ASSERT_TRUE(by_name.count(name)) << name;
    mats.push_back(by_name.at(name));
    rmin.push_back(radius.at(name));
    if (name == "alu") wall = static_cast<int>(k);
  }
  const double v = std::sqrt(2 * 9.81 * 0.03);
  expect_rel(s.expected_speed, v, "expected speed");
  // Defaults (safety 0.2, 40 steps per contact), then safety 1 and 10 steps per contact. (Each
  // load of this 3-material case solves clamped_beta once per distinct restitution of its pairs.)
  const Expected x = expected(mats, rmin, wall, 0.6, true, 40, v);
  expect_rel(s.dt, x.dt(0.2), "dt (defaults)");
  expect_rel(s.dt_critical, x.critical, "critical step");
  const bagdem::Scene t = load(toml, {"simulation.timestep_safety=1", "simulation.steps_per_contact=10"});
  const Expected x10 = expected(mats, rmin, wall, 0.6, true, 10, v);
  expect_rel(t.dt, x10.dt(1.0), "dt at safety 1, 10 steps per contact");
  expect_rel(t.dt_critical, x10.critical, "critical step");
  // The glass balls (smaller, lighter) set the contact time; the limit differs from the
  // steel-only value.
  const Expected steel_only = expected({kSteel}, {2e-3}, 0, 0.6, true, 40, v);
  EXPECT_LT(x.contact, steel_only.contact);
}

TEST(Timestep, ExplicitStepKeptAndCheckedAgainstCritical) {
  const double v = std::sqrt(2 * 9.81 * 0.02);
  const Expected x = expected({kSteel}, {2e-3}, 0, 0.5, false, 40, v);
  // Below the critical step: kept as given.
  const bagdem::Scene s = load(steel_case({{"timestep", "1e-6 s"}}));
  EXPECT_EQ(s.dt, 1e-6);
  expect_rel(s.dt_critical, x.critical, "critical step");
  EXPECT_NE(s.dt_reason.find("explicit"), std::string::npos) << s.dt_reason;
  // Just above it: refused, unless forced.
  const CaseText::Keys above = {{"timestep", exact(1.01 * x.critical)}};
  EXPECT_THROW(load(steel_case(above)), bagdem::InputError);
  const CaseText::Keys below = {{"timestep", exact(0.99 * x.critical)}};
  EXPECT_NO_THROW(load(steel_case(below)));
  const bagdem::Scene forced = load(steel_case({above[0], {"force_timestep", "true"}}));
  EXPECT_GT(forced.dt, forced.dt_critical);
  // force_timestep with a step that needs no forcing is accepted (it was once an "unknown key").
  EXPECT_NO_THROW(load(steel_case({below[0], {"force_timestep", "true"}})));
}

TEST(Timestep, OutOfRangeParametersAreRefused) {
  for (const auto& [key, bad] : std::vector<std::pair<std::string, std::string>>{
           {"timestep_safety", "0"}, {"timestep_safety", "1.5"}, {"steps_per_contact", "5"}, {"expected_speed", "-1"},
           {"expected_speed", "0"}, {"timestep", "-1e-6"}, {"timestep_safety", "\"fast\""}}) {
    EXPECT_THROW(load(steel_case({{key, bad}})), bagdem::InputError) << key << " = " << bad;
  }
  // The boundaries that are allowed.
  EXPECT_NO_THROW(load(steel_case({{"timestep_safety", 1}})));
  EXPECT_NO_THROW(load(steel_case({{"steps_per_contact", 10}})));
}

}  // namespace
