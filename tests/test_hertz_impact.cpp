// Elastic Hertz impacts against the closed-form theory (hertz_theory.hpp; Johnson, Contact Mechanics,
// 1985, eqs. 11.23-11.24): head-on sphere-sphere and sphere-plane impacts without gravity, e = 1
// (no damping), no friction. Measured: contact duration (entry and exit instants interpolated
// linearly between steps in the overlap), maximum overlap (parabola through the three largest
// samples) and the rebound speed.
//
// References and tolerances:
//   t_c       = hertz::contact_time(m*, R*, E*, v)  tolerance 1 % relative
//   delta_max = hertz::max_overlap(m*, R*, E*, v)   tolerance 1 % relative
//   (the exact Hertz constant is 2 (15/16)^(2/5) (2/5) B(2/5, 1/2) = 2.868254, 6e-4 below the 2.87
//   of contact_time, well inside the 1 %; the tolerance also covers the time discretisation,
//   dt = t_c / 200)
//   t_c against the exact constant 2.868254                    tolerance 1e-4 relative (a sharper
//   check of the integration and of the interpolated entry/exit instants)
//   rebound speed = approach speed (e = 1, no damping)  tolerance 1e-3 relative (velocity Verlet is
//   symplectic; its error for the non-smooth Hertz force is O(dt^2)-small at 200 steps per contact).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "bagdem/contact/hertz_theory.hpp"
#include "bagdem/step/simulation.hpp"
#include "scene_builder.hpp"

using namespace bagdem;
using bagdem::testing::SceneBuilder;
using bagdem::testing::sphere_mass;

namespace {

struct Mat {
  const char* name;
  double rho, E, nu;
};
const Mat kSteel{"steel", 7800, 200e9, 0.3};
const Mat kGlass{"glass", 2500, 70e9, 0.22};

constexpr double kStepsPerContact = 200;
// 2 (15/16)^(2/5) (2/5) Gamma(2/5) Gamma(1/2) / Gamma(9/10): t_c = this (m*^2/(R* E*^2 v))^(1/5).
const double kExactHertzConstant =
    2 * std::pow(15.0 / 16.0, 0.4) * 0.4 * std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);

struct ImpactMeasure {
  double t_contact = 0;    // interpolated contact duration (unit: s)
  double max_overlap = 0;  // (unit: m)
  double v_after = 0;      // separation speed after the contact (unit: m/s)
  double t_ref = 0, d_ref = 0;
};

// Interpolated zero crossing of the overlap between samples (t0, d0) and (t0 + dt, d1).
double crossing(double t0, double dt, double d0, double d1) { return t0 + dt * d0 / (d0 - d1); }

// Peak of the parabola through (-1, a), (0, b), (1, c) (equal spacing).
double parabola_peak(double a, double b, double c) {
  const double den = a - 2 * b + c;
  if (den >= 0) return b;
  const double s = 0.5 * (a - c) / den;
  return b - 0.25 * (a - c) * s;
}

// Runs the simulation until the overlap (returned by `overlap`) has opened and closed again.
template <class Overlap, class Separation>
ImpactMeasure run_impact(Simulation& sim, double dt, Overlap overlap, Separation separation) {
  ImpactMeasure r;
  double prev = overlap(), prev2 = prev;
  double t_in = -1, t_out = -1;
  bool in = false;
  double peak = 0;
  for (int s = 0; s < 20000 && t_out < 0; ++s) {
    const double t0 = sim.time();
    sim.step();
    const double d = overlap();
    if (!in && d > 0) {
      in = true;
      t_in = crossing(t0, dt, prev, d);
    }
    if (in && prev > peak && prev >= d && prev >= prev2) peak = parabola_peak(prev2, prev, d);
    if (in && d <= 0) t_out = crossing(t0, dt, prev, d);
    prev2 = prev;
    prev = d;
  }
  r.t_contact = t_out - t_in;
  r.max_overlap = peak;
  r.v_after = separation();
  return r;
}

