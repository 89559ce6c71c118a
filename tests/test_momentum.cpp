// Momentum conservation of the pair contacts (src/step/pair_kernel.cpp, contact/*.hpp).
//
// A cluster of balls converging on its centre in the middle of a large box, with friction, rolling
// resistance, damping and spin, but no gravity and no wall contact during the run (the test checks
// this every step): the only forces are pair forces, equal and opposite, and the pair torques
// balance the moment of the tangential force about the origin, since x_i - x_j = (arm_i + arm_j) n.
// Velocity Verlet conserves both linear momentum sum m v and angular momentum
// sum (m x × v + I w) exactly for such forces (each half kick adds sum of F = 0 and
// sum (x × F + T) = 0 at one configuration; the drift leaves x × v unchanged), so only round-off
// remains.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "bagdem/step/simulation.hpp"
#include "rng.hpp"
#include "scene_builder.hpp"

using namespace bagdem;
using bagdem::testing::Rng;
using bagdem::testing::SceneBuilder;

namespace {


struct Totals {
  Vec3 P = Vec3::Zero(), L = Vec3::Zero();
  double P_scale = 0, L_scale = 0;  // sum m|v| and sum (m |x||v| + I |w|): the size of the terms
};

Totals totals(const Particles& p) {
  Totals t;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double I = 1.0 / p.inv_inertia[i];
    t.P += p.mass[i] * p.v[i];
    t.L += p.mass[i] * p.x[i].cross(p.v[i]) + I * p.w[i];
    t.P_scale += p.mass[i] * p.v[i].norm();
    t.L_scale += p.mass[i] * p.x[i].norm() * p.v[i].norm() + I * p.w[i].norm();
  }
  return t;
}

// 40 balls (r 3-5 mm, E = 1e7 Pa) in a sphere of radius 3 cm centred at c = (0.3, -0.2, 0.1) m,
// converging (v = V - k (x - c) + noise, k = 12 /s), drifting at V, spinning up to 60 rad/s, in a
// 2 m box. 0.1 s = 10000 steps of 1e-5 s.
Scene cluster(double mu, double mu_r, std::uint64_t seed) {
  SceneBuilder b;
  b.material("glass", 2500, 1e7, 0.3).interaction(0.5, mu, mu_r);
  b.box(Vec3::Constant(-1), Vec3::Constant(1)).dt(1e-5).duration(0.1);
  const Vec3 c(0.3, -0.2, 0.1), V(0.3, 0.1, -0.2);
  Rng rng(seed);
  std::vector<Vec3> xs;
  std::vector<double> rs;
  while (xs.size() < 40) {
    const double r = rng.uniform(0.003, 0.005);
    const Vec3 d = draw_vec3([&] { return rng.uniform(-0.03, 0.03); });
    if (d.norm() > 0.03) continue;
    const Vec3 x = c + d;
    bool ok = true;
    for (std::size_t k = 0; k < xs.size() && ok; ++k) ok = (x - xs[k]).norm() > r + rs[k] + 2e-4;
    if (!ok) continue;
    xs.push_back(x);
    rs.push_back(r);
    const Vec3 noise = draw_vec3([&] { return rng.uniform(-0.1, 0.1); });
    const Vec3 w = draw_vec3([&] { return rng.uniform(-60, 60); });
    b.particle(x, V - 12.0 * d + noise, r, 0, w);
  }
  return b.build();
}

struct MomentumRun {
  double dP = 0, dL = 0;                 // relative changes (to P_scale, L_scale at t = 0)
  double dP_max = 0, dL_max = 0;         // max over the run
  double dL_spin = 0;                    // change of the spin part alone, relative to sum I|w| at t = 0
  std::size_t openings = 0, max_contacts = 0;
  bool touched_wall = false;
  EnergySample e;
};

