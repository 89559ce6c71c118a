// The single-ball impact damper (reduce/impact_damper_theory.hpp): the symmetric two-impact motion
// of Masri & Caughey (1966), checked against itself, against an exact rigid-impact model written here
// from scratch, and against the DEM.
//
//  * SingleBallTheory: the returned motion satisfies the impact and flight equations, its energy in
//    both forms, the study's Eq. (22), (19a) and the (19b) form of the effective mass (round-off
//    tolerances); its stability verdict and spectral radius agree with iterating the exact
//    event-driven rigid-impact map from a slightly perturbed start on both sides of the stability
//    boundary (rates within 0.03); the other root of the phase equation is a saddle; for small e
//    the left wall catches the ball below the admissibility limit.
//  * SingleBallDem: one 10-mm steel ball in a steel box shaken along x (X = 2 mm, 50 Hz, no
//    gravity; contact ~31 us, 1/650 of the period). The e the DEM returns is measured first by a
//    single wall impact at the theory's impact speed with the same time step, and the theory is
//    evaluated with it. Inside the stable range (d/X = 6, e = 0.6) the ball, started at the centre,
//    settles into two impacts per cycle at the theory's phases (0.02 rad) with its energy per cycle
//    (2%); below it (d/X = 2.4) it settles into an asymmetric motion that the exact rigid model,
//    started from the same state, predicts (0.05 rad), 0.37 rad or more away from the symmetric one.
//  The DEM's impact phases scatter by up to ~0.01 rad (stable case) and ~0.025 rad (asymmetric
//  motion) from impact to impact: its e depends on where inside a time step a contact begins
//  (+-0.3% at 48 steps per contact), and the impact map carries that on (the exact model with e
//  drawn uniformly in +-0.0018 per impact scatters by 0.007 and 0.013 rad at these two points).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bagdem/case/load_case.hpp"
#include "bagdem/reduce/impact_damper_theory.hpp"
#include "bagdem/run/runner.hpp"
#include "bagdem/step/simulation.hpp"
#include "h5_read.hpp"
#include "support.hpp"

using namespace bagdem;
using bagdem::testing::Doubles;
using bagdem::testing::open_read;
using bagdem::testing::read_doubles;
using bagdem::testing::TempDir;

namespace {

constexpr double kPi = std::numbers::pi;

// Phase difference wrapped into [-pi, pi).
double wrap(double a) { return a - 2 * kPi * std::floor((a + kPi) / (2 * kPi)); }

// ---------------------------------------------------------------------------------------------------
// The exact rigid-impact model: the ball flies at constant velocity; the next impact is the first
// time its centre reaches a wall of the cavity x(t) = X sin(w t) (walls at x -+ d/2), found by
// scanning steps of 1/4000 of a period for a sign change of the gap and bisecting it to round-off.
// A grazing contact shorter than a scan step would be missed; the motions tested cross walls
// transversally. Independent of the library's theory: no formula of the header is used.
struct Impact {
  int wall = 0;        // -1 left (x - d/2), +1 right (x + d/2)
  double time = 0;     // (unit: s)
  double velocity = 0; // ball velocity after the impact (unit: m/s)
};

class RigidImpactModel {
 public:
  RigidImpactModel(double X, double w, double d, double e) : X_(X), w_(w), d_(d), e_(e) {}
  void set_state(double t, double y, double v) { t_ = t, y_ = y, v_ = v; }
  // Advances to the next impact and applies it; wall = 0 if none within 50 periods.
  Impact next() {
    const double period = 2 * kPi / w_, h = period / 4000;
    for (double s = t_; s < t_ + 50 * period; s += h) {
      double when = 0;
      int wall = 0;
      for (int side : {-1, 1}) {
        if (gap(side, s + h) >= 0) continue;
        double lo = s, hi = s + h;  // gap(lo) >= 0 > gap(hi)
        for (int k = 0; k < 200 && hi - lo > 4 * std::numeric_limits<double>::epsilon() * hi; ++k) {
          const double mid = 0.5 * (lo + hi);
          (gap(side, mid) >= 0 ? lo : hi) = mid;
        }
        if (wall == 0 || hi < when) when = hi, wall = side;
      }
      if (wall == 0) continue;
      const double wall_velocity = X_ * w_ * std::cos(w_ * when);
      y_ = X_ * std::sin(w_ * when) + wall * d_ / 2;
      v_ = wall_velocity - e_ * (v_ - wall_velocity);  // relative velocity reversed, times e
      t_ = when;
      return {wall, t_, v_};
    }
    return {};
  }

