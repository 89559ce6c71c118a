// The critical step that src/case/timestep.cpp reports (Scene::dt_critical) against the stability
// of the stepper itself: a ball pressed onto a plane by gravity, oscillating about its equilibrium,
// integrated with an explicit step that is a multiple of dt_critical.
//
// Set-up: a soft ball (r = 5 mm, rho = 1000, E = 10 MPa, nu = 0.3) in a box of a 1000x stiffer
// material, so the ball-wall contact is the stiffest one the rule considers. The case states an
// expected speed v; gravity is chosen so that the static overlap equals the rule's overlap,
// delta_s = hertz::max_overlap(m, r, E*, v) (then the contact's linear frequency about equilibrium
// is the one the rule uses: w_n = sqrt(S_n(delta_s)/m), w_t = sqrt(3.5 S_t(delta_s)/m)).
// Perturbation energy E' = kinetic + elastic (Hertz + tangential spring) + m g (z - z_s) - U(delta_s),
// zero at rest at equilibrium.
//
// Modes and checks (references: velocity Verlet on a linear oscillator, critical step 2/w undamped;
// it conserves v^2 + w^2 x^2 (1 - (w dt/2)^2), so E' oscillates between E'_0 and E'_0/(1 - (w dt/2)^2)
// when started at the equilibrium with velocity only, and never exceeds E'_0 when started at rest at
// a turning point):
//  normal (no friction, e = 1): start at rest at delta = 1.05 delta_s.
//    dt = 1.5 dt_critical: E' grows above 10 E'_0 or a run guard fires, within 2000 steps.
//    dt = 0.7 dt_critical: E' <= E'_0 (1 + 2e-3) over 4000 steps (2e-3: Hertz nonlinearity at a 5 %
//    amplitude).
//  tangential (mu = 1, e = 1; the rule's limit is then the tangential one, 1/1.7 of the normal, so at
//    1.5x it the normal mode alone is stable): start at delta_s with v_x = u, w_y = -2.5 u/r (the
//    contact point moves at 3.5 u, no angular momentum about the contact point), u far below slip.
//    dt = 1.5 dt_critical: E' > 10 x the Verlet bound of the 0.7x run (below) or a guard fires,
//    within 2000 steps; the same step without friction stays bounded (E' <= E'_0 (1 + 1e-6)): the
//    tangential mode is what diverges.
//    dt = 0.7 dt_critical: E' <= E'_0 / (1 - (w_t dt/2)^2) (1 + 1e-2) over 4000 steps.
//  damped (e = 0.5 and 0.2; the rule's critical step 2/w (sqrt(1+z^2) - z), z = 0.5 x damping for
//    the normal mode, sqrt(3.5) times that for the tangential one): at 0.7 dt_critical E' stays
//    below E'_0 (normal, turning-point start) or the Verlet bound above (tangential) (1 % margin),
//    over 4000 steps, and at the end it has decayed below E'_0; at 1.5 dt_critical it diverges.
//  Measured stability limit (bisection on the step factor, see measured_limit): e = 1, within 3 % of
//    dt_critical (normal and tangential); damped, not below 0.97 dt_critical (the reported step must
//    not be optimistic; 3 % covers the bisection criterion and the Hertz nonlinearity).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>

#include "bagdem/case/load_case.hpp"
#include "bagdem/contact/hertz.hpp"
#include "bagdem/contact/hertz_theory.hpp"
#include "bagdem/error.hpp"
#include "bagdem/step/simulation.hpp"
#include "case_texts.hpp"
#include "support.hpp"

using namespace bagdem;
using bagdem::testing::CaseText;
using bagdem::testing::TempDir;
using bagdem::testing::vec;