// Head-on impact of spheres r1 (material a) and r2 at relative speed v, centre of mass at rest.
ImpactMeasure sphere_sphere_impact(const Mat& a, double r1, double r2, double v) {
  const double m1 = sphere_mass(a.rho, r1), m2 = sphere_mass(a.rho, r2);
  const double m_eff = m1 * m2 / (m1 + m2), R_eff = r1 * r2 / (r1 + r2);
  const Material mat{a.name, a.rho, a.E, a.nu};
  const double E_star = effective_youngs(mat, mat);
  const double tc = hertz::contact_time(m_eff, R_eff, E_star, v);
  const double dt = tc / kStepsPerContact;
  const double gap = 3.37 * v * dt;  // contact starts inside a step, after a few free steps
  Scene scene = SceneBuilder()
                    .material(a.name, a.rho, a.E, a.nu)
                    .interaction(1.0, 0.0, 0.0)
                    .particle(Vec3(r1 + 0.5 * gap, 0, 0), Vec3(-v * m2 / (m1 + m2), 0, 0), r1)
                    .particle(Vec3(-r2 - 0.5 * gap, 0, 0), Vec3(v * m1 / (m1 + m2), 0, 0), r2)
                    .dt(dt)
                    .build();
  Simulation sim(scene);
  const auto& p = sim.particles();
  ImpactMeasure r = run_impact(
      sim, dt, [&] { return r1 + r2 - (p.x[0] - p.x[1]).norm(); },
      [&] { return (p.v[0] - p.v[1]).dot((p.x[0] - p.x[1]).normalized()); });
  r.t_ref = tc;
  r.d_ref = hertz::max_overlap(m_eff, R_eff, E_star, v);
  return r;
}

// Sphere r (material a) hitting the plane z = 0 (same material) at speed v.
ImpactMeasure sphere_wall_impact(const Mat& a, double r, double v) {
  const double m = sphere_mass(a.rho, r);
  const Material mat{a.name, a.rho, a.E, a.nu};
  const double E_star = effective_youngs(mat, mat);  // sphere-wall: wall of the same material
  const double tc = hertz::contact_time(m, r, E_star, v);
  const double dt = tc / kStepsPerContact;
  const double gap = 3.37 * v * dt;
  Scene scene = SceneBuilder()
                    .material(a.name, a.rho, a.E, a.nu)
                    .interaction(1.0, 0.0, 0.0)
                    .plane(Vec3(0, 0, 0), Vec3(0, 0, 1))
                    .particle(Vec3(0, 0, r + gap), Vec3(0, 0, -v), r)
                    .dt(dt)
                    .build();
  Simulation sim(scene);
  const auto& p = sim.particles();
  ImpactMeasure res = run_impact(
      sim, dt, [&] { return r - p.x[0].z(); }, [&] { return p.v[0].z(); });
  res.t_ref = tc;
  res.d_ref = hertz::max_overlap(m, r, E_star, v);
  return res;
}

void check(const ImpactMeasure& r, double v, const char* what) {
  const double et = r.t_contact / r.t_ref - 1, ed = r.max_overlap / r.d_ref - 1;
  const double ev = r.v_after / v - 1;
  std::printf("  %-16s v=%5.2f m/s  t_c err %+.2e (vs exact constant %+.2e)  delta_max err %+.2e  rebound err %+.2e\n",
              what, v, et, r.t_contact / (r.t_ref * kExactHertzConstant / 2.87) - 1, ed, ev);
  EXPECT_NEAR(r.t_contact, r.t_ref, 0.01 * r.t_ref) << what << " v=" << v;
  const double t_exact = r.t_ref * kExactHertzConstant / 2.87;
  EXPECT_NEAR(r.t_contact, t_exact, 1e-4 * t_exact) << what << " v=" << v;
  EXPECT_NEAR(r.max_overlap, r.d_ref, 0.01 * r.d_ref) << what << " v=" << v;
  EXPECT_NEAR(r.v_after, v, 1e-3 * v) << what << " v=" << v;
}

}  // namespace

TEST(HertzImpact, SphereSphereSteelMatchesTheory) {
  for (double v : {0.01, 0.1, 1.0, 10.0}) check(sphere_sphere_impact(kSteel, 5e-3, 5e-3, v), v, "steel 5mm-5mm");
}

TEST(HertzImpact, SphereSphereGlassUnequalRadiiMatchesTheory) {
  // Unequal radii: m* and R* of the pair, not of one sphere.
  for (double v : {0.01, 0.1, 1.0, 10.0}) check(sphere_sphere_impact(kGlass, 4e-3, 2.5e-3, v), v, "glass 4mm-2.5mm");
}

TEST(HertzImpact, SphereWallMatchesTheory) {
  // Wall: R* = R, m* = m, E* of the sphere against a wall of the same material.
  for (double v : {0.01, 0.1, 1.0, 10.0}) check(sphere_wall_impact(kSteel, 5e-3, v), v, "steel 5mm-wall");
  for (double v : {0.01, 1.0}) check(sphere_wall_impact(kGlass, 3e-3, v), v, "glass 3mm-wall");
}