 private:
  // >= 0 while the ball is clear of that wall.
  double gap(int side, double s) const {
    const double y = y_ + v_ * (s - t_), x = X_ * std::sin(w_ * s);
    return side < 0 ? y - (x - d_ / 2) : (x + d_ / 2) - y;
  }
  double X_, w_, d_, e_;
  double t_ = 0, y_ = 0, v_ = 0;
};

// Distance of an impact from the symmetric motion (alpha, u), folded onto the left wall:
// hypot(phase error, velocity error / (X w)).
double deviation(const Impact& i, double alpha, double u, double X, double w) {
  const double theta = wrap(w * i.time - alpha - (i.wall > 0 ? kPi : 0.0));
  const double dv = (i.wall < 0 ? i.velocity - u : -i.velocity - u) / (X * w);
  return std::hypot(theta, dv);
}

// Starts the exact model on the left wall at phase alpha + delta with speed u (1 + delta) and
// returns the growth factor per impact of the distance from the symmetric motion: the least-squares
// slope of log(distance) over the impacts where it lies in [1e-11, 1e-4] (linear regime, far above
// round-off), the first 2 impacts left out so the dominant eigenvalue takes over. NaN if fewer
// than 5 impacts fall in the window.
double perturbation_rate(double X, double w, double d, double e, double alpha, double u, double delta) {
  RigidImpactModel model(X, w, d, e);
  const double t0 = (alpha + delta) / w;
  model.set_state(t0, X * std::sin(w * t0) - d / 2, u * (1 + delta));
  std::vector<double> n, logs;
  for (int k = 1; k <= 600; ++k) {
    const Impact i = model.next();
    if (i.wall == 0) break;
    const double dist = deviation(i, alpha, u, X, w);
    if (k > 2 && dist >= 1e-11 && dist <= 1e-4) n.push_back(k), logs.push_back(std::log(dist));
    if (k > 2 && (dist < 1e-11 || dist > 1e-3)) break;
  }
  if (n.size() < 5) return std::nan("");
  double mn = 0, ml = 0;
  for (std::size_t k = 0; k < n.size(); ++k) mn += n[k], ml += logs[k];
  mn /= static_cast<double>(n.size()), ml /= static_cast<double>(n.size());
  double sxy = 0, sxx = 0;
  for (std::size_t k = 0; k < n.size(); ++k) sxy += (n[k] - mn) * (logs[k] - ml), sxx += (n[k] - mn) * (n[k] - mn);
  return std::exp(sxy / sxx);
}

// Drive of the theory tests (any would do: the motion scales with X and 1/w).
constexpr double kX = 2e-3, kW = 2 * kPi * 50, kMass = 4.084e-3;

}  // namespace

