// The linear spring-dashpot law (contact/hooke.hpp, `law = "hooke"`) against its closed forms. A
// head-on impact under it is a damped linear oscillator of effective mass m*, stiffness k_n and
// damping ratio zeta = -ln e / sqrt(pi^2 + ln^2 e) (Schwager & Poeschel 2005, sec. 3.1.1):
//   contact time      t_c = pi / omega_d,  omega_d = omega_0 sqrt(1 - zeta^2),  omega_0 = sqrt(k_n / m*)
//   restitution       e = exp(-zeta pi / sqrt(1 - zeta^2))
//   largest overlap   (v / omega_d) exp(-zeta omega_0 t*) sin(omega_d t*),  tan(omega_d t*) = omega_d / (zeta omega_0)
// Stepped by the engine (velocity Verlet, 40 steps per contact as `auto` gives), ball on ball and
// ball on a plane, e from 0.2 to 1: the measured restitution within 0.5% of the requested (worst
// at e = 0.2: 0.40% low) and the contact time within 0.5% of the closed form (measured 0.15%). The
// largest overlap within zeta omega_0 dt + 0.5%: the dashpot's force jumps from 0 to gamma_n v at
// first touch, inside a step, an error of first order in dt (measured 3.5% at e = 0.2, where
// zeta omega_0 dt = 4.0%; 0.03% at e = 1). The force pulls at the
// end of a damped impact (not clamped, as LAMMPS' gran/hooke): its smallest value is negative for
// e < 1, and the closed forms hold only so. Also the time step's rule asks the law (the auto step
// is t_c / steps_per_contact, not Hertz's), and `bagdem check` names each pair's law.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bagdem/case/load_case.hpp"
#include "bagdem/contact/law.hpp"
#include "bagdem/contact/pair_laws.hpp"
#include "case_texts.hpp"
#include "impact.hpp"
#include "support.hpp"

using namespace bagdem;
using bagdem::testing::head_on_impact;

namespace {

constexpr double kRho = 7800, kE = 2e9, kNu = 0.3, kRadius = 2e-3;

Interaction hooke_law(double e, double k) {
  Interaction in;
  in.law = LawKind::Hooke;
  in.restitution = e;
  in.stiffness = k;
  return in;
}

PairLaw make_law(double e, double k) {
  const Material steel{"steel", kRho, kE, kNu};
  return make_pair_laws({steel}, {hooke_law(e, k)}).laws[0];
}

// The damped oscillator's largest overlap after an approach at speed v.
double oscillator_max_overlap(double k, double m_eff, double e, double v) {
  const double zeta = hooke::damping_ratio(e), w0 = std::sqrt(k / m_eff), wd = w0 * std::sqrt(1 - zeta * zeta);
  const double t = std::atan2(wd, zeta * w0) / wd;
  return v / wd * std::exp(-zeta * w0 * t) * std::sin(wd * t);
}

}  // namespace

TEST(HookeLaw, DampingRatioAndRestitutionAreInverse) {
  EXPECT_EQ(hooke::damping_ratio(1.0), 0.0);
  EXPECT_FALSE(std::signbit(hooke::damping_ratio(1.0))) << "bagdem check would print a damping ratio of -0";
  for (double e : {0.05, 0.2, 0.5, 0.8, 0.99}) {
    const double zeta = hooke::damping_ratio(e);
    EXPECT_GT(zeta, 0.0);
    EXPECT_LT(zeta, 1.0);
    EXPECT_NEAR(hooke::restitution(zeta), e, 1e-14) << "e " << e;
  }
  // The table row computes PairLaw::damping = 2 zeta.
  const ContactLawRow* row = find_contact_law("hooke");
  ASSERT_NE(row, nullptr);
  EXPECT_EQ(row->kind, LawKind::Hooke);
  EXPECT_DOUBLE_EQ(row->damping_of(0.5), 2 * hooke::damping_ratio(0.5));
  EXPECT_EQ(find_contact_law("walton"), nullptr);
  EXPECT_EQ(contact_law_names(), "\"hertz-mindlin\", \"hooke\"");
}

TEST(HookeLaw, HeadOnImpactsFollowTheDampedOscillator) {
  const double k = 5e5, v = 0.5;  // N/m, m/s: overlaps of ~1.6% of the radius
  const double m = 4.0 / 3.0 * std::numbers::pi * kRadius * kRadius * kRadius * kRho;
  for (bool wall : {false, true}) {
    const double m_eff = wall ? m : m / 2;
    for (double e : {0.2, 0.5, 0.8, 1.0}) {
      SCOPED_TRACE(std::string(wall ? "ball on a plane" : "ball on ball") + ", e " + std::to_string(e));
      const auto r = head_on_impact(hooke_law(e, k), kRho, kE, kNu, v, wall, 40, kRadius);
      const double zeta = hooke::damping_ratio(e);
      const double t_c = std::numbers::pi / (std::sqrt(k / m_eff) * std::sqrt(1 - zeta * zeta));
      std::printf("[hooke] %s e=%.2f: e_measured %.6f, t_c %.6e (closed %.6e), max overlap %.6e (closed %.6e), min F_n %.3e\n",
                  wall ? "wall" : "pair", e, r.restitution, r.duration, t_c, r.max_overlap,
                  oscillator_max_overlap(k, m_eff, e, v), r.min_normal_force);
      EXPECT_NEAR(r.restitution, e, 5e-3 * e);
      EXPECT_NEAR(r.duration, t_c, 5e-3 * t_c);
      EXPECT_NEAR(r.hertz_duration, t_c, 1e-12 * t_c);  // the law's own contact_time
      const double dt = contact_law(LawKind::Hooke).resolved_step(make_law(e, k), m_eff, 0, v, 40);
      EXPECT_NEAR(r.max_overlap, oscillator_max_overlap(k, m_eff, e, v), (zeta * std::sqrt(k / m_eff) * dt + 5e-3) * r.max_overlap);
      if (e < 1) EXPECT_LT(r.min_normal_force, 0.0) << "the dashpot pulls at the end of a damped impact";
    }
  }
}