namespace {

constexpr double kR = 5e-3, kRho = 1000, kE = 1e7, kNu = 0.3;   // ball
constexpr double kEw = 1e10, kRhoW = 7800;                       // wall
constexpr double kV = 0.1;                                       // expected speed (unit: m/s)
const double kMass = kRho * 4.0 / 3.0 * M_PI * kR * kR * kR;

double e_star() { return 1.0 / ((1 - kNu * kNu) / kE + (1 - kNu * kNu) / kEw); }
// Static overlap = the rule's overlap at kV: the weight the Hertz force carries there.
double gravity() {
  const double d = hertz::max_overlap(kMass, kR, e_star(), kV);
  return 4.0 / 3.0 * e_star() * std::sqrt(kR) * d * std::sqrt(d) / kMass;
}

std::string exact(double v) {
  std::ostringstream s;
  s << std::setprecision(17) << v;
  return s.str();
}

Scene load(double e, double mu) {
  TempDir tmp;
  std::ofstream(tmp.path / "case.toml") << CaseText()
                                               .simulation("0.01", vec(0, 0, -gravity()))
                                               .set("simulation", "expected_speed", kV)
                                               .material("ball", kRho, exact(kE), kNu)
                                               .material("wall", kRhoW, exact(kEw), kNu)
                                               .interactions(exact(e), exact(mu))
                                               .box("wall", "[-0.05, -0.05, 0]", "[0.05, 0.05, 0.1]")
                                               .balls("balls", "ball", exact(2 * kR), 1)
                                               .set("particles.balls", "seed", 1);
  return load_case(tmp.path.string());
}

enum class Mode { Normal, Tangential };

struct Outcome {
  double max_ratio = 0;  // max E'/E'_0 over the run
  double end_ratio = 0;  // E'/E'_0 at the end
  bool guard = false;    // a RunError stopped it
  int steps = 0;
};

// The ball on the bottom plane (z = 0) of the loaded scene, perturbed in `mode`, stepped `steps`
// times with dt = factor x dt_critical (of `crit_from`, default the scene's own).
Outcome run(const Scene& loaded, Mode mode, double factor, int steps, double crit = 0) {
  Scene s = loaded;
  s.dt = factor * (crit > 0 ? crit : loaded.dt_critical);
  const double g = -s.gravity.z();
  int ball = 0;
  while (s.materials[static_cast<std::size_t>(ball)].name != "ball") ++ball;
  int wall = 1 - ball;
  const PairLaw& law = s.laws(ball, wall);
  const double ds = hertz::static_overlap(kMass * g, kR, law.E_star);
  EXPECT_NEAR(ds, hertz::max_overlap(kMass, kR, law.E_star, kV), 1e-9 * ds) << "set-up: static overlap";
  s.particles.resize(1);
  ParticleInit& p = s.particles[0];
  p.radius = kR;
  p.material = ball;
  p.w = Vec3::Zero();
  const double u = 1e-4;  // tangential perturbation speed (slip would need ~0.1 m/s here)
  if (mode == Mode::Normal) {
    p.x = Vec3(0, 0, kR - 1.05 * ds);
    p.v = Vec3::Zero();
  } else {
    p.x = Vec3(0, 0, kR - ds);
    p.v = Vec3(u, 0, 0);
    p.w = Vec3(0, -2.5 * u / kR, 0);
  }
  Simulation sim(s);
  const double U_s = (8.0 / 15.0) * law.E_star * std::sqrt(kR) * ds * ds * std::sqrt(ds);
  auto perturbation = [&] {
    const auto& q = sim.particles();
    const double ke = 0.5 * kMass * q.v[0].squaredNorm() + 0.5 * 0.4 * kMass * kR * kR * q.w[0].squaredNorm();
    return ke + sim.energy().elastic + kMass * g * (q.x[0].z() - (kR - ds)) - U_s;
  };
  const double E0 = perturbation();
  Outcome r;
  double E = E0;
  try {
    for (r.steps = 0; r.steps < steps; ++r.steps) {
      sim.step();
      E = perturbation();
      r.max_ratio = std::max(r.max_ratio, E / E0);
      if (!std::isfinite(E) || E > 1e6 * E0) break;  // diverged for good
    }
  } catch (const RunError&) {
    r.guard = true;
  }
  r.end_ratio = E / E0;
  return r;
}

// Linear frequencies about the equilibrium (the rule's, at delta_s).
double w_normal(const PairLaw& law) {
  const double ds = hertz::max_overlap(kMass, kR, law.E_star, kV);
  return std::sqrt(2 * law.E_star * std::sqrt(kR * ds) / kMass);
}
double w_tangential(const PairLaw& law) {
  return w_normal(law) * std::sqrt(3.5 * 4 * law.G_star / law.E_star);
}
const PairLaw& ball_wall(const Scene& s) { return s.laws(0, 1); }

// Verlet bound on E'/E'_0 for a start at equilibrium with velocity only.
double verlet_bound(double w, double dt) { return 1.0 / (1.0 - 0.25 * w * w * dt * dt); }

bool diverged(const Outcome& r, double bound) { return r.guard || r.max_ratio > 10 * bound; }

// Measured stability limit in units of dt_critical: bisection on the step factor, 2000 steps each;
// diverged = a guard fired or E' exceeded 10 E'_0 (normal: the turning-point start never exceeds
// E'_0 when stable) or 100 E'_0 (tangential: the Verlet bound reaches 100 only at 0.995 of the
// limit).
double measured_limit(const Scene& s, Mode mode) {
  const double threshold = mode == Mode::Normal ? 10 : 100;
  double lo = 0.3, hi = 2.0;
  for (int k = 0; k < 14; ++k) {
    const double mid = 0.5 * (lo + hi);
    const Outcome r = run(s, mode, mid, 2000);
    (r.guard || r.max_ratio > threshold ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

TEST(StabilityLimit, NormalModeFrictionless) {
  const Scene s = load(1.0, 0.0);
  ASSERT_FALSE(s.models.tangential);
  // Set-up: the rule's step is the ball-wall normal one, 2/w_n (no damping at e = 1).
  EXPECT_NEAR(s.dt_critical, 2.0 / w_normal(ball_wall(s)), 1e-9 * s.dt_critical);
  const Outcome bad = run(s, Mode::Normal, 1.5, 2000), good = run(s, Mode::Normal, 0.7, 4000);
  std::printf("  normal, e=1: dt_critical=%.4e s; 1.5x: max E'/E'0=%.3e guard=%d after %d steps; "
              "0.7x: max E'/E'0=%.6f\n",
              s.dt_critical, bad.max_ratio, bad.guard, bad.steps, good.max_ratio);
  EXPECT_TRUE(diverged(bad, 1.0)) << "1.5 x dt_critical did not diverge";
  EXPECT_FALSE(good.guard);
  EXPECT_EQ(good.steps, 4000);
  EXPECT_LE(good.max_ratio, 1 + 2e-3) << "0.7 x dt_critical gained energy";
  const double limit = measured_limit(s, Mode::Normal);
  std::printf("  normal, e=1: measured limit = %.4f dt_critical\n", limit);
  EXPECT_NEAR(limit, 1.0, 0.03) << "the reported critical step is not the stability limit";
}

TEST(StabilityLimit, TangentialModeWithFriction) {
  const Scene s = load(1.0, 1.0), s0 = load(1.0, 0.0);
  ASSERT_TRUE(s.models.tangential);
  const PairLaw& law = ball_wall(s);
  // Set-up: the rule's step is the tangential one, 2/w_t, and 1.5 x it keeps the normal mode stable.
  EXPECT_NEAR(s.dt_critical, 2.0 / w_tangential(law), 1e-9 * s.dt_critical);
  ASSERT_LT(1.5 * s.dt_critical, s0.dt_critical);
  const double dt_good = 0.7 * s.dt_critical, bound = verlet_bound(w_tangential(law), dt_good);
  const Outcome bad = run(s, Mode::Tangential, 1.5, 2000), good = run(s, Mode::Tangential, 0.7, 4000);
  const Outcome control = run(s0, Mode::Tangential, 1.5, 2000, s.dt_critical);
  std::printf("  tangential, e=1, mu=1: dt_critical=%.4e s (normal only %.4e); 1.5x: max E'/E'0=%.3e guard=%d "
              "after %d steps; same step without friction: %.6f; 0.7x: max E'/E'0=%.4f (Verlet bound %.4f)\n",
              s.dt_critical, s0.dt_critical, bad.max_ratio, bad.guard, bad.steps, control.max_ratio, good.max_ratio,
              bound);
  EXPECT_TRUE(diverged(bad, bound)) << "1.5 x dt_critical did not diverge";
  EXPECT_FALSE(control.guard);
  EXPECT_LE(control.max_ratio, 1 + 1e-6) << "without friction the same step should be stable";
  EXPECT_FALSE(good.guard);
  EXPECT_EQ(good.steps, 4000);
  EXPECT_LE(good.max_ratio, bound * (1 + 1e-2)) << "0.7 x dt_critical gained energy";
  const double limit = measured_limit(s, Mode::Tangential);
  std::printf("  tangential, e=1: measured limit = %.4f dt_critical\n", limit);
  EXPECT_NEAR(limit, 1.0, 0.03) << "the reported critical step is not the stability limit";
}

TEST(StabilityLimit, DampedContacts) {
  for (double e : {0.5, 0.2}) {
    for (Mode mode : {Mode::Normal, Mode::Tangential}) {
      const bool tan = mode == Mode::Tangential;
      const Scene s = load(e, tan ? 1.0 : 0.0);
      const PairLaw& law = ball_wall(s);
      const double z = 0.5 * law.damping;
      const double expect = tan ? hertz::critical_step(w_tangential(law), std::sqrt(3.5) * z)
                                : hertz::critical_step(w_normal(law), z);
      EXPECT_NEAR(s.dt_critical, expect, 1e-9 * expect) << "set-up";
      const double bound = tan ? verlet_bound(w_tangential(law), 0.7 * s.dt_critical) : 1.0;
      const Outcome bad = run(s, mode, 1.5, 2000), good = run(s, mode, 0.7, 4000);
      const double limit = measured_limit(s, mode);
      // Linear analysis of the stepper (dashpot on the predicted end-of-step velocity v + dt a):
      // det(M + I) = 4 (1 - (w dt/2)^2 - 2 zeta w dt) vanishes at 2/w (sqrt(1 + 4 zeta^2) - 2 zeta),
      // the rule's formula with zeta doubled (the rule's formula is that of a half-step dashpot).
      const double zz = tan ? std::sqrt(3.5) * z : z, ww = tan ? w_tangential(law) : w_normal(law);
      const double linear = 2 / ww * (std::sqrt(1 + 4 * zz * zz) - 2 * zz) / s.dt_critical;
      std::printf("  %s, e=%.1f (zeta=%.3f): 1.5x: max E'/E'0=%.3e guard=%d; 0.7x: max E'/E'0=%.3e end %.3e "
                  "guard=%d; measured limit = %.3f dt_critical (linear analysis of the stepper: %.3f)\n",
                  tan ? "tangential" : "normal", e, zz, bad.max_ratio, bad.guard, good.max_ratio, good.end_ratio,
                  good.guard, limit, linear);
      EXPECT_TRUE(diverged(bad, bound)) << "e=" << e << (tan ? " tangential" : " normal");
      EXPECT_FALSE(good.guard) << "e=" << e << (tan ? " tangential" : " normal") << ": 0.7 x dt_critical";
      EXPECT_LE(good.max_ratio, bound * (1 + 1e-2))
          << "e=" << e << (tan ? " tangential" : " normal") << ": 0.7 x dt_critical is unstable (measured limit "
          << limit << " x dt_critical)";
      EXPECT_LT(good.end_ratio, 1.0) << "e=" << e << (tan ? " tangential" : " normal");
      // The reported step must not be optimistic: the stepper is stable up to it (3 %: bisection
      // criterion and the Hertz nonlinearity at the 5 % amplitude).
      EXPECT_GE(limit, 0.97) << "e=" << e << (tan ? " tangential" : " normal")
                             << ": the stepper's stability limit is below the reported critical step";
    }
  }
}