// (1), (2), both energy forms, E_cycle = pi C_eq w X^2, the study's (22) and (19a) with
// phi = study_phase, and M_eff in the (19b) form, all to round-off (1e-12 relative), over the
// existing range of d/X for three restitutions.
TEST(SingleBallTheory, PhaseAndEnergyEquationsHold) {
  for (double e : {0.2, 0.6, 0.9}) {
    const double r = (1 + e) / (1 - e);
    const ClearanceRatioRange range = stable_clearance_ratio(e);
    for (double D : {0.8 * range.lo, range.lo, 0.5 * (range.lo + range.hi), 0.99 * range.hi}) {
      const double d = D * kX;
      const TwoImpactMotion s = two_impact_motion(kMass, kX, kW, d, e);
      ASSERT_TRUE(s.exists) << "e " << e << " d/X " << D;
      const double a = s.phase, phi = s.study_phase, wall = kX * kW * std::cos(a), u = s.ball_speed;
      const double tol = 1e-12;
      EXPECT_NEAR((u - wall) / (-u - wall), -e, tol);                         // impact law, (1)
      EXPECT_NEAR((u * kPi / kW + 2 * kX * std::sin(a)) / d, 1.0, tol);        // half-period flight, (2)
      EXPECT_NEAR(s.impact_speed, u + wall, tol * u);
      EXPECT_NEAR(s.energy_per_impact / (0.5 * kMass * (1 - e * e) * s.impact_speed * s.impact_speed), 1.0, tol);
      EXPECT_NEAR(s.energy_per_impact / (2 * kMass * r * wall * wall), 1.0, tol);
      EXPECT_NEAR(s.energy_per_cycle, 2 * s.energy_per_impact, tol * s.energy_per_cycle);
      EXPECT_NEAR(s.equivalent_damping * kPi * kW * kX * kX / s.energy_per_cycle, 1.0, tol);
      EXPECT_GT(phi, 0.0);
      EXPECT_LT(phi, kPi);
      EXPECT_NEAR(std::abs(kPi * r * std::sin(phi) - 2 * std::cos(phi)), D, tol * D);                   // (22)
      EXPECT_NEAR(s.equivalent_damping / (kMass * kW), 4 / kPi * r * std::sin(phi) * std::sin(phi), tol);  // (19a)
      EXPECT_NEAR(s.effective_mass / kMass, 4 / kPi * r * std::sin(phi) * std::cos(phi), tol);          // (19b) form
      std::printf("  e %.2f d/X %6.3f: alpha %+.5f rad, phi %.5f rad, u %.5f m/s, v_rel %.5f m/s, E_cycle %.5e J, "
                  "C_eq/(m w) %.5f, M_eff/m %+.5f, |lambda| %.4f, %s\n",
                  e, D, a, phi, u, s.impact_speed, s.energy_per_cycle, s.equivalent_damping / (kMass * kW),
                  s.effective_mass / kMass, s.max_eigenvalue, s.stable ? "stable" : "unstable");
    }
    EXPECT_FALSE(two_impact_motion(kMass, kX, kW, 1.01 * range.hi * kX, e).exists);
  }
  EXPECT_THROW(two_impact_motion(kMass, kX, kW, 0.01, 1.0), std::invalid_argument);
  EXPECT_THROW(two_impact_motion(kMass, kX, kW, 0.01, 0.0), std::invalid_argument);
  EXPECT_THROW(two_impact_motion(kMass, kX, kW, -0.01, 0.5), std::invalid_argument);
  EXPECT_THROW(two_impact_motion(0.0, kX, kW, 0.01, 0.5), std::invalid_argument);
  EXPECT_THROW(stable_clearance_ratio(1.0), std::invalid_argument);
}

// The exact map started 1e-5 (stable) or 1e-10 (unstable) off the symmetric motion: the measured
// growth factor per impact is below 1 exactly when the theory says stable, and equals its spectral
// radius within 0.03. Points: below the stable range (0.8 lo), just inside it (1.1 lo), its middle,
// just below its top (0.98 hi); at lo and hi the spectral radius is 1 (1e-9).
TEST(SingleBallTheory, StabilityAgreesWithTheExactImpactMap) {
  for (double e : {0.3, 0.6, 0.85}) {
    const ClearanceRatioRange range = stable_clearance_ratio(e);
    EXPECT_NEAR(two_impact_motion(kMass, kX, kW, range.lo * kX, e).max_eigenvalue, 1.0, 1e-9);
    EXPECT_NEAR(two_impact_motion(kMass, kX, kW, range.hi * kX, e).max_eigenvalue, 1.0, 1e-9);
    std::printf("  e %.2f: stable for %.4f < d/X < %.4f\n", e, range.lo, range.hi);
    for (double D : {0.8 * range.lo, 1.1 * range.lo, 0.5 * (range.lo + range.hi), 0.98 * range.hi}) {
      const TwoImpactMotion s = two_impact_motion(kMass, kX, kW, D * kX, e);
      ASSERT_TRUE(s.exists);
      const double rate = perturbation_rate(kX, kW, D * kX, e, s.phase, s.ball_speed, s.stable ? 1e-5 : 1e-10);
      std::printf("    d/X %7.4f: theory %-8s |lambda| %.4f; exact map: perturbation x %.4f per impact\n", D,
                  s.stable ? "stable" : "unstable", s.max_eigenvalue, rate);
      ASSERT_FALSE(std::isnan(rate)) << "d/X " << D;
      EXPECT_EQ(rate < 1, s.stable) << "e " << e << " d/X " << D;
      EXPECT_NEAR(rate, s.max_eigenvalue, 0.03) << "e " << e << " d/X " << D;
    }
  }
}