// The auto step of a Hooke case is the law's: t_c / steps_per_contact at the expected speed (the
// ball-ball pair's m* is the smallest), not the Hertz contact time of the materials' moduli, and
// no Rayleigh limit (the spring is the user's, not the moduli's).
TEST(HookeLaw, TheAutoStepIsTheLawsContactTime) {
  bagdem::testing::TempDir tmp;
  using bagdem::testing::CaseText;
  CaseText c;
  c.simulation("0.01 s", bagdem::testing::kNoGravity).steel().interactions(0.5);
  c.box("steel", "[0, 0, 0]", "[\"20 mm\", \"20 mm\", \"20 mm\"]");
  c.set("simulation", {{"expected_speed", "0.5 m/s"}, {"steps_per_contact", 40}})
      .set("interactions.default", {{"law", "\"hooke\""}, {"stiffness", "5e5 N/m"}})
      .balls("balls", "steel", "4 mm", 5);
  tmp.write("case.toml", c.str());
  const Scene s = load_case(tmp.path, {});
  const double m = 4.0 / 3.0 * std::numbers::pi * kRadius * kRadius * kRadius * 7800;
  const double zeta = hooke::damping_ratio(0.5);
  const double t_c = std::numbers::pi / (std::sqrt(5e5 / (m / 2)) * std::sqrt(1 - zeta * zeta));
  EXPECT_NEAR(s.dt, t_c / 40, 1e-9 * t_c) << "the step of 200 GPa's Rayleigh time would be " << s.dt;
  EXPECT_EQ(s.laws(0, 0).kind, LawKind::Hooke);
  EXPECT_EQ(s.laws(0, 0).stiffness, 5e5);
  EXPECT_NEAR(s.laws(0, 0).tangential_ratio * s.laws(0, 0).tangential_ratio, 2.0 / 7.0, 1e-15);

  const auto r = bagdem::testing::run_bagdem({"check", tmp.str()}, tmp.path);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("pair        steel-steel: hooke, e 0.5"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("k_n 5e+05 N/m"), std::string::npos) << r.out;
}

// A spring too soft for the impacts is named before the run: at the expected speed the undamped
// linear contact overlaps delta = v sqrt(m*/k) (a ball on a wall: m* = m); above the guard's
// simulation.max_overlap of the radius the case loads with a warning naming the pair's stiffness.
TEST(HookeLaw, ASpringTooSoftForTheImpactsIsNamed) {
  const double m = 4.0 / 3.0 * std::numbers::pi * kRadius * kRadius * kRadius * 7800;
  const double v = 0.5, k_edge = m * v * v / (0.1 * kRadius * 0.1 * kRadius);  // delta = 10% of the radius
  auto warnings = [&](double k) {
    bagdem::testing::TempDir tmp;
    bagdem::testing::CaseText c;
    c.simulation("0.01 s", bagdem::testing::kNoGravity).steel().interactions(0.5);
    c.box("steel", "[0, 0, 0]", "[\"20 mm\", \"20 mm\", \"20 mm\"]");
    c.set("simulation", {{"expected_speed", "0.5 m/s"}, {"timestep", "1e-6 s"}, {"force_timestep", "true"}})
        .set("interactions.default", {{"law", "\"hooke\""}, {"stiffness", std::to_string(k) + " N/m"}})
        .balls("balls", "steel", "4 mm", 5);
    tmp.write("case.toml", c.str());
    std::string all;
    for (const std::string& w : load_case(tmp.path, {}).warnings) all += w + "\n";
    return all;
  };
  // Damping shortens the overlap a little (e = 0.5): just above the undamped edge passes.
  EXPECT_EQ(warnings(1.01 * k_edge).find("would overlap"), std::string::npos) << warnings(1.01 * k_edge);
  const std::string soft = warnings(0.5 * k_edge);
  EXPECT_NE(soft.find("would overlap"), std::string::npos) << soft;
  EXPECT_NE(soft.find("Raise interactions.default.stiffness"), std::string::npos) << soft;
  // A stiff spring at a step forced above its critical step says so.
  const std::string stiff = warnings(1e9);
  EXPECT_NE(stiff.find("is above the critical step"), std::string::npos) << stiff;
}
