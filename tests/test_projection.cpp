// First-harmonic projection, effective mass and damping, impacts and restitution
// (reduce/harmonic_projection.hpp, reduce/impacts.hpp), against synthetic signals whose interval
// means are computed analytically (the mean of a derivative over [t - Delta, t] is a difference of
// the function, divided by Delta), so the references are exact to round-off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "bagdem/reduce/harmonic_projection.hpp"
#include "bagdem/reduce/impacts.hpp"
#include "rng.hpp"

namespace {

using bagdem::Sampling;
using cplx = std::complex<double>;
constexpr double kPi = std::numbers::pi;

std::vector<double> uniform_times(double delta, std::size_t count, double t0 = 0) {
  std::vector<double> t(count);
  for (std::size_t k = 0; k < count; ++k) t[k] = t0 + static_cast<double>(k) * delta;
  return t;
}

// x(t) = X cos(w t + a) + X3 cos(3 w t + b) + B e^{-t/tau} cos(w2 t): the steady motion, an optional
// third harmonic and a decaying transient, with its derivative and its antiderivative.
struct Motion {
  double X = 2e-3, a = 0.7, w = 2 * kPi * 25;  // m, rad, rad/s
  double X3 = 0, b = 0.3;                      // m, rad
  double B = 1e-3, tau = 0.02, w2 = 2 * kPi * 37;  // m, s, rad/s
  cplx X_hat() const { return std::polar(X, a); }
  double x(double t) const {
    return X * std::cos(w * t + a) + X3 * std::cos(3 * w * t + b) + B * std::exp(-t / tau) * std::cos(w2 * t);
  }
  double v(double t) const {
    const double e = std::exp(-t / tau);
    return -X * w * std::sin(w * t + a) - 3 * w * X3 * std::sin(3 * w * t + b) +
           B * e * (-std::cos(w2 * t) / tau - w2 * std::sin(w2 * t));
  }
  double integral(double t) const {  // an antiderivative of x
    const double e = std::exp(-t / tau), d = 1 / (tau * tau) + w2 * w2;
    return X * std::sin(w * t + a) / w + X3 * std::sin(3 * w * t + b) / (3 * w) +
           B * e * (-std::cos(w2 * t) / tau + w2 * std::sin(w2 * t)) / d;
  }
};

struct Record {
  std::vector<double> t, x, x_mean, F;  // x point samples, x interval means, F interval means
};

// F = -M x'' - C x' + F0, interval means: -(M/Delta)[x'(t) - x'(t - Delta)] - (C/Delta)[x(t) - x(t - Delta)] + F0.
Record make_record(const Motion& m, double M, double C, double F0, double delta, std::size_t count) {
  Record r;
  r.t = uniform_times(delta, count, delta);
  for (double t : r.t) {
    r.x.push_back(m.x(t));
    r.x_mean.push_back((m.integral(t) - m.integral(t - delta)) / delta);
    r.F.push_back(-M * (m.v(t) - m.v(t - delta)) / delta - C * (m.x(t) - m.x(t - delta)) / delta + F0);
  }
  return r;
}

double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }
double rel(cplx a, cplx b) { return std::abs(a - b) / std::abs(b); }

constexpr double kM = 0.35, kC = 4.2, kF0 = 1.5;  // kg, N s/m, N

