// Energy conservation and the energy budget of the stepper (src/step/, docs/reference-study.md, section 4).
//
//  * ElasticGasConservesEnergy: e = 1, no friction, no gravity, closed fixed box. Velocity Verlet is
//    symplectic (Swope et al. 1982), and the undamped Hertz law is conservative, so kinetic + elastic
//    energy must stay at its initial value up to the integrator's bounded error over >= 1e4
//    collisions (no secular drift).
//  * EnergyErrorIsSecondOrderInDt: the energy error seen between collisions must fall at least
//    fourfold when dt halves (Verlet is second order; for the C^1 Hertz force the per-impact error of
//    the shadow energy scales as (dt/t_c)^(5/2), i.e. ratio ~5.7).
//  * BudgetClosesShakenFrictionalBox / BudgetClosesWithRollingResistance / BudgetClosesWithTheHookeLaw:
//    damped, frictional balls in a harmonically shaken box under gravity (Hertz-Mindlin, and the
//    linear spring-dashpot): W_cavity + W_gravity = (K + U) - (K0 + U0) + D.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "bagdem/motion/motion.hpp"
#include "bagdem/step/simulation.hpp"
#include "rng.hpp"
#include "scene_builder.hpp"

using namespace bagdem;
using bagdem::testing::Rng;
using bagdem::testing::SceneBuilder;

namespace {


// Places n balls with radii in [rmin, rmax] at random in the box [lo, hi], no overlap with each
// other (gap >= `gap`) or with the walls. Velocities: components uniform in [-vmax, vmax].
void random_gas(SceneBuilder& b, Rng& rng, int n, double rmin, double rmax, const Vec3& lo,
                const Vec3& hi, double vmax, double gap) {
  std::vector<Vec3> xs;
  std::vector<double> rs;
  int tries = 0;
  while (static_cast<int>(xs.size()) < n) {
    if (++tries > 1'000'000) throw std::runtime_error("random_gas: box too full");
    const double r = rng.uniform(rmin, rmax);
    const double z = rng.uniform(lo.z() + r + gap, hi.z() - r - gap), y = rng.uniform(lo.y() + r + gap, hi.y() - r - gap),
                 x_ = rng.uniform(lo.x() + r + gap, hi.x() - r - gap);  // draw_vec3's order
    const Vec3 x(x_, y, z);
    bool ok = true;
    for (std::size_t k = 0; k < xs.size() && ok; ++k) ok = (x - xs[k]).norm() > r + rs[k] + gap;
    if (!ok) continue;
    xs.push_back(x);
    rs.push_back(r);
    const Vec3 v = draw_vec3([&] { return rng.uniform(-vmax, vmax); });
    b.particle(x, v, r);
  }
}

// Counts collisions as contact openings (closed -> open transitions), ball-ball and ball-wall,
// independently of the engine's pair list: all pairs are tested by brute force, walls are the six
// faces of a fixed box [lo, hi].
class CollisionCounter {
 public:
  CollisionCounter(std::size_t n, const Vec3& lo, const Vec3& hi)
      : n_(n), lo_(lo), hi_(hi), pair_(n * n, 0), wall_(6 * n, 0) {}
  void update(const Particles& p) {
    for (std::size_t i = 0; i < n_; ++i) {
      for (std::size_t j = i + 1; j < n_; ++j) {
        const double c = p.radius[i] + p.radius[j];
        const char closed = (p.x[i] - p.x[j]).squaredNorm() < c * c;
        char& s = pair_[i * n_ + j];
        if (s && !closed) ++pair_openings;
        s = closed;
      }
      for (int k = 0; k < 3; ++k) {
        const char c_lo = p.x[i][k] - p.radius[i] < lo_[k];
        const char c_hi = p.x[i][k] + p.radius[i] > hi_[k];
        char& a = wall_[6 * i + 2 * k];
        char& b = wall_[6 * i + 2 * k + 1];
        if (a && !c_lo) ++wall_openings;
        if (b && !c_hi) ++wall_openings;
        a = c_lo;
        b = c_hi;
      }
    }
  }
  std::size_t pair_openings = 0, wall_openings = 0;

