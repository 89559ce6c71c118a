// Unit tests of the contact roles' clamps and caps (hertz.hpp, mindlin.hpp, geometry.hpp):
//  - hertz_normal: F_n = max(0, F_el + gamma_n d(delta)/dt), F_el = 4/3 E* sqrt(R*) delta^(3/2),
//    S_n = 2 E* sqrt(R* delta), gamma_n = damping sqrt(S_n m*), d(delta)/dt = -v_rel.n. A separating
//    contact whose unclamped sum (computed here) is negative returns exactly 0; an approaching one,
//    and a slowly separating one whose sum stays positive, return the sum (1e-14 relative). The
//    elastic force and stiffness are returned unclamped (1e-14 relative).
//  - mindlin_tangential: |F_t| <= mu F_n (1e-12 relative) for random states (history force
//    0.01 to 100 mu F_n, random normal, random relative velocities, new and old contacts); below the cap
//    F_t = F_e - gamma_t v_t (F_e the carried history minus S_t dt v_t), with S_t = S_n 4G*/E* and
//    gamma_t = gamma_n sqrt(4G*/E*) (1e-12); above it F_t is the trial force scaled to the cap
//    (parallel to within 1e-12) and the history holds it; F_t is tangential (|F_t.n| <= 1e-12 |F_t|);
//    a contact whose normal force is clamped to 0 carries no tangential force (exactly 0).
//  - carry_spring: |v'|^2 / (2 k_new) <= |v|^2 / (2 k_old) (1 + 1e-12) for random v, n, k_old, k_new;
//    v' is tangential (1e-12 |v|); magnitude kept when the stiffness rose, scaled by k_new/k_old
//    when it fell (1e-12 relative).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "bagdem/contact/geometry.hpp"
#include "bagdem/contact/hertz.hpp"
#include "bagdem/contact/mindlin.hpp"
#include "bagdem/contact/restitution.hpp"
#include "rng.hpp"

using namespace bagdem;
using bagdem::testing::Rng;

namespace {

PairLaw make_law(double e, double mu) {
  PairLaw law;
  law.E_star = 1.1e8;
  law.G_star = 0.45e8;
  law.damping = 2 * std::sqrt(5.0 / 6.0) * clamped_beta(e);
  law.tangential_ratio = std::sqrt(4 * law.G_star / law.E_star);
  law.friction = mu;
  law.restitution = e;
  return law;
}

// Sphere on a wall-like partner: normal n, overlap d, relative velocity v (end of step and half step).
ContactGeometry geometry(const Vec3& n, double d, const Vec3& v_end, const Vec3& v_half) {
  ContactGeometry g;
  g.n = n;
  g.overlap = d;
  g.R_eff = 2e-3;
  g.m_eff = 3e-4;
  g.arm_i = 2e-3 - 0.5 * d;
  g.arm_j = 0;
  g.v_rel = v_end;
  g.v_half = v_half;
  g.w_half = Vec3::Zero();
  return g;
}

struct Unclamped {
  double elastic, stiffness, gamma, sum;
};
Unclamped unclamped(const ContactGeometry& g, const PairLaw& law) {
  const double S = 2 * law.E_star * std::sqrt(g.R_eff * g.overlap);
  const double Fel = 4.0 / 3.0 * law.E_star * std::sqrt(g.R_eff) * g.overlap * std::sqrt(g.overlap);
  const double gamma = law.damping * std::sqrt(S * g.m_eff);
  return {Fel, S, gamma, Fel + gamma * (-g.v_rel.dot(g.n))};
}

}  // namespace

TEST(HertzClamp, SeparatingContactReturnsExactlyZero) {
  const PairLaw law = make_law(0.3, 0.0);
  const Vec3 n = Vec3(1, -2, 0.5).normalized();
  for (double d : {1e-8, 1e-7, 1e-6, 1e-5}) {
    // Separating fast: i moves away from j along n.
    const ContactGeometry g = geometry(n, d, 2.0 * n, 2.0 * n);
    const Unclamped u = unclamped(g, law);
    ASSERT_LT(u.sum, 0.0) << "set-up: the unclamped sum must be tensile, d=" << d;
    const NormalResult r = hertz_normal(g, law);
    EXPECT_EQ(r.force, 0.0) << "d=" << d << " unclamped " << u.sum;
    EXPECT_NEAR(r.elastic, u.elastic, 1e-14 * u.elastic);
    EXPECT_NEAR(r.stiffness, u.stiffness, 1e-14 * u.stiffness);
  }
}