// 200 samples per period at 25 Hz, the transient (tau = 20 ms) skipped after 0.5 s (e^{-25} B < 1e-13 m).
TEST(Projection, CleanSignalsGiveMassAndDampingExactly) {
  const Motion m;
  const double f = 25, delta = 1 / (f * 200), t_skip = 0.5;
  const Record r = make_record(m, kM, kC, kF0, delta, 200 * 33);
  const auto xp = bagdem::first_harmonic(r.t, r.x, f, t_skip, Sampling::point);
  const auto xm = bagdem::first_harmonic(r.t, r.x_mean, f, t_skip, Sampling::interval_mean);
  const auto F = bagdem::first_harmonic(r.t, r.F, f, t_skip, Sampling::interval_mean);
  const auto p = bagdem::effective_parameters(r.t, r.x, r.F, f, t_skip);
  const double w = m.w, E = kPi * kC * w * m.X * m.X;
  std::printf("  cycles %zu over [%.4f, %.4f] s; X point fit err %.2e, X interval-mean fit err %.2e\n", p.cycles,
              xp.t_begin, xp.t_end, rel(xp.amplitude, m.X_hat()), rel(xm.amplitude, m.X_hat()));
  std::printf("  M_eff %.12f kg (exact %.2f, rel err %.1e), C_eff %.12f N s/m (exact %.2f, rel err %.1e)\n", p.mass,
              kM, rel(p.mass, kM), p.damping, kC, rel(p.damping, kC));
  std::printf("  E/cycle %.9e J (exact %.9e), loss factor %.9f (exact %.9f), F offset %.12f N\n",
              p.energy_per_cycle, E, p.loss_factor, kC / (kM * w), F.offset);
  EXPECT_EQ(p.cycles, 20u);  // 33 periods recorded, 12.5 skipped
  EXPECT_EQ(xp.per_cycle.size(), 20u);
  EXPECT_NEAR(xp.t_end - xp.t_begin, 20 / f, 1e-12);
  EXPECT_LT(rel(xp.amplitude, m.X_hat()), 1e-9);
  EXPECT_LT(rel(xm.amplitude, m.X_hat()), 1e-9);
  EXPECT_LT(rel(p.displacement, m.X_hat()), 1e-9);
  EXPECT_LT(rel(p.force, (w * w * kM - cplx(0, w * kC)) * m.X_hat()), 1e-9);
  EXPECT_LT(rel(p.mass, kM), 1e-9);
  EXPECT_LT(rel(p.damping, kC), 1e-9);
  EXPECT_LT(rel(p.energy_per_cycle, E), 1e-9);
  EXPECT_LT(rel(p.loss_factor, kC / (kM * w)), 1e-9);
  EXPECT_NEAR(F.offset, kF0, 1e-9 * kF0);
  EXPECT_NEAR(xp.offset, 0, 1e-9 * m.X);
  // Clean signals: every cycle is the same, so the standard errors vanish to round-off.
  EXPECT_LT(p.mass_se, 1e-9 * kM);
  EXPECT_LT(p.damping_se, 1e-9 * kC);
}

// The design check: fitting the interval-mean force with the point basis multiplies F_hat by
// sinc(w Delta/2) e^{-i w Delta/2}; the half-interval phase lag turns inertia into spurious damping.
TEST(Projection, PointBasisOnIntervalMeansWouldGiveTheSincError) {
  const Motion m;
  const double f = 25, delta = 1 / (f * 200), t_skip = 0.5, w = m.w;
  const Record r = make_record(m, kM, kC, kF0, delta, 200 * 33);
  const auto right = bagdem::first_harmonic(r.t, r.F, f, t_skip, Sampling::interval_mean);
  const auto wrong = bagdem::first_harmonic(r.t, r.F, f, t_skip, Sampling::point);
  const auto X = bagdem::first_harmonic(r.t, r.x, f, t_skip, Sampling::point);
  const double half = w * delta / 2;
  const cplx predicted = std::sin(half) / half * std::polar(1.0, -half);
  const cplx H = wrong.amplitude / X.amplitude;
  const double M_wrong = H.real() / (w * w), C_wrong = -H.imag() / w;
  std::printf("  point basis on interval means: F ratio %.9f at %.6f rad (predicted %.9f at %.6f rad)\n",
              std::abs(wrong.amplitude / right.amplitude), std::arg(wrong.amplitude / right.amplitude),
              std::abs(predicted), std::arg(predicted));
  std::printf("  would give M_eff %.6f kg (err %.2e), C_eff %.4f N s/m (err %+.1f%%; w M Delta w/2 = %.4f)\n", M_wrong,
              rel(M_wrong, kM), C_wrong, 100 * (C_wrong - kC) / kC, w * kM * half);
  EXPECT_LT(rel(wrong.amplitude / right.amplitude, predicted), 1e-9);
  EXPECT_GT(std::abs(C_wrong - kC) / kC, 0.1);  // 200 samples per period are not enough to ignore it
}