 private:
  std::size_t n_;
  Vec3 lo_, hi_;
  std::vector<char> pair_, wall_;
};

double stored(const EnergySample& e) { return e.kinetic + e.elastic; }

// The elastic gas of tests (a) and (b): n glass-like balls, radius 4-6 mm, E = 1e7 Pa (soft, so
// that t_c ~ 1 ms and dt can be large), in a closed 6 cm box, velocity components up to 1 m/s.
Scene elastic_gas(double dt, std::uint64_t seed, double duration, int n) {
  SceneBuilder b;
  b.material("glass", 2500, 1e7, 0.3).interaction(1.0, 0.0, 0.0);
  const Vec3 lo(0, 0, 0), hi(0.06, 0.06, 0.06);
  b.box(lo, hi).dt(dt).duration(duration);
  Rng rng(seed);
  random_gas(b, rng, n, 0.004, 0.006, lo, hi, 1.0, 0.0005);
  return b.build();
}

struct GasRun {
  double max_rel_error_all = 0;     // max |E - E0|/E0 over every sample (in contact or not)
  double max_rel_error_free = 0;    // same, only samples with contact_count() == 0
  double path_free = 0;             // sum of |E_k - E_{k-1}|/E0 between consecutive contact-free samples
  double final_rel_error = 0;
  std::size_t pair_collisions = 0, wall_collisions = 0, free_samples = 0;
};

// Samples every `sample_every` steps: all samples, or (all_samples = false) only contact-free ones.
GasRun run_gas(const Scene& s, int sample_every, bool count, bool all_samples) {
  Simulation sim(s);
  GasRun out;
  const double E0 = sim.initial_stored_energy();
  CollisionCounter cc(sim.particles().size(), s.cavity_lo, s.cavity_hi);
  const std::uint64_t steps = s.total_steps();
  double last_free = E0;
  for (std::uint64_t k = 1; k <= steps; ++k) {
    sim.step();
    if (count) cc.update(sim.particles());
    if (k % static_cast<std::uint64_t>(sample_every) == 0 || k == steps) {
      const bool free = sim.contact_count() == 0;
      if (!free && !all_samples && k != steps) continue;
      const double E = stored(sim.energy());
      const double err = std::abs(E - E0) / E0;
      out.max_rel_error_all = std::max(out.max_rel_error_all, err);
      if (free) {
        out.max_rel_error_free = std::max(out.max_rel_error_free, err);
        out.path_free += std::abs(E - last_free) / E0;
        last_free = E;
        ++out.free_samples;
      }
      if (k == steps) out.final_rel_error = err;
    }
  }
  out.pair_collisions = cc.pair_openings;
  out.wall_collisions = cc.wall_openings;
  return out;
}

}  // namespace

// (a) Reference: E(t) = E0 exactly (conservative Hamiltonian system). Tolerance 1e-3 relative,
// on the maximum over all samples (every 10th step, contacts open or closed) over >= 1e4
// collisions. dt = 2e-5 s is ~1/45 of the shortest impact (t_c ~ 0.9 ms at 2 m/s), so the bounded
// in-contact Verlet oscillation is ~(pi dt/t_c)^2/8 ~ 6e-4 of one pair's energy, ~3e-5 of the total.
// Measured: 11463 collisions (6556 ball-ball, 4907 ball-wall), max |dE|/E0 = 2.2e-4, final 1.5e-4.
TEST(Energy, ElasticGasConservesEnergy) {
  const Scene s = elastic_gas(2e-5, 11, 3.0, 40);  // 150000 steps
  ASSERT_FALSE(s.models.tangential);
  ASSERT_FALSE(s.models.gravity);
  const GasRun r = run_gas(s, 10, true, true);
  std::printf("[energy-a] collisions: %zu ball-ball + %zu ball-wall = %zu; max |dE|/E0 = %.3e "
              "(contact-free samples %.3e), final %.3e\n",
              r.pair_collisions, r.wall_collisions, r.pair_collisions + r.wall_collisions,
              r.max_rel_error_all, r.max_rel_error_free, r.final_rel_error);
  EXPECT_GE(r.pair_collisions + r.wall_collisions, 10000u);
  EXPECT_GE(r.pair_collisions, 2000u);  // both kinds of contact are exercised
  EXPECT_GE(r.wall_collisions, 2000u);
  EXPECT_LT(r.max_rel_error_all, 1e-3);
  EXPECT_LT(r.final_rel_error, 1e-3);
}

