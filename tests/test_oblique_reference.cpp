// Oblique impacts in the stick / partial-slip / sliding range against an independent, converged
// integration of the same Hertz-Mindlin model (test_oblique_impact.cpp checks this range only
// qualitatively, after Maw, Barber & Fawcett 1976).
//
// Model integrated here (docs/reference-study.md, section 4; hertz.hpp, mindlin.hpp, geometry.hpp), typed again
// from the formulas; of the engine only bagdem::clamped_beta is used:
//   F_el = 4/3 E* sqrt(R*) d^(3/2), S_n = 2 E* sqrt(R* d), gamma_n = 2 sqrt(5/6)|beta| sqrt(S_n m*),
//   F_n  = max(0, F_el + gamma_n d'),                                  |beta| = clamped_beta(e)
//   S_t  = S_n 4G*/E*, gamma_t = gamma_n sqrt(4G*/E*),
//   F_e' = -S_t v_c + F_e min(0, S_t')/S_t       (spring; scaled down with S_t when it unloads)
//   F_t  = F_e - gamma_t v_c, capped |F_t| <= mu F_n; in slip F_e = F_t,
//   arm  = R - d/2: v_c = (relative centre velocity).t - (arm w summed over the spheres),
//   torque on each sphere -arm n x F_t.
// Planar motion in the plane of incidence. State: relative centre position and velocity (2-D), spin
// w (both spheres of a pair spin alike), spring force F_e along the tangent t (carrying the spring
// into the rotating tangent plane with its magnitude kept leaves this scalar unchanged). For the
// pair the line of centres turns during the contact (by ~0.08 rad at v_t/v_n = 4 here), which the
// 2-D state follows; for the wall n is fixed. Integrated with RK4 at t_c / 20000 (elastic predictor,
// Coulomb return mapping after each step, as the model's slip rule states it); the test checks its
// convergence: at t_c / 10000 the results differ by < 2e-4 (ratio) / 2e-4 relative (spin).
// ReferenceReproducesClosedForms checks it against the rigid-body gross-sliding impulse.
//
// Compared: bagdem at its default resolution (40 steps per contact: the automatic step,
// hertz::resolved_step(t_c, a, 40), below half the critical step here), three entry phases within
// a step, for v_t/v_n in {0.1, 0.3, 0.6, 1, 2, 4}, mu in {0.1, 0.5}, e in {0.5, 1}:
//   v_c'/v_c (rebound over incident tangential contact-point velocity, v_c' = v_x' - sum R w', lab
//            frame)   |bagdem - reference| <= 0.02 absolute (2 % of the incident v_c; a relative
//            measure is meaningless where MBF's reversal puts v_c' near 0)
//   spin w'           |bagdem - reference| <= 2 % of the reference spin
// Sphere on a plane (wall z = 0) and two equal spheres colliding obliquely (both spin freely).
// For the pair also exact checks: total linear momentum stays 0 (|P| <= 1e-12 m v_n), total angular
// momentum about the origin (orbital + spin) is conserved to 1e-12 relative (the contact forces are
// equal and opposite and the torque arms add up to the centre distance, so velocity Verlet keeps it
// to rounding), and the two spins are equal to 1e-12 relative (equal arms, equal torques).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "bagdem/contact/hertz_theory.hpp"
#include "bagdem/contact/restitution.hpp"
#include "bagdem/step/simulation.hpp"
#include "scene_builder.hpp"

using namespace bagdem;
using bagdem::testing::SceneBuilder;
using bagdem::testing::sphere_mass;