TEST(Projection, ThirdHarmonicDoesNotLeakIntoTheFirst) {
  Motion m;
  m.X3 = 0.4 * m.X;  // a strongly distorted motion (and force: 9 w^2 M X3 on the third harmonic)
  const double f = 25, delta = 1 / (f * 200), t_skip = 0.5;
  const Record r = make_record(m, kM, kC, kF0, delta, 200 * 33);
  const auto X = bagdem::first_harmonic(r.t, r.x, f, t_skip, Sampling::point);
  const auto p = bagdem::effective_parameters(r.t, r.x, r.F, f, t_skip);
  std::printf("  with a third harmonic of 40%%: X err %.1e, M_eff err %.1e, C_eff err %.1e\n",
              rel(X.amplitude, m.X_hat()), rel(p.mass, kM), rel(p.damping, kC));
  EXPECT_LT(rel(X.amplitude, m.X_hat()), 1e-9);
  EXPECT_LT(rel(p.mass, kM), 1e-9);
  EXPECT_LT(rel(p.damping, kC), 1e-9);
}

// P = 1/(f Delta) not whole: cycles of floor(P) or ceil(P) samples; a clean first harmonic stays
// exact (least squares over the samples' true times), a third harmonic leaks in by O(1/P).
TEST(Projection, NonWholeSamplesPerPeriod) {
  const double f = 25, P = 173.37, delta = 1 / (f * P), t_skip = 0.5;
  Motion m;
  const Record clean = make_record(m, kM, kC, kF0, delta, static_cast<std::size_t>(P * 33));
  const auto fit = bagdem::first_harmonic(clean.t, clean.x, f, t_skip, Sampling::point);
  const auto p = bagdem::effective_parameters(clean.t, clean.x, clean.F, f, t_skip);
  m.X3 = 0.4 * m.X;
  const Record distorted = make_record(m, kM, kC, kF0, delta, static_cast<std::size_t>(P * 33));
  const auto q = bagdem::effective_parameters(distorted.t, distorted.x, distorted.F, f, t_skip);
  std::printf("  %.2f samples per period, %zu cycles over %.6f s (%.6f expected): X err %.1e, M err %.1e, C err %.1e\n",
              P, p.cycles, fit.t_end - fit.t_begin, 20 / f, rel(fit.amplitude, m.X_hat()), rel(p.mass, kM),
              rel(p.damping, kC));
  std::printf("  with a 40%% third harmonic: M err %.1e, C err %.1e (leakage through the uneven window)\n",
              rel(q.mass, kM), rel(q.damping, kC));
  EXPECT_EQ(p.cycles, 20u);
  EXPECT_LT(rel(fit.amplitude, m.X_hat()), 1e-9);
  EXPECT_LT(rel(p.mass, kM), 1e-9);
  EXPECT_LT(rel(p.damping, kC), 1e-9);
  EXPECT_LT(rel(q.mass, kM), 1e-2);
  EXPECT_LT(rel(q.damping, kC), 5e-2);
}

// Gaussian noise of 3% of |F_hat| on each force sample, 200 cycles: the estimates lie within 3
// standard errors, and the standard error matches the spread over 50 independent realisations.
TEST(Projection, NoisyForceStandardErrors) {
  Motion m;
  m.B = 0;
  const double f = 25, N = 200, delta = 1 / (f * N), w = m.w;
  const Record r = make_record(m, kM, kC, kF0, delta, 200 * 200);
  const double sigma = 0.03 * std::abs((w * w * kM - cplx(0, w * kC)) * m.X_hat());
  bagdem::testing::Rng rng(20240611);
  constexpr int kRealisations = 50;
  std::vector<double> M(kRealisations), C(kRealisations);
  double mean_M_se = 0, mean_C_se = 0;
  bagdem::EffectiveParameters first;
  for (int i = 0; i < kRealisations; ++i) {
    std::vector<double> F = r.F;
    for (double& y : F) y += sigma * rng.normal();
    const auto p = bagdem::effective_parameters(r.t, r.x, F, f, 0);
    if (i == 0) first = p;
    M[i] = p.mass, C[i] = p.damping;
    mean_M_se += p.mass_se / kRealisations, mean_C_se += p.damping_se / kRealisations;
  }
  auto sd = [](const std::vector<double>& v) {
    double mean = 0, ss = 0;
    for (double x : v) mean += x / static_cast<double>(v.size());
    for (double x : v) ss += (x - mean) * (x - mean);
    return std::sqrt(ss / static_cast<double>(v.size() - 1));
  };
  // Least squares over N samples of a whole cycle: var of each part of F_j = 2 sigma^2 / (g^2 N), with
  // g = sinc(w Delta / 2) the interval-mean basis' gain; |X| divides it out.
  const double half = w * delta / 2, g = std::sin(half) / half;
  const double sd_H = std::sqrt(2 / N) * sigma / (g * m.X) / std::sqrt(200.0);
  std::printf("  %zu cycles, noise %.3f N: M_eff %.5f +- %.5f kg (%.1f SE off), C_eff %.4f +- %.4f N s/m (%.1f SE off)\n",
              first.cycles, sigma, first.mass, first.mass_se, (first.mass - kM) / first.mass_se, first.damping,
              first.damping_se, (first.damping - kC) / first.damping_se);
  std::printf("  SE of M: mean reported %.3e, spread of %d realisations %.3e, theory %.3e\n", mean_M_se, kRealisations,
              sd(M), sd_H / (w * w));
  std::printf("  SE of C: mean reported %.3e, spread of %d realisations %.3e, theory %.3e\n", mean_C_se, kRealisations,
              sd(C), sd_H / w);
  EXPECT_EQ(first.cycles, 200u);
  EXPECT_LT(std::abs(first.mass - kM), 3 * first.mass_se);
  EXPECT_LT(std::abs(first.damping - kC), 3 * first.damping_se);
  EXPECT_NEAR(mean_M_se / sd(M), 1, 0.3);
  EXPECT_NEAR(mean_C_se / sd(C), 1, 0.3);
  EXPECT_NEAR(mean_M_se / (sd_H / (w * w)), 1, 0.1);
  EXPECT_NEAR(mean_C_se / (sd_H / w), 1, 0.1);
}