// (b) Reference: the energy error between collisions of a second-order integrator scales as dt^p,
// p >= 2 (expected p = 2.5 here, ratio 5.7), so halving dt divides it by >= 4. Trajectories of
// different dt diverge (the gas is chaotic), so only statistics over many impacts compare: 20 balls,
// 0.6 s, ~800 impacts per run, 3 seeds pooled, dt = 4e-5, 2e-5, 1e-5 s (22 to 90 steps per impact),
// E sampled at every step with no contact closed (contact_count() == 0). Statistics:
//   accumulated |E_k - E_(k-1)| between consecutive contact-free samples (the sum of the net errors
//   of the impacts in between; stable): ratio >= 4 for each halving, pooled and per seed;
//   max |E - E0| over contact-free samples (a random walk; noisy): pooled ratio >= 3 per halving.
TEST(Energy, EnergyErrorIsSecondOrderInDt) {
  constexpr int kLevels = 3;
  const double dts[kLevels] = {4e-5, 2e-5, 1e-5};
  double path[kLevels] = {0, 0, 0}, maxfree[kLevels] = {0, 0, 0};
  for (std::uint64_t seed : {21u, 22u, 23u}) {
    double seed_path[kLevels];
    for (int k = 0; k < kLevels; ++k) {
      const Scene s = elastic_gas(dts[k], seed, 0.6, 20);
      const GasRun r = run_gas(s, 1, false, false);
      ASSERT_GT(r.free_samples, 1000u) << "seed " << seed;
      seed_path[k] = r.path_free;
      path[k] += r.path_free;
      maxfree[k] += r.max_rel_error_free;
      std::printf("[energy-b] seed %llu dt %.0e: accumulated jumps %.3e, max contact-free error %.3e "
                  "(%zu contact-free samples)\n",
                  static_cast<unsigned long long>(seed), dts[k], r.path_free, r.max_rel_error_free,
                  r.free_samples);
    }
    for (int k = 0; k + 1 < kLevels; ++k)
      EXPECT_GE(seed_path[k] / seed_path[k + 1], 4.0) << "seed " << seed << ", dt " << dts[k];
  }
  for (int k = 0; k + 1 < kLevels; ++k) {
    const double ratio_path = path[k] / path[k + 1], ratio_max = maxfree[k] / maxfree[k + 1];
    std::printf("[energy-b] pooled ratio dt %.0e -> %.0e: accumulated jumps %.2f, max contact-free "
                "error %.2f\n", dts[k], dts[k + 1], ratio_path, ratio_max);
    EXPECT_GE(ratio_path, 4.0);
    EXPECT_GE(ratio_max, 3.0);
  }
  EXPECT_GT(path[kLevels - 1], 1e-6);  // the finest level is still far above round-off
}