namespace {

// Steel density and Poisson ratio, softened modulus (the impact is self-similar in the stiffness).
constexpr double kRho = 7800, kE = 2e9, kNu = 0.3, kR = 5e-3, kVn = 1.0;
constexpr double kTolRatio = 0.02;  // absolute, on v_c'/v_c
constexpr double kTolSpin = 0.02;   // relative to the reference spin

// Effective moduli of two equal materials (docs/reference-study.md, section 4), typed again.
double e_star() { return 1.0 / (2 * (1 - kNu * kNu) / kE); }
double g_star() { return 1.0 / (2 * 2 * (2 - kNu) * (1 + kNu) / kE); }
double mass() { return sphere_mass(kRho, kR); }

// ---- the reference ------------------------------------------------------------------------------

struct RefParams {
  bool pair;       // two equal spheres (else sphere on the plane z = 0)
  double m_eff;    // m* (unit: kg)
  double R_eff;    // R* (unit: m)
  double inertia;  // of one sphere (unit: kg m^2)
  double E_star, ratio2;  // E*, S_t/S_n = 4G*/E*
  double damping;  // 2 sqrt(5/6)|beta|
  double mu;
};

RefParams ref_params(bool pair, double e, double mu) {
  const double m = mass();
  return {pair, pair ? m / 2 : m, pair ? kR / 2 : kR, 0.4 * m * kR * kR, e_star(), 4 * g_star() / e_star(),
          2 * std::sqrt(5.0 / 6.0) * clamped_beta(e), mu};
}

struct RefResult {
  double vc_ratio;  // v_c' / v_c, lab frame (x)
  double w;         // spin after (each sphere) (unit: rad/s)
  double vn;        // normal separation speed, lab frame (z) (unit: m/s)
};

// First contact at relative position (0, 2R) (pair) or height R (wall), relative velocity
// (vt, -vn) in the (x, z) plane, no spin.
RefResult reference(const RefParams& p, double vn, double vt, double steps_per_tc) {
  using State = std::array<double, 6>;  // r_x, r_z, v_x, v_z, w, F_e
  const int spheres = p.pair ? 2 : 1;
  const double k = 4.0 / 3.0 * p.E_star * std::sqrt(p.R_eff);
  const double tc = 2.87 * std::pow(p.m_eff * p.m_eff / (p.R_eff * p.E_star * p.E_star * vn), 0.2);
  const double h = tc / steps_per_tc;
  struct Contact {
    double d, nx, nz, tx, tz, ddot, arm, vc, Fn, Ft, St, gt;
  };
  auto contact = [&](const State& y) {
    Contact c{};
    if (p.pair) {
      const double dist = std::hypot(y[0], y[1]);
      c.d = 2 * kR - dist, c.nx = y[0] / dist, c.nz = y[1] / dist;
    } else {
      c.d = kR - y[1], c.nx = 0, c.nz = 1;
    }
    c.tx = c.nz, c.tz = -c.nx;  // t = y x n: then (w y) x n = w t
    c.ddot = -(y[2] * c.nx + y[3] * c.nz);
    const double d = std::max(c.d, 0.0);
    c.arm = kR - 0.5 * d;
    c.vc = y[2] * c.tx + y[3] * c.tz - spheres * c.arm * y[4];
    if (c.d <= 0) return c;  // no contact: no forces
    const double Sn = 2 * p.E_star * std::sqrt(p.R_eff * d);
    const double gn = p.damping * std::sqrt(Sn * p.m_eff);
    c.Fn = std::max(0.0, k * d * std::sqrt(d) + gn * c.ddot);
    c.St = Sn * p.ratio2, c.gt = gn * std::sqrt(p.ratio2);
    const double cap = p.mu * c.Fn;
    c.Ft = std::clamp(y[5] - c.gt * c.vc, -cap, cap);
    return c;
  };
  auto rhs = [&](const State& y) {
    const Contact c = contact(y);
    if (c.d <= 0) return State{y[2], y[3], 0, 0, 0, 0};
    // S_t ~ sqrt(d): S_t'/S_t = d'/(2d); the spring is scaled only while S_t falls.
    const double unload = c.ddot < 0 ? y[5] * 0.5 * c.ddot / c.d : 0.0;
    const double Fx = c.Fn * c.nx + c.Ft * c.tx, Fz = c.Fn * c.nz + c.Ft * c.tz;
    return State{y[2], y[3], Fx / p.m_eff, Fz / p.m_eff, -c.arm * c.Ft / p.inertia, -c.St * c.vc + unload};
  };
  State y{0, p.pair ? 2 * kR : kR, vt, -vn, 0, 0};
  auto axpy = [](const State& a, double s, const State& b) {
    State r;
    for (int i = 0; i < 6; ++i) r[i] = a[i] + s * b[i];
    return r;
  };
  bool started = false, ended = false;
  for (long it = 0; it < 20 * static_cast<long>(steps_per_tc) && !ended; ++it) {
    const State k1 = rhs(y), k2 = rhs(axpy(y, 0.5 * h, k1)), k3 = rhs(axpy(y, 0.5 * h, k2)),
                k4 = rhs(axpy(y, h, k3));
    for (int i = 0; i < 6; ++i) y[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    const Contact c = contact(y);
    // Coulomb return mapping: a trial force above the cap slips, the spring holds the capped force.
    if (c.d > 0 && std::abs(y[5] - c.gt * c.vc) > p.mu * c.Fn) y[5] = c.Ft;
    started = started || c.d > 0;
    ended = started && c.d <= 0;
  }
  EXPECT_TRUE(ended) << "reference contact did not end";
  return {(y[2] - spheres * kR * y[4]) / vt, y[4], y[3]};
}

// ---- bagdem -------------------------------------------------------------------------------------

struct Measured {
  RefResult r;
  double P = 0;   // |total linear momentum| after (pair) (unit: kg m/s)
  double dL = 0;  // |L after - L before| / |L before| (pair)
  double dw = 0;  // |w0 - w1| / |w1| (pair)
};

// The scene for one (e, mu) (building it calibrates the damping, ~0.1 s, so once per law): the step
// is what the automatic rule gives at expected speed v_n (40 steps per contact; the damping time
// does not bind at e >= 0.5), checked against half the critical step.
Scene base_scene(bool pair, double e, double mu) {
  SceneBuilder b;
  b.material("soft steel", kRho, kE, kNu).interaction(e, mu, 0.0);
  if (pair) {
    b.particle(Vec3::Zero(), Vec3::Zero(), kR).particle(Vec3::Zero(), Vec3::Zero(), kR);
  } else {
    b.plane(Vec3::Zero(), Vec3::UnitZ()).particle(Vec3::Zero(), Vec3::Zero(), kR);
  }
  Scene s = b.dt(1.0).build();
  const double m_eff = pair ? mass() / 2 : mass(), R_eff = pair ? kR / 2 : kR;
  const PairLaw& law = s.laws(0, 0);
  const double tc = hertz::contact_time(m_eff, R_eff, law.E_star, kVn);
  s.dt = hertz::resolved_step(tc, hertz::damping_parameter(law.damping), 40);
  const double delta = hertz::max_overlap(m_eff, R_eff, law.E_star, kVn);
  const double S_n = 2 * law.E_star * std::sqrt(R_eff * delta), S_t = S_n * 4 * law.G_star / law.E_star;
  const double crit = std::min(hertz::critical_step(std::sqrt(S_n / m_eff), 0.5 * law.damping),
                               hertz::critical_step(std::sqrt(3.5 * S_t / m_eff), std::sqrt(3.5) * 0.5 * law.damping));
  EXPECT_LT(s.dt, 0.5 * crit);
  return s;
}

// Wall: the sphere moves (vt, 0, -vn) towards the plane z = 0. Pair: sphere 1 moves (vt/2, 0, -vn/2),
// sphere 0 the opposite, offset along x so that they first touch with the line of centres along z
// (as in the reference). The first contact sample falls at `phase` within a step.
Measured bagdem_impact(const Scene& base, double vt, double phase) {
  Scene scene = base;
  const bool pair = scene.particles.size() == 2;
  const double t_gap = (2 + phase) * scene.dt;  // flight time to the first touch
  if (pair) {
    scene.particles[1].x = Vec3(-vt / 2 * t_gap, 0, kR + kVn / 2 * t_gap);
    scene.particles[1].v = Vec3(vt / 2, 0, -kVn / 2);
    scene.particles[0].x = -scene.particles[1].x;
    scene.particles[0].v = -scene.particles[1].v;
  } else {
    scene.particles[0].x = Vec3(0, 0, kR + kVn * t_gap);
    scene.particles[0].v = Vec3(vt, 0, -kVn);
  }
  Simulation sim(scene);
  const auto& p = sim.particles();
  const double m = mass(), I = 0.4 * m * kR * kR;
  auto L = [&] {
    Vec3 l = Vec3::Zero();
    for (std::size_t i = 0; i < p.size(); ++i) l += m * p.x[i].cross(p.v[i]) + I * p.w[i];
    return l;
  };
  const Vec3 L0 = L();
  auto touching = [&] { return pair ? (p.x[1] - p.x[0]).norm() < 2 * kR : p.x[0].z() < kR; };
  bool in = false, out = false;
  for (int s = 0; s < 100000 && !out; ++s) {
    sim.step();
    in = in || touching();
    out = in && !touching();
  }
  EXPECT_TRUE(out) << "the contact never closed";
  sim.step();
  Measured r;
  if (!pair) {
    r.r = {(p.v[0].x() - kR * p.w[0].y()) / vt, p.w[0].y(), p.v[0].z()};
  } else {
    const Vec3 v = p.v[1] - p.v[0];
    r.r = {(v.x() - kR * (p.w[0].y() + p.w[1].y())) / vt, p.w[1].y(), v.z()};
    r.P = (m * (p.v[0] + p.v[1])).norm();
    r.dL = (L() - L0).norm() / L0.norm();
    r.dw = (p.w[0] - p.w[1]).norm() / p.w[1].norm();
  }
  return r;
}

void compare_against_reference(bool pair) {
  const double m = mass();
  const char* what = pair ? "pair" : "wall";
  double worst_ratio = 0, worst_spin = 0, worst_conv_ratio = 0, worst_conv_spin = 0;
  double worst_P = 0, worst_L = 0, worst_w = 0;
  for (double e : {0.5, 1.0}) {
    for (double mu : {0.1, 0.5}) {
      const Scene base = base_scene(pair, e, mu);
      const RefParams rp = ref_params(pair, e, mu);
      for (double ratio : {0.1, 0.3, 0.6, 1.0, 2.0, 4.0}) {
        const double vt = ratio * kVn;
        const RefResult ref = reference(rp, kVn, vt, 20000), coarse = reference(rp, kVn, vt, 10000);
        // The reference is converged far below the tolerances.
        worst_conv_ratio = std::max(worst_conv_ratio, std::abs(coarse.vc_ratio - ref.vc_ratio));
        worst_conv_spin = std::max(worst_conv_spin, std::abs(coarse.w / ref.w - 1));
        EXPECT_LT(std::abs(coarse.vc_ratio - ref.vc_ratio), 2e-4) << "reference not converged";
        EXPECT_LT(std::abs(coarse.w / ref.w - 1), 2e-4) << "reference not converged";
        double er = 0, es = 0;
        for (double phase : {0.0, 0.37, 0.71}) {
          const Measured b = bagdem_impact(base, vt, phase);
          er = std::max(er, std::abs(b.r.vc_ratio - ref.vc_ratio));
          es = std::max(es, std::abs(b.r.w / ref.w - 1));
          EXPECT_NEAR(b.r.vc_ratio, ref.vc_ratio, kTolRatio)
              << what << ": v_c'/v_c, e=" << e << " mu=" << mu << " vt/vn=" << ratio << " phase=" << phase;
          EXPECT_NEAR(b.r.w, ref.w, kTolSpin * std::abs(ref.w))
              << what << ": spin, e=" << e << " mu=" << mu << " vt/vn=" << ratio << " phase=" << phase;
          if (pair) {
            worst_P = std::max(worst_P, b.P / (m * kVn));
            worst_L = std::max(worst_L, b.dL);
            worst_w = std::max(worst_w, b.dw);
            EXPECT_LE(b.P, 1e-12 * m * kVn) << "linear momentum, e=" << e << " mu=" << mu << " vt/vn=" << ratio;
            EXPECT_LE(b.dL, 1e-12) << "angular momentum, e=" << e << " mu=" << mu << " vt/vn=" << ratio;
            EXPECT_LE(b.dw, 1e-12) << "spins differ, e=" << e << " mu=" << mu << " vt/vn=" << ratio;
          }
        }
        worst_ratio = std::max(worst_ratio, er);
        worst_spin = std::max(worst_spin, es);
        std::printf("  %s e=%.1f mu=%.1f vt/vn=%3.1f: reference v_c'/v_c=%+.4f wR/v_n=%.4f | bagdem worst "
                    "|d ratio|=%.2e |d w|/w=%.2e\n",
                    what, e, mu, ratio, ref.vc_ratio, ref.w * kR / kVn, er, es);
      }
    }
  }
  std::printf("  %s: worst |d(v_c'/v_c)| = %.3e (tol %.0e), worst |d w|/w = %.3e (tol %.0e); "
              "reference t_c/10000 vs t_c/20000: %.1e, %.1e\n",
              what, worst_ratio, kTolRatio, worst_spin, kTolSpin, worst_conv_ratio, worst_conv_spin);
  if (pair)
    std::printf("  pair: worst |P|/(m v_n) = %.1e, |dL|/L = %.1e, |w0-w1|/|w| = %.1e\n", worst_P, worst_L, worst_w);
}

}  // namespace

TEST(ObliqueReference, SphereOnPlaneMatchesIntegratedModel) { compare_against_reference(false); }

TEST(ObliqueReference, TwoSpheresMatchIntegratedModelAndConserve) { compare_against_reference(true); }

// The reference itself against closed forms it must reproduce, sphere on plane:
//  - its normal restitution is the requested e (clamped_beta's calibration): 1e-4 absolute;
//  - gross sliding (v_t/v_n = 4, mu = 0.1 > 7/2 mu (1+e)): tangential velocity loses exactly
//    mu (1+e_n) v_n (1e-3 relative) and the spin is 5/2 mu (1+e_n) v_n / R lowered by the lever arm
//    R - d/2 during the contact (within 1 %, and below);
//  - no friction: v_c unchanged (1e-12), e = 1 returns the approach speed (1e-6).
TEST(ObliqueReference, ReferenceReproducesClosedForms) {
  for (double e : {0.5, 1.0}) {
    const RefResult r = reference(ref_params(false, e, 0.1), kVn, 4 * kVn, 20000);
    EXPECT_NEAR(r.vn, e * kVn, 1e-4) << "e=" << e;
    const double dv = 0.1 * (1 + r.vn / kVn) * kVn, w = 2.5 * dv / kR;
    const double vt_after = r.vc_ratio * 4 * kVn + kR * r.w;
    EXPECT_NEAR(4 * kVn - vt_after, dv, 1e-3 * dv) << "e=" << e;
    EXPECT_NEAR(r.w, w, 0.01 * w) << "e=" << e;
    EXPECT_LT(r.w, w) << "e=" << e;
    std::printf("  reference, gross sliding e=%.1f: e_n=%.6f dv_t/[mu(1+e)v_n]=%.6f w/[5/2 mu(1+e)v_n/R]=%.5f\n", e,
                r.vn / kVn, (4 * kVn - vt_after) / dv, r.w / w);
  }
  const RefResult r = reference(ref_params(false, 1.0, 0.0), kVn, 0.5 * kVn, 20000);
  EXPECT_NEAR(r.vn, kVn, 1e-6);
  EXPECT_NEAR(r.vc_ratio, 1.0, 1e-12);
}