TEST(Projection, BadInputThrows) {
  const double f = 25, delta = 1 / (f * 200);
  const Motion m;
  const Record r = make_record(m, kM, kC, kF0, delta, 200 * 3);
  // One whole cycle is the least; its standard error is unknown (NaN).
  const auto one = bagdem::first_harmonic(r.t, r.x, f, r.t[399], Sampling::point);
  EXPECT_EQ(one.per_cycle.size(), 1u);
  EXPECT_TRUE(std::isnan(one.standard_error.real()));
  EXPECT_THROW(bagdem::first_harmonic(r.t, r.x, f, r.t[401], Sampling::point), std::invalid_argument);
  EXPECT_THROW(bagdem::first_harmonic(r.t, r.x, f / 4, 0, Sampling::point), std::invalid_argument);
  EXPECT_THROW(bagdem::effective_parameters(r.t, r.x, r.F, f, r.t[450]), std::invalid_argument);
  // Non-uniform times: one sample moved by 1% of an interval.
  std::vector<double> t = r.t;
  t[300] += 0.01 * delta;
  EXPECT_THROW(bagdem::first_harmonic(t, r.x, f, 0, Sampling::point), std::invalid_argument);
  EXPECT_THROW(bagdem::effective_parameters(t, r.x, r.F, f, 0), std::invalid_argument);
  EXPECT_THROW(bagdem::find_impacts(t, r.F, 0), std::invalid_argument);
  EXPECT_THROW(bagdem::sample_interval({0.0, 1.0, 1.0}), std::invalid_argument);
  EXPECT_THROW(bagdem::sample_interval({1.0}), std::invalid_argument);
  // Sizes that differ, a bad frequency, under 3 samples per period, bad impact parameters.
  std::vector<double> short_x(r.x.begin(), r.x.end() - 1);
  EXPECT_THROW(bagdem::first_harmonic(r.t, short_x, f, 0, Sampling::point), std::invalid_argument);
  EXPECT_THROW(bagdem::effective_parameters(r.t, r.x, short_x, f, 0), std::invalid_argument);
  EXPECT_THROW(bagdem::first_harmonic(r.t, r.x, 0, 0, Sampling::point), std::invalid_argument);
  EXPECT_THROW(bagdem::first_harmonic(r.t, r.x, 1 / (2.5 * delta), 0, Sampling::point), std::invalid_argument);
  EXPECT_THROW(bagdem::find_impacts(r.t, r.F, 0, 0.0), std::invalid_argument);
  EXPECT_THROW(bagdem::find_impacts(r.t, r.F, 0, 1.0), std::invalid_argument);
  EXPECT_THROW(bagdem::find_impacts(r.t, r.F, 0, 0.05, -1e-3), std::invalid_argument);
  EXPECT_THROW(bagdem::impact_restitution({}, r.t, short_x), std::invalid_argument);
  // A still cavity has no effective parameters.
  const std::vector<double> still(r.t.size(), 0.0);
  EXPECT_THROW(bagdem::effective_parameters(r.t, still, r.F, f, 0), std::invalid_argument);
}