// For d/X > 2 the phase equation (2) has a second root with cos(alpha) > 0, alpha = psi + acos(D/R).
// It is a periodic motion of the exact model too, but perturbations grow: it is the saddle the header
// discards. Reference: the exact map; the root and its speed are computed here from (1) and (2).
TEST(SingleBallTheory, SecondRootIsASaddle) {
  const double e = 0.6, r = (1 + e) / (1 - e), D = 5.0;
  const double R = std::hypot(kPi * r, 2.0), alpha2 = std::atan2(2.0, kPi * r) + std::acos(D / R);
  ASSERT_GT(std::cos(alpha2), 0.0);
  const double u2 = r * kX * kW * std::cos(alpha2);
  EXPECT_NEAR(kPi * r * std::cos(alpha2) + 2 * std::sin(alpha2), D, 1e-12);
  const double rate = perturbation_rate(kX, kW, D * kX, e, alpha2, u2, 1e-13);
  const TwoImpactMotion s = two_impact_motion(kMass, kX, kW, D * kX, e);
  std::printf("  e %.2f d/X %.2f: reported root alpha %+.5f (|lambda| %.4f), second root alpha %+.5f: "
              "perturbation x %.4f per impact\n",
              e, D, s.phase, s.max_eigenvalue, alpha2, rate);
  EXPECT_TRUE(s.stable);
  EXPECT_LT(s.phase, alpha2);
  // Its growth factor is the larger root of lambda^2 - T lambda + e^2 (header, section 4) at alpha2.
  const double T = 2 * e + 0.5 * kPi * (1 - e * e) * std::tan(alpha2);
  const double lambda = 0.5 * T + std::sqrt(0.25 * T * T - e * e);
  std::printf("  linearised map at the second root: lambda %.4f\n", lambda);
  EXPECT_GT(rate, 1.2);
  EXPECT_NEAR(rate / lambda, 1.0, 0.01);
}