TEST(HertzClamp, ApproachingContactReturnsTheSum) {
  const PairLaw law = make_law(0.3, 0.0);
  const Vec3 n = Vec3(0.3, 0.1, -1).normalized();
  for (double d : {1e-8, 1e-6, 1e-5}) {
    const Unclamped el = unclamped(geometry(n, d, Vec3::Zero(), Vec3::Zero()), law);
    // Approaching (any speed), and separating slowly enough that the sum stays compressive.
    const double slow = 0.5 * el.elastic / el.gamma;
    for (double vn : {-3.0, -0.1, -1e-4, 0.0, slow}) {
      const Vec3 slide = Vec3(0.2, 0.3, 0.1) - Vec3(0.2, 0.3, 0.1).dot(n) * n;  // tangential, ignored
      const ContactGeometry g = geometry(n, d, vn * n + slide, vn * n + slide);
      const Unclamped u = unclamped(g, law);
      ASSERT_GT(u.sum, 0.0) << "set-up";
      const NormalResult r = hertz_normal(g, law);
      EXPECT_NEAR(r.force, u.sum, 1e-14 * u.sum) << "d=" << d << " v_n=" << vn;
      if (vn < 0) {
        EXPECT_GT(r.force, r.elastic) << "approach: damping adds to the elastic force";
      } else if (vn > 0) {
        EXPECT_LT(r.force, r.elastic) << "separation: damping subtracts";
      }
    }
  }
  // Without damping (e = 1) the force is the Hertz force whatever the velocity (separating too).
  const PairLaw elastic = make_law(1.0, 0.0);
  const ContactGeometry g = geometry(n, 1e-6, 5.0 * n, 5.0 * n);
  EXPECT_NEAR(hertz_normal(g, elastic).force, unclamped(g, elastic).elastic, 1e-14 * unclamped(g, elastic).elastic);
}

TEST(HertzClamp, MindlinForceNeverExceedsCoulombCap) {
  Rng rng(20240611);
  const double dt = 1e-6;
  int capped = 0, free = 0;
  for (double mu : {0.05, 0.3, 1.0}) {
    const PairLaw law = make_law(0.5, mu);
    for (int k = 0; k < 4000; ++k) {
      const Vec3 n = rng.unit();
      const double d = std::pow(10.0, rng.uniform(-8, -5));
      const double speed = std::pow(10.0, rng.uniform(-5, 0.3));
      const Vec3 v_end = speed * rng.unit(), v_half = v_end + 0.1 * speed * rng.unit();
      const ContactGeometry g = geometry(n, d, v_end, v_half);
      const NormalResult nr = hertz_normal(g, law);
      const double cap = mu * nr.force;
      TangentialHistory h;
      if (k % 5 != 0) {  // an old contact (k % 5 == 0: a new one, empty history)
        const Vec3 old_n = (n + 0.2 * rng.unit()).normalized();
        // One draw at a time (the operands of an expression are evaluated in an unspecified order).
        const double scale = std::pow(10.0, rng.uniform(-2, 2)) * std::max(cap, 1e-9);
        const Vec3 u = rng.unit();
        h.force = scale * (u - u.dot(old_n) * old_n).normalized();  // in old_n's tangent plane
        h.stiffness = nr.stiffness * law.tangential_ratio * law.tangential_ratio * rng.uniform(0.5, 1.5);
        h.total = h.force;
      }
      const TangentialHistory before = h;
      const TangentialResult tr = mindlin_tangential(g, law, nr, dt, h);
      const double Ft = tr.force.norm();
      EXPECT_LE(Ft, cap * (1 + 1e-12)) << "mu=" << mu << " k=" << k;
      EXPECT_LE(std::abs(tr.force.dot(n)), 1e-12 * std::max(Ft, 1e-300)) << "F_t not tangential";

      // The trial force, typed again: history rotated into the tangent plane with its magnitude
      // kept, scaled by S_t/S_t,old when S_t fell, minus S dt v_t with S the step's mean stiffness
      // ((S_old + S_t)/2; for a new contact 2/3 S_t over the part of the step since first touch);
      // then the dashpot.
      const double S_t = nr.stiffness * 4 * law.G_star / law.E_star;
      const double gamma_t = law.damping * std::sqrt(nr.stiffness * g.m_eff) * std::sqrt(4 * law.G_star / law.E_star);
      Vec3 Fe = before.force - before.force.dot(n) * n;
      if (Fe.norm() > 0) Fe *= before.force.norm() / Fe.norm();
      if (before.stiffness > S_t) Fe *= S_t / before.stiffness;
      const double approach = -v_half.dot(n) * dt;
      const double S_dt = before.stiffness > 0 ? 0.5 * (before.stiffness + S_t) * dt
                                               : (2.0 / 3.0) * S_t * (approach > d ? d / approach : 1.0) * dt;
      Fe -= S_dt * (v_half - v_half.dot(n) * n);
      const Vec3 trial = Fe - gamma_t * (v_end - v_end.dot(n) * n);
      if (trial.norm() <= cap * (1 - 1e-9)) {
        ++free;
        EXPECT_LE((tr.force - trial).norm(), 1e-12 * trial.norm()) << "below the cap F_t is the trial force";
        EXPECT_LE((h.force - Fe).norm(), 1e-12 * std::max(Fe.norm(), 1e-300)) << "spring history";
      } else if (trial.norm() > cap * (1 + 1e-9)) {
        ++capped;
        EXPECT_NEAR(Ft, cap, 1e-12 * cap) << "slip: F_t at the cap";
        if (cap > 0) {
          EXPECT_GE(tr.force.dot(trial), (1 - 1e-12) * Ft * trial.norm()) << "slip: along the trial force";
        }
        EXPECT_LE((h.force - tr.force).norm(), 1e-12 * std::max(Ft, 1e-300)) << "slip: the spring holds F_t";
      }
    }
  }
  std::printf("  mindlin: %d samples at the cap, %d below it\n", capped, free);
  EXPECT_GT(capped, 1000) << "set-up: too few capped samples";
  EXPECT_GT(free, 500) << "set-up: too few samples below the cap";
}