// theta with x = |X| cos(theta); for x = X sin(w t) (X_hat = -i X) the cavity speed is w X sin(theta).
TEST(Projection, MotionPhase) {
  const double w = 2 * kPi * 25, X = 3e-3;
  double worst = 0;
  for (const cplx X_hat : {std::polar(X, 0.7), std::polar(X, -2.9), cplx(0, -X), cplx(-X, 0)}) {
    for (int k = 0; k < 200; ++k) {
      const double t = 1.234 + 0.00173 * k;
      const double theta = bagdem::motion_phase(X_hat, w, t);
      ASSERT_GE(theta, 0);
      ASSERT_LT(theta, 2 * kPi);
      const double x = (X_hat * std::polar(1.0, w * t)).real(), v = (cplx(0, w) * X_hat * std::polar(1.0, w * t)).real();
      worst = std::max({worst, std::abs(X * std::cos(theta) - x) / X, std::abs(-w * X * std::sin(theta) - v) / (w * X)});
    }
  }
  std::printf("  x = |X| cos(theta), x' = -w |X| sin(theta): worst error %.1e of |X|\n", worst);
  EXPECT_LT(worst, 1e-12);
  EXPECT_NEAR(bagdem::motion_phase(cplx(0, -X), w, 0), 1.5 * kPi, 1e-15);  // X sin(wt) at t = 0
  // -1e-17 wraps to 2 pi - 1e-17, which rounds to 2 pi: returned as 0.
  EXPECT_EQ(bagdem::motion_phase(std::polar(X, -1e-17), w, 0), 0.0);
}

// Half-sine pulses s P sin(pi (t - t_s)/tau) on [t_s, t_s + tau], recorded as exact interval means.
struct Pulse {
  double centre, tau, peak;  // s, s, N
  int side;
  double start() const { return centre - tau / 2; }
  double end() const { return centre + tau / 2; }
  double impulse() const { return side * 2 * peak * tau / kPi; }
  double integral(double lo, double hi) const {  // integral of the pulse over [lo, hi]
    lo = std::max(lo, start()), hi = std::min(hi, end());
    if (!(hi > lo)) return 0;
    return side * peak * tau / kPi * (std::cos(kPi * (lo - start()) / tau) - std::cos(kPi * (hi - start()) / tau));
  }
};

std::vector<double> interval_means(const std::vector<double>& t, double delta, const std::vector<Pulse>& pulses) {
  std::vector<double> F(t.size(), 0.0);
  for (std::size_t k = 0; k < t.size(); ++k)
    for (const Pulse& p : pulses) F[k] += p.integral(t[k] - delta, t[k]) / delta;
  return F;
}

constexpr double kDelta = 1e-4;  // s
// Alternating sides; centres on an interval boundary (k Delta) or a midpoint ((k + 1/2) Delta).
const std::vector<Pulse> kTrain = {{0.0200, 2.0e-3, 50, +1}, {0.04005, 3.1e-3, 80, -1}, {0.0600, 0.73e-3, 120, +1},
                                   {0.08005, 5.0e-3, 35, -1}, {0.1000, 1.5e-3, 60, +1}, {0.12005, 2.2e-3, 90, -1}};