// Small e: below the admissibility limit the left wall catches the ball again before it crosses
// (the exact model's next impact is on the same wall); above it the ball crosses at alpha + pi.
// e = 0.05 and 0.005 (for the latter the limit lies above the middle of [D_min, R]).
TEST(SingleBallTheory, SmallRestitutionAdmissibilityLimit) {
  for (double e : {0.05, 0.005}) {
    const double r = (1 + e) / (1 - e);
    const ClearanceRatioRange range = stable_clearance_ratio(e);
    const double linear_lo = r * (kPi * kPi - 4) / std::sqrt(kPi * kPi + 4 * r * r);
    std::printf("  e %.3f: linear stability from d/X = %.4f, admissible and stable from %.4f to %.4f\n", e,
                linear_lo, range.lo, range.hi);
    EXPECT_GT(range.lo, linear_lo * 1.05);
    EXPECT_LT(range.lo, range.hi);
    for (double D : {0.98 * range.lo, 1.02 * range.lo}) {
      const TwoImpactMotion s = two_impact_motion(kMass, kX, kW, D * kX, e);
      RigidImpactModel model(kX, kW, D * kX, e);
      const double t0 = s.phase / kW;
      model.set_state(t0, kX * std::sin(s.phase) - D * kX / 2, s.ball_speed);
      const Impact next = model.next();
      const double err = wrap(kW * next.time - s.phase - kPi);
      std::printf("    d/X %.4f: theory exists %d stable %d; exact model: next impact on the %s wall, phase "
                  "error %.2e rad\n",
                  D, s.exists, s.stable, next.wall < 0 ? "same (left)" : "other (right)", err);
      if (D < range.lo) {
        EXPECT_FALSE(s.exists);
        EXPECT_EQ(next.wall, -1);
      } else {
        EXPECT_TRUE(s.stable);
        EXPECT_EQ(next.wall, 1);
        EXPECT_LT(std::abs(err), 1e-9);
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------------
// DEM.
namespace {

constexpr double kBallRadius = 5e-3, kDensity = 7800;
constexpr double kDriveX = 2e-3, kDriveF = 50, kDriveW = 2 * kPi * kDriveF;
constexpr double kRequestedE = 0.6;
const double kBallMass = kDensity * 4.0 / 3.0 * kPi * std::pow(kBallRadius, 3);

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

// One steel ball in a steel box, free travel d along x, 2 mm of room across; no gravity.
// `motion` is the [cavity.motion] table's body; the ball starts at x0 on the axis with velocity v0.
std::string ball_case(double d, const std::string& motion, double x0, double v0, double duration,
                      double expected_speed, const std::string& output) {
  const double half_x = d / 2 + kBallRadius, half_yz = kBallRadius + 2e-3;
  std::ostringstream s;
  s << "[simulation]\nduration = " << num(duration) << "\ngravity = [0, 0, 0]\nexpected_speed = "
    << num(expected_speed) << "\n\n"
    << "[materials.steel]\ndensity = " << num(kDensity) << "\nyoungs_modulus = \"200 GPa\"\npoisson_ratio = 0.3\n\n"
    << "[interactions.default]\nrestitution = " << num(kRequestedE) << "\n\n"
    << "[cavity]\nkind = \"box\"\nmaterial = \"steel\"\nmin = [" << num(-half_x) << ", " << num(-half_yz) << ", "
    << num(-half_yz) << "]\nmax = [" << num(half_x) << ", " << num(half_yz) << ", " << num(half_yz) << "]\n\n"
    << "[cavity.motion]\n" << motion << "\n"
    << "[particles.ball]\nmaterial = \"steel\"\ndiameter = " << num(2 * kBallRadius) << "\npositions = [[" << num(x0)
    << ", 0, 0]]\nvelocities = [[" << num(v0) << ", 0, 0]]\n\n"
    << "[output]\n" << output;
  return s.str();
}

std::string harmonic_motion() {
  return "kind = \"harmonic\"\namplitude = " + num(kDriveX) + "\nfrequency = " + num(kDriveF) +
         "\ndirection = [1, 0, 0]\n";
}

// The restitution the DEM returns: the ball hits the left wall of the fixed box head-on at speed v
// with time step dt; e = speed after / speed before, once the contact has opened. The contact opens
// at an arbitrary point inside a step, and e depends on where (about +-0.3% at 48 steps per
// contact), so the impact is repeated with the start shifted by k/8 of the distance covered in a
// step, k = 0..7, and the mean is the DEM's e; the range is reported with it.
struct Restitution {
  double mean = 0, min = 1, max = 0;
};
Restitution measured_restitution(double d, double v, double dt) {
  constexpr int kOffsets = 8;
  TempDir dir;
  dir.write("case.toml", ball_case(d, "kind = \"fixed\"\n", -d / 2 + 1e-5, -v, 1e-3, v, ""));
  const Scene loaded = load_case(dir.str(), {"simulation.timestep=" + num(dt)});
  Restitution e;
  for (int k = 0; k < kOffsets; ++k) {
    Scene scene = loaded;
    scene.particles.at(0).x.x() += k * v * dt / kOffsets;
    Simulation sim(scene);
    bool touched = false, left = false;
    for (std::uint64_t n = 0; n < scene.total_steps() && !left; ++n) {
      sim.step();
      touched = touched || sim.contact_count() > 0;
      left = touched && sim.contact_count() == 0;
    }
    EXPECT_TRUE(left) << "the ball did not leave the wall";
    const double ek = sim.particles().v[0].x() / v;
    e.mean += ek / kOffsets;
    e.min = std::min(e.min, ek);
    e.max = std::max(e.max, ek);
  }
  return e;
}

struct DemImpact {
  int wall = 0;          // -1 left, +1 right (from the sign of the force on the cavity)
  double time = 0;       // impulse-weighted mean time of the contact (unit: s)
  double impulse = 0;    // |impulse| on the cavity (unit: N s)
};

struct ShakenRun {
  RunReport report;
  double dt = 0, sample = 0;      // step and cavity sample interval (unit: s)
  std::vector<DemImpact> impacts;
  double measured_from = 0;       // start of the measured cycles (unit: s)
  double cavity_work_per_cycle = 0, c_eff = 0, m_eff = 0;  // from /cavity over the measured cycles
};

// Runs the shaken box: `cycles` drive cycles, the first `skip` left out of the per-cycle figures,
// the ball starting at the centre at speed u0. Impacts are read from /cavity/force: a contact is a
// run of non-zero samples (interval 5 us, 1/6 of a contact), its time the impulse-weighted mean.
ShakenRun run_shaken_box(double d, double u0, int cycles, int skip, double expected_speed, double dt) {
  TempDir dir;
  const std::string output = "cavity_interval = 5e-6\nenergy_interval = 1e-3\nframe_interval = " +
                             num(cycles / kDriveF) + "\nskip_cycles = " + std::to_string(skip) + "\n";
  dir.write("case.toml", ball_case(d, harmonic_motion(), 0.0, u0, cycles / kDriveF, expected_speed, output));
  const Scene scene = load_case(dir.str(), {"simulation.timestep=" + num(dt)});
  RunOptions options;
  options.out_dir = (dir.path / "out").string();
  options.quiet = true;
  ShakenRun run;
  run.report = run_scene(scene, options);
  run.dt = scene.dt;
  run.measured_from = skip / kDriveF;
  EXPECT_TRUE(run.report.complete) << run.report.message;
  const hid_t f = open_read((dir.path / "out" / "results.h5").string());
  const Doubles times = read_doubles(f, "/cavity/time");
  const Doubles force = read_doubles(f, "/cavity/force");
  const Doubles velocity = read_doubles(f, "/cavity/velocity");
  H5Fclose(f);
  const std::size_t rows = times.values.size();
  EXPECT_GT(rows, 100u);
  if (rows < 100) return run;
  run.sample = times.values[1] - times.values[0];
  DemImpact open;
  double weighted_time = 0, signed_impulse = 0;
  double work = 0, cos_sum = 0, sin_sum = 0;
  for (std::size_t k = 0; k + 1 < rows; ++k) {  // the last sample may be a partial interval
    const double t = times.values[k], Fx = force.values[3 * k];
    EXPECT_EQ(force.values[3 * k + 1], 0.0);  // nothing touches the side walls
    EXPECT_EQ(force.values[3 * k + 2], 0.0);
    if (Fx != 0) {
      weighted_time += Fx * t;
      signed_impulse += Fx;
    } else if (signed_impulse != 0) {
      open.wall = signed_impulse < 0 ? -1 : 1;  // the left wall pushes the ball to +x, the ball it to -x
      open.time = weighted_time / signed_impulse;
      open.impulse = std::abs(signed_impulse) * run.sample;
      run.impacts.push_back(open);
      weighted_time = signed_impulse = 0;
    }
    if (t >= run.measured_from) {
      work -= Fx * velocity.values[3 * k] * run.sample;  // the cavity's work on the ball
      cos_sum += Fx * std::cos(kDriveW * t) * run.sample;
      sin_sum += Fx * std::sin(kDriveW * t) * run.sample;
    }
  }
  const double n = cycles - skip, span = n / kDriveF;
  run.cavity_work_per_cycle = work / n;
  run.c_eff = -2 / (span * kDriveW * kDriveX) * cos_sum;  // docs/reference-study.md, section 5
  run.m_eff = 2 / (span * kDriveW * kDriveW * kDriveX) * sin_sum;
  return run;
}

// Step and e for a clearance: the auto step of the shaken case (expected speed 1.25 x the theory's
// impact speed at the requested e), then e measured with that step at that impact speed.
struct Calibration {
  double dt = 0, expected_speed = 0, e = 0;
};
Calibration calibrate(double d) {
  const TwoImpactMotion nominal = two_impact_motion(kBallMass, kDriveX, kDriveW, d, kRequestedE);
  EXPECT_TRUE(nominal.exists);
  Calibration c;
  c.expected_speed = 1.25 * nominal.impact_speed;
  TempDir dir;
  dir.write("case.toml", ball_case(d, harmonic_motion(), 0.0, 0.0, 1 / kDriveF, c.expected_speed, ""));
  c.dt = load_case(dir.str()).dt;
  const Restitution e = measured_restitution(d, nominal.impact_speed, c.dt);
  c.e = e.mean;
  std::printf("  d = %.2f mm: step %.4g s (auto, expected speed %.3f m/s), Hertz contact %.1f steps; e requested "
              "%.3f, measured %.6f at v = %.4f m/s (%.6f to %.6f with the contact's onset within a step)\n",
              1e3 * d, c.dt, c.expected_speed,
              2.87 * std::pow(kBallMass * kBallMass / (kBallRadius * std::pow(200e9 / (2 * (1 - 0.09)), 2) *
                                                       nominal.impact_speed), 0.2) / c.dt,
              kRequestedE, c.e, nominal.impact_speed, e.min, e.max);
  return c;
}

}  // namespace

// Inside the stable range: d/X = 6 at e = 0.6 (stable for 2.73 < d/X < 12.7, |lambda| = e). The ball
// starts at the centre with the theory's speed, 16 cycles, the first 10 skipped (the exact model
// from this start is within 1e-4 rad of the periodic motion after 8). Expected from the theory with
// the measured e: two impacts per cycle, alternating walls; every impact phase within 0.02 rad of
// alpha (left) and alpha + pi (right); energy per cycle (the run's dissipation tally) within 2%;
// besides, printed and checked loosely (3%): the ball speed from each impulse (2 m u), the cavity's
// work per cycle, C_eff and M_eff from the Fourier projection of /cavity/force against C_eq, M_eff.
// Measured: energy +0.4%, C_eff +0.5%. Likely cause of that small excess: a compliant contact acts
// as a rigid one at the instant of the impulse's centroid, when the ball has run up to
// v_rel t_c/2 ~ 30 um into the wall, so the effective d/X is larger by up to 0.03 (+0.7% in
// E_cycle by the theory's slope).
TEST(SingleBallDem, ShakenBoxSettlesIntoTheTwoImpactMotion) {
  const double d = 6 * kDriveX;
  const Calibration cal = calibrate(d);
  const TwoImpactMotion theory = two_impact_motion(kBallMass, kDriveX, kDriveW, d, cal.e);
  ASSERT_TRUE(theory.stable);
  const int cycles = 16, skip = 10;
  const ShakenRun run = run_shaken_box(d, theory.ball_speed, cycles, skip, cal.expected_speed, cal.dt);
  ASSERT_TRUE(run.report.complete);
  int counted = 0, last_wall = 0;
  double worst_phase = 0, worst_speed = 0;
  bool alternate = true;
  for (const DemImpact& i : run.impacts) {
    if (i.time < run.measured_from) continue;
    ++counted;
    alternate = alternate && i.wall != last_wall;
    last_wall = i.wall;
    const double err = wrap(kDriveW * i.time - theory.phase - (i.wall > 0 ? kPi : 0.0));
    worst_phase = std::max(worst_phase, std::abs(err));
    worst_speed = std::max(worst_speed, std::abs(i.impulse / (2 * kBallMass) / theory.ball_speed - 1));
  }
  const double per_cycle = counted / double(cycles - skip);
  const double energy_err = run.report.dissipated_per_cycle / theory.energy_per_cycle - 1;
  std::printf("  theory (e %.4f): alpha %+.5f rad (phi %.5f), u %.5f m/s, v_rel %.5f m/s, E_cycle %.6e J, "
              "C_eq %.6e N s/m, M_eff %.6e kg, |lambda| %.3f\n",
              cal.e, theory.phase, theory.study_phase, theory.ball_speed, theory.impact_speed, theory.energy_per_cycle,
              theory.equivalent_damping, theory.effective_mass, theory.max_eigenvalue);
  std::printf("  DEM: %d impacts in %d cycles (%.2f per cycle, alternating %d), worst phase error %.2e rad, "
              "worst ball speed error %.2e\n",
              counted, cycles - skip, per_cycle, alternate, worst_phase, worst_speed);
  std::printf("  DEM: dissipated per cycle %.6e J (%+.3f%%), cavity work per cycle %.6e J (%+.3f%%), "
              "C_eff %.6e (%+.3f%%), M_eff %.6e (%+.3f%%); %.3f s wall clock\n",
              run.report.dissipated_per_cycle, 100 * energy_err, run.cavity_work_per_cycle,
              100 * (run.cavity_work_per_cycle / theory.energy_per_cycle - 1), run.c_eff,
              100 * (run.c_eff / theory.equivalent_damping - 1), run.m_eff,
              100 * (run.m_eff / theory.effective_mass - 1), run.report.wall_seconds);
  EXPECT_EQ(counted, 2 * (cycles - skip));
  EXPECT_TRUE(alternate);
  EXPECT_LT(worst_phase, 0.02);
  EXPECT_LT(std::abs(energy_err), 0.02);
  EXPECT_LT(worst_speed, 0.03);
  EXPECT_NEAR(run.cavity_work_per_cycle / theory.energy_per_cycle, 1.0, 0.03);
  EXPECT_NEAR(run.c_eff / theory.equivalent_damping, 1.0, 0.03);
  EXPECT_NEAR(run.m_eff / theory.effective_mass, 1.0, 0.03);
}

// Below the stable range: d/X = 2.4 at e = 0.6 (the symmetric motion exists, |lambda| = 1.30 > 1:
// an eigenvalue through -1). Same start as above, 20 cycles, the last 8 read. The exact rigid model
// from the same start (with the measured e) settles within 10 cycles into an asymmetric motion, still
// two impacts per cycle but at other phases and speeds; the DEM must follow it (phases within 0.05
// rad: its impact-to-impact scatter reaches 0.025 rad here, see the top of the file) and stay away
// from the symmetric phases (more than 0.2 rad on each wall).
TEST(SingleBallDem, BelowTheStableRangeTheMotionIsNotSymmetric) {
  const double d = 2.4 * kDriveX;
  const Calibration cal = calibrate(d);
  const TwoImpactMotion theory = two_impact_motion(kBallMass, kDriveX, kDriveW, d, cal.e);
  ASSERT_TRUE(theory.exists);
  ASSERT_FALSE(theory.stable);
  const int cycles = 20, skip = 12;
  const ShakenRun run = run_shaken_box(d, theory.ball_speed, cycles, skip, cal.expected_speed, cal.dt);
  ASSERT_TRUE(run.report.complete);
  // The exact model from the DEM's start: the last impact on each wall before the end.
  RigidImpactModel model(kDriveX, kDriveW, d, cal.e);
  model.set_state(0, 0, theory.ball_speed);
  double rigid_phase[2] = {0, 0}, rigid_speed[2] = {0, 0};
  for (Impact i = model.next(); i.wall != 0 && i.time < cycles / kDriveF; i = model.next())
    rigid_phase[i.wall > 0] = kDriveW * i.time, rigid_speed[i.wall > 0] = std::abs(i.velocity);
  int counted = 0;
  double worst_vs_rigid = 0, least_vs_symmetric = 1e9;
  for (const DemImpact& i : run.impacts) {
    if (i.time < run.measured_from) continue;
    ++counted;
    const int side = i.wall > 0;
    worst_vs_rigid = std::max(worst_vs_rigid, std::abs(wrap(kDriveW * i.time - rigid_phase[side])));
    least_vs_symmetric = std::min(least_vs_symmetric,
                                  std::abs(wrap(kDriveW * i.time - theory.phase - (side ? kPi : 0.0))));
  }
  std::printf("  theory (e %.4f): symmetric alpha %+.5f rad, |lambda| %.3f (unstable); exact model settles at "
              "left %+.5f rad (|v| %.4f m/s), right pi %+.5f rad (|v| %.4f m/s)\n",
              cal.e, theory.phase, theory.max_eigenvalue, wrap(rigid_phase[0]), rigid_speed[0],
              wrap(rigid_phase[1] - kPi), rigid_speed[1]);
  std::printf("  DEM: %d impacts in %d cycles; worst phase difference from the exact model %.2e rad, smallest "
              "from the symmetric motion %.3f rad; dissipated per cycle %.6e J (symmetric theory %.6e J)\n",
              counted, cycles - skip, worst_vs_rigid, least_vs_symmetric, run.report.dissipated_per_cycle,
              theory.energy_per_cycle);
  EXPECT_EQ(counted, 2 * (cycles - skip));
  EXPECT_LT(worst_vs_rigid, 0.05);
  EXPECT_GT(least_vs_symmetric, 0.2);
}