TEST(HertzClamp, ClampedNormalForceCarriesNoTangentialForce) {
  const PairLaw law = make_law(0.3, 0.5);
  const Vec3 n = Vec3::UnitZ();
  const ContactGeometry g = geometry(n, 1e-6, Vec3(0.5, 0, 2.0), Vec3(0.5, 0, 2.0));  // separating fast, sliding
  const NormalResult nr = hertz_normal(g, law);
  ASSERT_EQ(nr.force, 0.0) << "set-up";
  TangentialHistory h;
  h.force = Vec3(-1e-3, 0, 0);
  h.stiffness = nr.stiffness * law.tangential_ratio * law.tangential_ratio;
  const TangentialResult tr = mindlin_tangential(g, law, nr, 1e-6, h);
  EXPECT_EQ(tr.force.norm(), 0.0);
  EXPECT_EQ(h.force.norm(), 0.0);
}

TEST(HertzClamp, CarrySpringNeverAddsStoredEnergy) {
  Rng rng(7);
  int rose = 0, fell = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 n = rng.unit();
    const Vec3 v = std::pow(10.0, rng.uniform(-6, 2)) * rng.unit();
    const double k_old = std::pow(10.0, rng.uniform(2, 6));
    const double k_new = k_old * std::pow(10.0, rng.uniform(-1, 1));
    const Vec3 c = carry_spring(v, n, k_old, k_new);
    const double before = v.squaredNorm() / (2 * k_old), after = c.squaredNorm() / (2 * k_new);
    EXPECT_LE(after, before * (1 + 1e-12)) << "k=" << k << " k_old=" << k_old << " k_new=" << k_new;
    EXPECT_LE(std::abs(c.dot(n)), 1e-12 * v.norm()) << "not in the tangent plane";
    const double tangential = (v - v.dot(n) * n).norm();
    if (tangential < 1e-6 * v.norm()) continue;  // (nearly) along n: nothing to rotate
    if (k_new >= k_old) {
      ++rose;
      EXPECT_NEAR(c.norm(), v.norm(), 1e-12 * v.norm()) << "rotation keeps the magnitude";
    } else {
      ++fell;
      EXPECT_NEAR(c.norm(), v.norm() * k_new / k_old, 1e-12 * v.norm()) << "unloading scales by k_new/k_old";
    }
  }
  EXPECT_GT(rose, 5000);
  EXPECT_GT(fell, 5000);
  // A history along the new normal cannot be rotated into the tangent plane: dropped, not grown.
  const Vec3 along = carry_spring(Vec3(0, 0, 3), Vec3::UnitZ(), 1e3, 2e3);
  EXPECT_EQ(along.norm(), 0.0);
}