TEST(Projection, ImpactTrain) {
  const auto t = uniform_times(kDelta, 1500);
  const auto F = interval_means(t, kDelta, kTrain);
  const double q = 0.05;
  const auto impacts = bagdem::find_impacts(t, F, 0, q);
  ASSERT_EQ(impacts.size(), kTrain.size());
  double largest = 0;
  for (double y : F) largest = std::max(largest, std::abs(y));
  const double threshold = q * largest;
  double worst_impulse = 0, worst_centroid = 0, worst_duration = 0, worst_end = 0, worst_peak = 0;
  for (std::size_t i = 0; i < impacts.size(); ++i) {
    const auto& m = impacts[i];
    const Pulse& p = kTrain[i];
    // Above the threshold from s1 to s2; the peak interval mean is P sinc(x) centred on a boundary,
    // P sinc(x/2) on a midpoint, x = pi Delta / tau.
    const double clip = p.tau / kPi * std::asin(threshold / p.peak), s1 = p.start() + clip, s2 = p.end() - clip;
    const double x = kPi * kDelta / p.tau;
    const bool on_boundary = std::abs(std::remainder(p.centre, kDelta)) < 1e-3 * kDelta;
    const double peak = on_boundary ? p.peak * std::sin(x) / x : p.peak * std::sin(x / 2) / (x / 2);
    std::printf("  impact %zu side %+d: impulse %.9e N s (exact %.9e), centroid %.9f s (%.5f), duration %.5f ms "
                "(above threshold %.5f ms, feet %.1f ms, pulse %.2f ms), peak %.4f N (pulse %.0f)\n",
                i, m.side, m.impulse, p.impulse(), m.t_centroid, p.centre, 1e3 * m.duration(), 1e3 * (s2 - s1),
                1e3 * (m.t_foot_end - m.t_foot_start), 1e3 * p.tau, m.peak_force, p.peak);
    EXPECT_EQ(m.side, p.side);
    EXPECT_NEAR(m.impulse, p.impulse(), 1e-9 * std::abs(p.impulse()));
    EXPECT_NEAR(m.t_centroid, p.centre, 1e-9);
    EXPECT_NEAR(m.duration(), s2 - s1, kDelta);
    EXPECT_NEAR(m.t_start, s1, kDelta);
    EXPECT_NEAR(m.t_end, s2, kDelta);
    EXPECT_NEAR(m.peak_force, peak, 1e-9 * peak);
    // The feet: the intervals holding the pulse's first and last force.
    EXPECT_TRUE(m.t_foot_start <= p.start() && p.start() < m.t_foot_start + kDelta);
    EXPECT_TRUE(m.t_foot_end - kDelta < p.end() && p.end() <= m.t_foot_end);
    worst_impulse = std::max(worst_impulse, std::abs(m.impulse - p.impulse()) / std::abs(p.impulse()));
    worst_centroid = std::max(worst_centroid, std::abs(m.t_centroid - p.centre));
    worst_duration = std::max(worst_duration, std::abs(m.duration() - (s2 - s1)) / kDelta);
    worst_end = std::max({worst_end, std::abs(m.t_start - s1) / kDelta, std::abs(m.t_end - s2) / kDelta});
    worst_peak = std::max(worst_peak, std::abs(m.peak_force - peak) / peak);
  }
  std::printf("  worst: impulse %.1e rel, centroid %.1e s, duration %.2f intervals (ends %.2f), peak %.1e rel\n",
              worst_impulse, worst_centroid, worst_duration, worst_end, worst_peak);
  EXPECT_LT(worst_end, 0.5 + 1e-9);  // the force is near linear at these crossings
  // A pulse off the grid's symmetry: the centroid is no longer exact, but well inside an interval.
  const std::vector<Pulse> off = {{0.0500 + 0.37 * kDelta, 1.3e-3, 70, +1}};
  const auto m = bagdem::find_impacts(t, interval_means(t, kDelta, off), 0);
  ASSERT_EQ(m.size(), 1u);
  std::printf("  off-grid pulse: centroid off by %.1e intervals, impulse rel err %.1e\n",
              (m[0].t_centroid - off[0].centre) / kDelta, std::abs(m[0].impulse - off[0].impulse()) / off[0].impulse());
  EXPECT_LT(std::abs(m[0].t_centroid - off[0].centre), 0.01 * kDelta);
  EXPECT_NEAR(m[0].impulse, off[0].impulse(), 1e-9 * off[0].impulse());
}