MomentumRun run_cluster(const Scene& s) {
  Simulation sim(s);
  MomentumRun out;
  const Particles& p = sim.particles();
  const std::size_t n = p.size();
  const Totals t0 = totals(p);
  Vec3 spin0 = Vec3::Zero();
  double spin_scale = 0;
  for (std::size_t i = 0; i < n; ++i) {
    spin0 += p.w[i] / p.inv_inertia[i];
    spin_scale += p.w[i].norm() / p.inv_inertia[i];
  }
  std::vector<char> closed(n * n, 0);
  for (std::uint64_t k = 1; k <= s.total_steps(); ++k) {
    sim.step();
    for (std::size_t i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a)
        out.touched_wall = out.touched_wall || p.x[i][a] - p.radius[i] <= s.cavity_lo[a] ||
                           p.x[i][a] + p.radius[i] >= s.cavity_hi[a];
      for (std::size_t j = i + 1; j < n; ++j) {
        const double c = p.radius[i] + p.radius[j];
        const char now = (p.x[i] - p.x[j]).squaredNorm() < c * c;
        out.openings += closed[i * n + j] && !now;
        closed[i * n + j] = now;
      }
    }
    out.max_contacts = std::max(out.max_contacts, sim.contact_count());
    if (k % 100 == 0) {
      const Totals t = totals(p);
      out.dP_max = std::max(out.dP_max, (t.P - t0.P).norm() / t0.P_scale);
      out.dL_max = std::max(out.dL_max, (t.L - t0.L).norm() / t0.L_scale);
    }
  }
  const Totals t1 = totals(p);
  out.dP = (t1.P - t0.P).norm() / t0.P_scale;
  out.dL = (t1.L - t0.L).norm() / t0.L_scale;
  Vec3 spin1 = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) spin1 += p.w[i] / p.inv_inertia[i];
  out.dL_spin = (spin1 - spin0).norm() / spin_scale;
  out.e = sim.energy();
  return out;
}

}  // namespace

// Reference: sum m v constant (pair forces are equal and opposite; no wall, no gravity).
// Tolerance 1e-12 of sum m|v| (measured ~6e-16). The scene must really collide
// (>= 40 contact openings, several contacts at once) and never touch a wall.
TEST(Momentum, LinearMomentumConservedWithFriction) {
  for (std::uint64_t seed : {1u, 2u}) {
    const Scene s = cluster(0.5, 0.0, seed);
    ASSERT_TRUE(s.models.tangential);
    const MomentumRun r = run_cluster(s);
    std::printf("[momentum] seed %llu: %zu contact openings, up to %zu contacts; |dP|/sum m|v| = %.3e "
                "(max %.3e); D_t = %.3e J\n",
                static_cast<unsigned long long>(seed), r.openings, r.max_contacts, r.dP, r.dP_max,
                r.e.dissipated_tangential);
    EXPECT_FALSE(r.touched_wall);
    EXPECT_GE(r.openings, 40u);
    EXPECT_GE(r.max_contacts, 5u);
    EXPECT_GT(r.e.dissipated_tangential, 0.0);  // friction acted
    EXPECT_LT(r.dP, 1e-12);
    EXPECT_LT(r.dP_max, 1e-12);
  }
}

// Reference: sum (m x × v + I w) about the origin constant (the cluster sits 0.37 m from the origin,
// so orbital terms are large and a torque imbalance of the pair law would show). Friction and EPSD
// rolling resistance on; the spin part alone must change substantially (by > 10% of sum I|w|, so the
// tangential torques act) while the total changes by < 1e-12 of sum (m|x||v| + I|w|) (round-off of
// 1e4 steps: ~3e-14 measured).
TEST(Momentum, AngularMomentumWithSpinConservedWithFriction) {
  for (std::uint64_t seed : {3u, 4u}) {
    const Scene s = cluster(0.5, 0.1, seed);
    ASSERT_TRUE(s.models.tangential);
    ASSERT_TRUE(s.models.rolling);
    const MomentumRun r = run_cluster(s);
    std::printf("[momentum] seed %llu: %zu contact openings; |dL|/scale = %.3e (max %.3e); spin part "
                "changed by %.3e; |dP| %.3e; D_t = %.3e J, D_r = %.3e J\n",
                static_cast<unsigned long long>(seed), r.openings, r.dL, r.dL_max, r.dL_spin, r.dP,
                r.e.dissipated_tangential, r.e.dissipated_rolling);
    EXPECT_FALSE(r.touched_wall);
    EXPECT_GE(r.openings, 40u);
    EXPECT_GT(r.dL_spin, 0.1);
    EXPECT_GT(r.e.dissipated_rolling, 0.0);
    EXPECT_LT(r.dL, 1e-12);
    EXPECT_LT(r.dL_max, 1e-12);
    EXPECT_LT(r.dP, 1e-12);
  }
}