namespace {

struct BudgetResult {
  EnergySample e;
  double initial = 0;
  double closure = 0;  // |W - dE - D| / D
  double dissipated = 0, work = 0;
  std::size_t min_contacts = 0, max_contacts = 0;
};

// 40 balls (r 3-4 mm, E = 1e7 Pa, e = 0.5, mu = 0.3) in a 4 x 4 x 8 cm box shaken vertically,
// X = 2 mm, f = 20 Hz (Gamma = X w^2 / g = 3.2), gravity -z, 0.5 s (10 cycles), dt = 1e-5 s (~100
// steps per impact). The residue is O(dt^2) (measured: 7.2e-4, 1.7e-4, 4.1e-5 of D at dt = 2e-5,
// 1e-5, 5e-6 s), so dt = 1e-5 s leaves a 6x margin under the tolerance.
// `law` (default Hertz-Mindlin) with e = 0.5, mu = 0.3 and mu_r set here.
BudgetResult run_budget(double mu_r, Interaction law = {}) {
  SceneBuilder b;
  law.restitution = 0.5, law.friction = 0.3, law.rolling_friction = mu_r;
  b.material("glass", 2500, 1e7, 0.3).interaction(law);
  const Vec3 lo(0, 0, 0), hi(0.04, 0.04, 0.08);
  b.box(lo, hi).gravity(Vec3(0, 0, -9.81)).dt(1e-5).duration(0.5);
  b.motion(make_harmonic_motion(0.002, 20.0, Vec3::UnitZ(), 0.0));
  Rng rng(7);
  random_gas(b, rng, 40, 0.003, 0.004, lo, hi, 0.3, 0.0005);
  const Scene s = b.build();
  Simulation sim(s);
  BudgetResult r;
  r.initial = sim.initial_stored_energy();
  r.min_contacts = 1u << 30;
  const std::uint64_t steps = s.total_steps();
  for (std::uint64_t k = 1; k <= steps; ++k) {
    sim.step();
    if (k > steps / 2 && k % 50 == 0) {
      const std::size_t c = sim.contact_count();
      r.min_contacts = std::min(r.min_contacts, c);
      r.max_contacts = std::max(r.max_contacts, c);
    }
  }
  r.e = sim.energy();
  r.dissipated = r.e.dissipated_normal + r.e.dissipated_tangential + r.e.dissipated_rolling;
  r.work = r.e.work_cavity + r.e.work_gravity;
  r.closure = std::abs(r.work - (stored(r.e) - r.initial) - r.dissipated) / r.dissipated;
  std::printf("[energy-c] mu_r=%.2f W_cav=%.6e W_grav=%.6e K=%.6e U=%.6e K0+U0=%.6e D_n=%.6e D_t=%.6e "
              "D_r=%.6e -> closure %.3e (contacts %zu..%zu)\n",
              mu_r, r.e.work_cavity, r.e.work_gravity, r.e.kinetic, r.e.elastic, r.initial,
              r.e.dissipated_normal, r.e.dissipated_tangential, r.e.dissipated_rolling, r.closure,
              r.min_contacts, r.max_contacts);
  return r;
}

}  // namespace

// (c) Reference: the energy balance W_cav + W_grav = (K + U) - (K0 + U0) + D_n + D_t (+ D_r), exact
// for the continuous model; the tallies use velocity Verlet's discrete work, so only a small
// O(dt^2) residue is expected. Tolerance: residue < 1e-3 of the total dissipation (measured
// 1.7e-4). The test also
// requires that the shaker injects energy (W_cav > 0), that each dissipation channel is positive and
// that dissipation is most of the input (D > 0.5 W): the scene really exercises the tallies.
TEST(Energy, BudgetClosesShakenFrictionalBox) {
  const BudgetResult r = run_budget(0.0);
  EXPECT_GT(r.e.work_cavity, 0.0);
  EXPECT_GT(r.e.dissipated_normal, 0.0);
  EXPECT_GT(r.e.dissipated_tangential, 0.0);
  EXPECT_EQ(r.e.dissipated_rolling, 0.0);
  EXPECT_GT(r.dissipated, 0.5 * r.work);
  EXPECT_GT(r.e.dissipated_tangential, 0.02 * r.dissipated);
  EXPECT_LT(r.closure, 1e-3);
}

// Same with EPSD rolling resistance (mu_r = 0.05): the rolling channel must be positive as well.
namespace {
// The budget of a run with rolling resistance closes and every channel dissipates.
void expect_rolling_budget_closes(const BudgetResult& r) {
  EXPECT_GT(r.e.work_cavity, 0.0);
  EXPECT_GT(r.e.dissipated_normal, 0.0);
  EXPECT_GT(r.e.dissipated_tangential, 0.0);
  EXPECT_GT(r.e.dissipated_rolling, 0.0);
  EXPECT_GT(r.dissipated, 0.5 * r.work);
  EXPECT_LT(r.closure, 1e-3);
}
}  // namespace

TEST(Energy, BudgetClosesWithRollingResistance) { expect_rolling_budget_closes(run_budget(0.05)); }

// The same with the linear spring-dashpot law (contact/hooke.hpp) and rolling resistance: its
// elastic energy k delta^2 / 2 (on pairs and walls) and its pulling damping force at the end of an
// impact are in the budget. k_n = 2.2 kN/m gives these balls about the Hertz contact's duration
// (1 ms, 100 steps).
TEST(Energy, BudgetClosesWithTheHookeLaw) {
  Interaction hooke;
  hooke.law = LawKind::Hooke;
  hooke.stiffness = 2.2e3;
  expect_rolling_budget_closes(run_budget(0.05, hooke));
}