TEST(Projection, ImpactMergeGapAndCutImpacts) {
  const auto t = uniform_times(kDelta, 800);
  // Two +x halves 0.3 ms apart (one impact split by a dip), then a -x pulse 0.2 ms later.
  const std::vector<Pulse> pulses = {{0.0305, 1e-3, 40, +1}, {0.0318, 1e-3, 40, +1}, {0.0330, 1e-3, 40, -1}};
  const auto F = interval_means(t, kDelta, pulses);
  const auto apart = bagdem::find_impacts(t, F, 0);
  const auto merged = bagdem::find_impacts(t, F, 0, 0.05, 1e-3);
  std::printf("  merge_gap 0: %zu impacts; merge_gap 1 ms: %zu impacts, first %.4f..%.4f ms, impulse %.9e N s (%.9e)\n",
              apart.size(), merged.size(), 1e3 * merged.at(0).t_start, 1e3 * merged.at(0).t_end, merged.at(0).impulse,
              pulses[0].impulse() + pulses[1].impulse());
  ASSERT_EQ(apart.size(), 3u);
  ASSERT_EQ(merged.size(), 2u);  // the -x pulse is not merged: other side
  EXPECT_EQ(merged[0].side, 1);
  EXPECT_EQ(merged[1].side, -1);
  EXPECT_DOUBLE_EQ(merged[0].t_start, apart[0].t_start);
  EXPECT_DOUBLE_EQ(merged[0].t_end, apart[1].t_end);
  EXPECT_NEAR(merged[0].impulse, pulses[0].impulse() + pulses[1].impulse(), 1e-9 * merged[0].impulse);
  EXPECT_NEAR(merged[0].t_centroid, 0.5 * (pulses[0].centre + pulses[1].centre), 1e-9);
  EXPECT_DOUBLE_EQ(merged[0].peak_force, std::max(apart[0].peak_force, apart[1].peak_force));
  // The gap measured between the halves: 0.3 ms plus the two clipped ends below the threshold, to an
  // interval; a merge_gap equal to it does not merge (strictly fewer), a little more does.
  const double gap = apart[1].t_start - apart[0].t_end;
  const double clip = pulses[0].tau / kPi * std::asin(0.05);  // both pulses peak at the largest |F|
  std::printf("  gap between the halves %.4f ms (0.3 ms + clipped ends %.4f ms)\n", 1e3 * gap, 2e3 * clip);
  EXPECT_NEAR(gap, 0.3e-3 + 2 * clip, kDelta);
  EXPECT_EQ(bagdem::find_impacts(t, F, 0, 0.05, gap).size(), 3u);
  EXPECT_EQ(bagdem::find_impacts(t, F, 0, 0.05, gap + kDelta / 2).size(), 2u);

  // Impacts cut by t_skip or by the end of the record are left out; F is zero elsewhere.
  const std::vector<Pulse> cut = {{0.0200, 2e-3, 50, +1}, {0.0500, 2e-3, 50, -1}, {0.0795, 2e-3, 50, +1}};
  const auto Fc = interval_means(t, kDelta, cut);
  const auto kept = bagdem::find_impacts(t, Fc, 0.0200);
  std::printf("  pulses cut by t_skip and by the record's end left out: %zu of 3 kept\n", kept.size());
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_NEAR(kept[0].impulse, cut[1].impulse(), 1e-9 * std::abs(cut[1].impulse()));
  EXPECT_TRUE(bagdem::find_impacts(t, std::vector<double>(t.size(), 0.0), 0).empty());
}

// Contents of mass m moving in +x hit the +x wall (F on the cavity > 0, side +1) and bounce back. The
// relative velocity follows the force, v = v_before - (1/m) integral F dt (the contents feel -F), with
// each pulse's impulse J = side m (1 + e) |v_before|, so v leaves the pulse at -e v_before; between
// impacts it changes by a known jump halfway (drift the force record does not show).
TEST(Projection, ImpactRestitution) {
  const auto t = uniform_times(kDelta, 1500);
  const auto impacts = bagdem::find_impacts(t, interval_means(t, kDelta, kTrain), 0);
  ASSERT_EQ(impacts.size(), kTrain.size());
  const double mass = 0.1;  // kg
  // e of each impact; impact 3 (side -1) has the contents moving in +x, away from the -x wall that
  // pushes them: skipped.
  const std::vector<double> e_set = {0.6, 0.45, 0.8, 0.5, 0.7, 0.3};
  const std::vector<double> expected = {0.6, 0.45, 0.8, 0.7, 0.3};
  std::vector<double> v_before(kTrain.size());
  for (std::size_t i = 0; i < kTrain.size(); ++i) {
    const double u = std::abs(kTrain[i].impulse()) / (mass * (1 + e_set[i]));
    v_before[i] = (i == 3 ? -1 : 1) * kTrain[i].side * u;
  }
  std::vector<double> v(t.size());
  for (std::size_t k = 0; k < t.size(); ++k) {
    std::size_t i = 0;  // the pulse whose neighbourhood (halfway to the next ones) holds t_k
    while (i + 1 < kTrain.size() && t[k] >= 0.5 * (kTrain[i].centre + kTrain[i + 1].centre)) ++i;
    v[k] = v_before[i] - kTrain[i].integral(t[k] - 1, t[k]) / mass;
  }
  const auto e = bagdem::impact_restitution(impacts, t, v);
  std::printf("  e:");
  for (double x : e.values) std::printf(" %.12f", x);
  std::printf("\n  mean %.12f (0.57), sd %.12f (%.12f), SE %.12f; %zu of %zu impacts counted\n", e.mean, e.sd,
              std::sqrt(0.0395), e.standard_error, e.values.size(), impacts.size());
  // Sampled at the threshold times instead of the feet, the tails' share of the impulse is missed.
  auto at = [&](double time) { return v[static_cast<std::size_t>(std::llround(time / kDelta))]; };
  std::printf("  from the threshold times t_start, t_end instead of the feet:");
  for (std::size_t i : {0, 1, 2, 4, 5}) std::printf(" %.4f", -at(impacts[i].t_end) / at(impacts[i].t_start));
  std::printf("\n");
  ASSERT_EQ(e.values.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(e.values[i], expected[i], 1e-12);
  EXPECT_NEAR(e.mean, 0.57, 1e-12);
  EXPECT_NEAR(e.sd, std::sqrt(0.0395), 1e-12);
  EXPECT_NEAR(e.standard_error, std::sqrt(0.0395 / 5), 1e-12);
  EXPECT_EQ(e.body(), e.mean);
  // No impacts: nothing to average; one: no spread.
  const auto none = bagdem::impact_restitution({}, t, v);
  EXPECT_TRUE(none.values.empty());
  EXPECT_TRUE(std::isnan(none.mean));
  const auto one = bagdem::impact_restitution({impacts[0]}, t, v);
  EXPECT_NEAR(one.mean, 0.6, 1e-12);
  EXPECT_TRUE(std::isnan(one.sd));
  // Contents that keep moving towards the wall after each pulse (v leaves at +0.4 v_before: "e" =
  // -0.4, a bed shearing against the wall rather than rebounding): no restitution of a body.
  std::vector<double> v_on(t.size());
  for (std::size_t k = 0; k < t.size(); ++k) {
    std::size_t i = 0;
    while (i + 1 < kTrain.size() && t[k] >= 0.5 * (kTrain[i].centre + kTrain[i + 1].centre)) ++i;
    const double u = kTrain[i].side * std::abs(kTrain[i].impulse()) / (mass * (1 - 0.4));
    v_on[k] = u - kTrain[i].integral(t[k] - 1, t[k]) / mass;
  }
  const auto on = bagdem::impact_restitution(impacts, t, v_on);
  ASSERT_EQ(on.values.size(), kTrain.size());
  EXPECT_NEAR(on.mean, -0.4, 1e-12);
  EXPECT_TRUE(std::isnan(on.body()));

  // Free flight: pulses 20 ms apart and at most 5 ms long fly free for 10 ms on each side; for 25 ms
  // every pulse meets a neighbour (or the record's start).
  const std::vector<double> F = interval_means(t, kDelta, kTrain);
  double largest = 0;
  for (double y : F) largest = std::max(largest, std::abs(y));
  const bagdem::FreeFlight free10{.span = 10e-3, .threshold = 0.05 * largest, .min_approach_speed = 0};
  const auto free = bagdem::impact_restitution(impacts, t, v, F, free10);
  ASSERT_EQ(free.values.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(free.values[i], expected[i], 1e-12);
  const bagdem::FreeFlight free25{.span = 25e-3, .threshold = 0.05 * largest, .min_approach_speed = 0};
  EXPECT_TRUE(bagdem::impact_restitution(impacts, t, v, F, free25).values.empty());
  // A slow approach is left out: the speed bar between the counted impacts' speeds keeps the faster.
  std::vector<double> speeds;
  for (std::size_t i : {0, 1, 2, 4, 5}) speeds.push_back(std::abs(v_before[i]));
  std::vector<double> sorted = speeds;
  std::sort(sorted.begin(), sorted.end());
  const double bar = 0.5 * (sorted[1] + sorted[2]);
  const bagdem::FreeFlight fast{.span = 0, .threshold = 0, .min_approach_speed = bar};
  const auto kept = bagdem::impact_restitution(impacts, t, v, {}, fast);
  ASSERT_EQ(kept.values.size(), 3u);
  std::size_t j = 0;
  for (std::size_t i = 0; i < speeds.size(); ++i)
    if (speeds[i] > bar) EXPECT_NEAR(kept.values[j++], expected[i], 1e-12);
}

}  // namespace
