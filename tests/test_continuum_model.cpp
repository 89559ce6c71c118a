// The continuum (SDOF) model of the bean-bag damper study (include/bagdem/reduce/continuum_model.hpp):
// each formula against an independent reference: the inverses against the forward formulas,
// Eq. (7) against the dimensional system (3), Eq. (20) against (7) with (19a) substituted by hand,
// the exact peak against a dense scan, the printed (24)-(26) against hand-computed values, and the
// modal models against sums and 2x2 solves written out by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <initializer_list>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "bagdem/reduce/continuum_model.hpp"
#include "bagdem/structure/modes.hpp"

using namespace bagdem;
using namespace bagdem::continuum;
using cd = std::complex<double>;

namespace {

constexpr double kPi = std::numbers::pi;

double rel_diff(cd a, cd b) { return std::abs(a - b) / std::abs(b); }

// A dynamic-size vector from its entries. (Fixed-size Eigen::Vector2d temporaries assigned to
// VectorXd trip GCC 12's -Warray-bounds inside the AVX-512 load intrinsics: a false positive.)
Eigen::VectorXd vec(std::initializer_list<double> entries) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(entries.size()));
  Eigen::Index i = 0;
  for (double x : entries) v(i++) = x;
  return v;
}

// Golden-section search for the maximum of f on [lo, hi] (f unimodal there).
template <class F>
double golden_max(F f, double lo, double hi) {
  const double g = (std::sqrt(5.0) - 1) / 2;
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = f(x1), f2 = f(x2);
  for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
    if (f1 < f2) {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = f(x2);
    } else {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = f(x1);
    }
  }
  return 0.5 * (lo + hi);
}

}  // namespace

// (19a) forward and back: e -> C_b/(M_b w) -> e over e in (0, 1), phi in (0, pi); and no solution
// where none exists. (19b) as printed against a hand value.
TEST(ContinuumModel, DampingFromRestitutionRoundTrip) {
  std::vector<double> es = {1e-3, 0.999};
  for (int i = 1; i < 20; ++i) es.push_back(i / 20.0);
  double worst = 0;
  int cases = 0;
  for (double e : es)
    for (int j = 1; j < 40; ++j) {
      const double phi = j * kPi / 40;
      const double c = bag_damping_number(e, phi);
      // (19a) by hand.
      const double s = std::sin(phi);
      ASSERT_NEAR(c, 4 / kPi * (1 + e) / (1 - e) * s * s, 1e-15 * c);
      const std::optional<double> back = restitution_from_damping(c, phi);
      ASSERT_TRUE(back.has_value()) << "e = " << e << ", phi = " << phi;
      worst = std::max(worst, std::abs(*back - e));
      ++cases;
    }
  std::printf("  (19a) round trip over %d (e, phi) pairs: max |e' - e| = %.2e\n", cases, worst);
  EXPECT_LT(worst, 1e-13);

  // Just below the e = 0 threshold (4/pi) sin^2(phi): no e in [0, 1) gives it.
  const double phi = 1.0, threshold = 4 / kPi * std::sin(phi) * std::sin(phi);
  EXPECT_FALSE(restitution_from_damping(threshold * (1 - 1e-9), phi).has_value());
  EXPECT_NEAR(restitution_from_damping(threshold, phi).value(), 0.0, 1e-15);
  EXPECT_FALSE(restitution_from_damping(-0.1, phi).has_value());  // negative damping
  EXPECT_FALSE(restitution_from_damping(1.0, 0.0).has_value());   // sin(phi) = 0: only e = 1
  EXPECT_FALSE(restitution_from_damping(0.0, 0.0).has_value());
  std::printf("  no solution below C_b/(M_b w) = (4/pi) sin^2(phi) = %.6f at phi = 1 (e would be < 0)\n", threshold);

  // (19b) as printed, e = 0.5 (r = 3), phi = pi/4: (4/pi) 3 (1/2) = 6/pi; negative beyond pi/2.
  EXPECT_NEAR(mass_ratio_printed(0.5, kPi / 4), 6 / kPi, 1e-15);
  EXPECT_LT(mass_ratio_printed(0.5, 3 * kPi / 4), 0);
  std::printf("  (19b) at e = 0.5, phi = pi/4: %.15f (6/pi = %.15f)\n", mass_ratio_printed(0.5, kPi / 4), 6 / kPi);

  EXPECT_THROW(bag_damping_number(1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(bag_damping_number(-0.1, 1.0), std::invalid_argument);
}

// (22) forward and back: the returned phase reproduces d/X everywhere, and is the phase itself on
// the documented branch phi in [delta, delta + pi/2]; none beyond the largest clearance A.
TEST(ContinuumModel, ClearanceRoundTrip) {
  double worst_ratio = 0, worst_phase = 0;
  int on_branch = 0, cases = 0;
  for (int i = 1; i < 20; ++i)
    for (int j = 1; j < 80; ++j) {
      const double e = i / 20.0, phi = j * kPi / 80, r = (1 + e) / (1 - e);
      const double d_over_X = clearance_ratio(e, phi);
      ASSERT_NEAR(d_over_X, std::abs(kPi * r * std::sin(phi) - 2 * std::cos(phi)), 1e-14 * (1 + d_over_X));
      const std::optional<double> back = impact_phase_from_clearance(d_over_X, e);
      ASSERT_TRUE(back.has_value());
      ASSERT_GT(*back, 0);
      ASSERT_LT(*back, kPi);
      // The sign inside the bars is + for the returned root (the bag crosses to the other wall).
      EXPECT_GE(kPi * r * std::sin(*back) - 2 * std::cos(*back), -1e-12);
      worst_ratio = std::max(worst_ratio, std::abs(clearance_ratio(e, *back) - d_over_X) / (1 + d_over_X));
      const double delta = std::atan2(2.0, kPi * r);
      if (phi >= delta && std::cos(phi - delta) > 0.1) {  // on the branch, away from its fold
        worst_phase = std::max(worst_phase, std::abs(*back - phi));
        ++on_branch;
      }
      ++cases;
    }
  std::printf("  (22) round trip over %d (e, phi) pairs: max |d/X' - d/X| / (1 + d/X) = %.2e\n", cases, worst_ratio);
  std::printf("  phase recovered on the branch [delta, delta + pi/2] (%d pairs): max |phi' - phi| = %.2e rad\n",
              on_branch, worst_phase);
  EXPECT_LT(worst_ratio, 1e-13);
  EXPECT_LT(worst_phase, 1e-12);

  // The largest clearance ratio for e = 0.5: A = sqrt((3 pi)^2 + 4), reached at phi = delta + pi/2.
  const double A = std::hypot(3 * kPi, 2.0), delta = std::atan2(2.0, 3 * kPi);
  EXPECT_NEAR(impact_phase_from_clearance(A, 0.5).value(), delta + kPi / 2, 1e-12);
  EXPECT_FALSE(impact_phase_from_clearance(A * (1 + 1e-9), 0.5).has_value());
  EXPECT_NEAR(impact_phase_from_clearance(0.0, 0.5).value(), delta, 1e-15);
  std::printf("  e = 0.5: largest d/X = %.6f at phi = %.6f rad; none above it\n", A, delta + kPi / 2);
}

// Eq. (7), consistent form, is (3) divided by K_p: compare with the dimensional amplitude. The
// printed form differs by mu -> mu^2 in the added mass and the bag's damping term.
TEST(ContinuumModel, InverseAmplificationMatchesDimensionalSystem) {
  double worst = 0;
  const double Mp = 0.332, Kp = 9.6e4;
  const double wn = std::sqrt(Kp / Mp);
  for (double mu : {0.03, 0.08, 0.14})
    for (double Cb : {0.0, 0.5, 3.0})
      for (double Cp : {0.0, 0.2})
        for (double lambda : {0.3, 0.9, 0.97, 1.0, 1.4}) {
          const double w = lambda * wn, Mb = mu * Mp, F = 2.5;
          const SdofSystem sys{Mp, Kp, Cp, Mb, Cb};
          const cd X = sdof_displacement(sys, F, w);
          const cd reference = (F / Kp) / X;
          const cd model = inverse_amplification(lambda, mu, Cb / (Mb * w), Cp / (Mp * w));
          // Near resonance 1 - lambda^2 (1 + mu) cancels: measure against the size of its terms.
          worst = std::max(worst, std::abs(model - reference) / (1 + lambda * lambda * (1 + mu)));
          EXPECT_NEAR(amplification(lambda, mu, Cb / (Mb * w), Cp / (Mp * w)), std::abs(X) / (F / Kp),
                      1e-13 * std::abs(X) / (F / Kp));
          const cd printed = inverse_amplification(lambda, mu, Cb / (Mb * w), Cp / (Mp * w), Form::printed);
          EXPECT_NEAR(printed.real(), 1 - lambda * lambda * (1 + mu * mu), 1e-15);
          EXPECT_NEAR(printed.imag(), lambda * lambda * (mu * mu * Cb / (Mb * w) + Cp / (Mp * w)), 1e-15);
        }
  std::printf("  Eq. (7) against F/(K_p X) of Eq. (3), 90 points: max |difference| / (1 + lambda^2 (1 + mu)) %.2e\n",
              worst);
  EXPECT_LT(worst, 1e-14);
  EXPECT_STREQ(form_name(Form::consistent), "consistent");
  EXPECT_STREQ(form_name(Form::printed), "printed");
}

// Eq. (20): consistent = (7) with (19a) substituted by hand; printed = the bag's term times r.
TEST(ContinuumModel, ImpactModelIsSevenWithNineteenA) {
  double worst = 0, worst_printed = 0;
  int cases = 0;
  for (double lambda : {0.5, 0.95, 1.0, 1.2})
    for (double mu : {0.03, 0.08, 0.1})
      for (double e : {0.1, 0.5, 0.9})
        for (double phi : {0.3, 1.0, 2.0})
          for (double cp : {0.0, 0.004}) {
            const double r = (1 + e) / (1 - e), s = std::sin(phi);
            const double cb_by_hand = 4 / kPi * r * s * s;
            const cd reference = inverse_amplification(lambda, mu, cb_by_hand, cp);
            const ImpactModelResult consistent = impact_model(lambda, mu, e, phi, cp);
            EXPECT_EQ(consistent.form, Form::consistent);
            worst = std::max(worst, rel_diff(consistent.inverse_amplification, reference));
            EXPECT_NEAR(consistent.amplification, 1 / std::abs(reference), 1e-14 / std::abs(reference));

            const ImpactModelResult printed = impact_model(lambda, mu, e, phi, cp, Form::printed);
            EXPECT_EQ(printed.form, Form::printed);
            EXPECT_EQ(printed.inverse_amplification.real(), consistent.inverse_amplification.real());
            // The bag's part of the imaginary part carries one more factor r.
            const double cp_part = lambda * lambda * cp;
            const double bag_consistent = consistent.inverse_amplification.imag() - cp_part;
            const double bag_printed = printed.inverse_amplification.imag() - cp_part;
            worst_printed = std::max(worst_printed, std::abs(bag_printed - r * bag_consistent) /
                                                        printed.inverse_amplification.imag());
            if (cp == 0) {  // then the whole imaginary part is the bag's
              EXPECT_NEAR(printed.inverse_amplification.imag() / consistent.inverse_amplification.imag(), r,
                          1e-14 * r);
            }
            ++cases;
          }
  std::printf("  Eq. (20) consistent against (7) + (19a) by hand, %d points: max relative difference %.2e\n", cases,
              worst);
  std::printf("  printed minus r x consistent (bag term), relative to Im: max %.2e\n", worst_printed);
  EXPECT_LT(worst, 1e-14);
  EXPECT_LT(worst_printed, 1e-14);
  const ImpactModelResult example = impact_model(1.0, 0.08, 0.5, 1.0, 0.0, Form::printed);
  std::printf("  example lambda = 1, mu = 0.08, e = 0.5, phi = 1: |X/X_st| %s = %.4f, %s = %.4f\n",
              form_name(Form::consistent), impact_model(1.0, 0.08, 0.5, 1.0, 0.0).amplification,
              form_name(example.form), example.amplification);
}

// The exact peak of X/X_st = 1/(1 - a lambda^2 + i 2 zeta lambda) against a dense scan of Eq. (7)
// (consistent) refined by golden-section search, including the case without a peak.
TEST(ContinuumModel, ExactPeakMatchesDenseScan) {
  struct Case {
    double mu, zeta;
  };
  for (const Case c : {Case{0.08, 0.01}, Case{0.08, 0.05}, Case{0.03, 0.2}, Case{0.1, 0.7}, Case{0.1, 0.8},
                       Case{0.0, 0.3}}) {
    // Split the damping between bag and primary (70/30) and evaluate (7) through its damping
    // numbers: C/(M w) = 2 zeta w_n / w = 2 zeta / lambda.
    const double zeta_b = 0.7 * c.zeta, zeta_p = c.zeta - zeta_b;
    auto amp = [&](double lambda) {
      if (lambda == 0) return 1.0;
      const double cb = c.mu > 0 ? 2 * zeta_b / (c.mu * lambda) : 0, cp = 2 * (c.mu > 0 ? zeta_p : c.zeta) / lambda;
      return amplification(lambda, c.mu, cb, cp);
    };
    const int n = 200000;
    const double top = 2.0, h = top / n;
    int best = 0;
    for (int i = 1; i <= n; ++i)
      if (amp(i * h) > amp(best * h)) best = i;
    double lambda_scan = 0, peak_scan = 1;
    if (best > 0) {
      lambda_scan = golden_max(amp, (best - 1) * h, (best + 1) * h);
      peak_scan = amp(lambda_scan);
    }
    const ExactPeak exact = exact_peak(c.mu, c.zeta);
    std::printf("  mu = %.2f zeta = %.2f: scan lambda %.9f |X/X_st| %.9f; exact %s lambda %.9f |X/X_st| %.9f\n",
                c.mu, c.zeta, lambda_scan, peak_scan, exact.resonant ? "peak" : "no peak", exact.lambda,
                exact.amplification);
    EXPECT_EQ(exact.resonant, best > 0);
    EXPECT_NEAR(exact.amplification, peak_scan, 1e-6 * peak_scan);
    EXPECT_NEAR(exact.lambda, lambda_scan, 1e-6 * std::max(lambda_scan, 1e-3));
    EXPECT_GE(exact.amplification, 1.0);
  }
  const ExactPeak undamped = exact_peak(0.1, 0.0);
  EXPECT_TRUE(std::isinf(undamped.amplification));
  EXPECT_NEAR(undamped.lambda, 1 / std::sqrt(1.1), 1e-15);
  // At a = 2 zeta^2 the two branches meet at lambda = 0, |X/X_st| = 1.
  const ExactPeak fold = exact_peak(0.1, std::sqrt(0.55) * (1 - 1e-12));
  EXPECT_NEAR(fold.amplification, 1.0, 1e-9);
  EXPECT_NEAR(fold.lambda, 0.0, 1e-5);
}

// Eqs. (24)-(26) as printed, each against a value computed by hand; (26) falls below 1 for large mu
// (no real damper does: the exact peak is always >= 1).
TEST(ContinuumModel, PrintedPeakFormulas) {
  // (24), mu = 0.1, D = 0.05: 1/sqrt(1 + 0.01 + 0.05) = 1/sqrt(1.06) = 0.971285862357264.
  EXPECT_NEAR(peak_frequency_ratio_printed(0.1, 0.05), 0.971285862357264, 1e-14);
  // (25), mu = 0.1, D = 0.05: 1.06 / (0.141421356237310 + 0.05) = 5.53752214923132.
  EXPECT_NEAR(peak_amplification_printed(0.1, 0.05), 5.53752214923132, 1e-13);
  // (26), mu = 0.08, e = 0.5: 0.5 / (4 sqrt(2) 0.08 1.5) + 1/sqrt(2) = 0.736570 + 0.707107 = 1.44367634492253.
  EXPECT_NEAR(peak_amplification_impacts_printed(0.08, 0.5), 1.44367634492253, 1e-13);
  std::printf("  (24) mu 0.1 D 0.05: %.15f   (25): %.14f   (26) mu 0.08 e 0.5: %.14f\n",
              peak_frequency_ratio_printed(0.1, 0.05), peak_amplification_printed(0.1, 0.05),
              peak_amplification_impacts_printed(0.08, 0.5));
  // (25) stays finite without damping, where the exact peak is infinite.
  EXPECT_TRUE(std::isfinite(peak_amplification_printed(0.1, 0.0)));
  EXPECT_TRUE(std::isinf(exact_peak(0.1, 0.0).amplification));

  // (26) = 1 at mu* = (1 - e) / (4 sqrt(2) (1 + e) (1 - 1/sqrt(2))); above it (26) < 1.
  for (double e : {0.0, 0.5, 0.8}) {
    const double mu_star = (1 - e) / (4 * std::numbers::sqrt2 * (1 + e) * (1 - 1 / std::numbers::sqrt2));
    EXPECT_NEAR(peak_amplification_impacts_printed(mu_star, e), 1.0, 1e-14);
    EXPECT_GT(peak_amplification_impacts_printed(0.99 * mu_star, e), 1.0);
    EXPECT_LT(peak_amplification_impacts_printed(1.01 * mu_star, e), 1.0);
    std::printf("  e = %.1f: (26) falls below 1 for mu > %.4f; at mu = 0.5 it gives %.4f\n", e, mu_star,
                peak_amplification_impacts_printed(0.5, e));
  }
  EXPECT_LT(peak_amplification_impacts_printed(0.5, 0.5), 1.0);
  for (double zeta : {0.01, 0.1, 0.5, 0.74}) EXPECT_GE(exact_peak(0.5, zeta).amplification, 1.0);
}

// The exact SDOF (3) is the one-mode modal model (unit modal mass, unit shapes).
TEST(ContinuumModel, SdofEqualsOneModeModalModel) {
  const double omega = 2 * kPi * 85.6, zeta = 0.004, Mb = 0.08, Cb = 1.5, F = 3.0;
  ModalModel model;
  model.omega = Eigen::VectorXd::Constant(1, omega);
  model.zeta = Eigen::VectorXd::Constant(1, zeta);
  model.shape_at_force = model.shape_at_response = model.shape_at_bag = Eigen::VectorXd::Ones(1);
  const SdofSystem sys{1.0, omega * omega, 2 * zeta * omega, Mb, Cb};
  double worst = 0;
  for (int i = 0; i <= 100; ++i) {
    const double w = omega * (0.5 + i / 100.0);
    worst = std::max(worst, rel_diff(F * modal_receptance(model, Mb, Cb, w), sdof_displacement(sys, F, w)));
  }
  std::printf("  one-mode modal model against the SDOF over 0.5-1.5 omega (101 points): max rel. diff. %.2e\n",
              worst);
  EXPECT_LT(worst, 1e-13);  // round-off of two paths through a cancelling dynamic stiffness
  EXPECT_NEAR(sdof_amplitude(sys, F, 0.0), F / (omega * omega), 1e-15 * F / (omega * omega));
}

// Without a bag, the modal model is the modal sum phi_a phi_f / (k_r - w^2 + i w c_r).
TEST(ContinuumModel, ModalModelWithoutBagIsModalSum) {
  ModalModel model;
  model.omega = vec({2 * kPi * 85.6, 2 * kPi * 235.9, 2 * kPi * 462.4, 2 * kPi * 764.3});
  model.zeta = vec({0.002, 0.003, 0.004, 0.005});
  model.shape_at_force = vec({2.1, -1.3, 0.4, 1.9});
  model.shape_at_response = vec({1.7, 0.6, -2.2, 0.8});
  model.shape_at_bag = vec({2.4, 0.0, -1.1, 0.3});
  double worst = 0;
  for (int i = 0; i <= 200; ++i) {
    const double w = 2 * kPi * (20 + 4 * i);
    cd sum = 0;
    for (int r = 0; r < 4; ++r) {
      const double k = model.omega(r) * model.omega(r), c = 2 * model.zeta(r) * model.omega(r);
      sum += model.shape_at_response(r) * model.shape_at_force(r) / cd(k - w * w, w * c);
    }
    worst = std::max(worst, rel_diff(modal_receptance(model, 0.0, 0.0, w), sum));
  }
  std::printf("  4 modes, no bag, 20-820 Hz (201 points): max relative difference from the modal sum %.2e\n", worst);
  EXPECT_LT(worst, 1e-12);
}

// With a bag (and a cavity mass coupling the modes), two modes against the 2x2 system written out
// and solved by Cramer's rule.
TEST(ContinuumModel, ModalModelWithBagMatchesTwoModeHandSolve) {
  const double w1 = 2 * kPi * 85.6, w2 = 2 * kPi * 462.4, z1 = 0.003, z2 = 0.005;
  const double fa[2] = {1.9, -0.7}, fb[2] = {-1.2, 2.3}, ff[2] = {2.0, 1.1}, fc[2] = {0.8, -1.5};
  const double Mb = 0.026, Cb = 2.0, mc = 0.05;
  for (bool cavity : {false, true}) {
    ModalModel model;
    model.omega = vec({w1, w2});
    model.zeta = vec({z1, z2});
    model.shape_at_force = vec({ff[0], ff[1]});
    model.shape_at_response = vec({fa[0], fa[1]});
    model.shape_at_bag = vec({fb[0], fb[1]});
    if (cavity) {
      const Eigen::VectorXd pc = vec({fc[0], fc[1]});
      model.mass = Eigen::MatrixXd::Identity(2, 2) + mc * pc * pc.transpose();
    }
    double worst = 0;
    for (int i = 0; i <= 120; ++i) {
      const double w = 2 * kPi * (40 + 5 * i);
      // A_jk = delta_jk (k_j + i w c_j) - w^2 (M_jk + M_b fb_j fb_k) + i w C_b fb_j fb_k
      cd A[2][2];
      const double k[2] = {w1 * w1, w2 * w2}, c[2] = {2 * z1 * w1, 2 * z2 * w2};
      for (int j = 0; j < 2; ++j)
        for (int l = 0; l < 2; ++l) {
          const double M_jl = (j == l ? 1.0 : 0.0) + (cavity ? mc * fc[j] * fc[l] : 0.0);
          A[j][l] = cd(-w * w * (M_jl + Mb * fb[j] * fb[l]), w * Cb * fb[j] * fb[l]);
          if (j == l) A[j][l] += cd(k[j], w * c[j]);
        }
      const cd det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
      const cd q0 = (A[1][1] * ff[0] - A[0][1] * ff[1]) / det;
      const cd q1 = (A[0][0] * ff[1] - A[1][0] * ff[0]) / det;
      const cd by_hand = fa[0] * q0 + fa[1] * q1;
      worst = std::max(worst, rel_diff(modal_receptance(model, Mb, Cb, w), by_hand));
    }
    std::printf("  2 modes with a bag%s, 40-640 Hz (121 points): max relative difference from Cramer %.2e\n",
                cavity ? " and a cavity mass" : "", worst);
    EXPECT_LT(worst, 1e-12);
  }
}

// The equivalent SDOF of a beam mode at the bag: one mode of the study's pipe (free-free, analytic
// mass-normalised shapes), bag at mid-span, force at 0.1 L: the modal model's response at x_b
// near resonance equals the SDOF displacement under F phi_f/phi_b.
TEST(ContinuumModel, BeamModeEquivalentSdof) {
  const UniformBeam pipe{1.39, 514.8, 0.332 / 1.39, BeamEnds::free_free};
  const auto modes = analytic_beam_modes(pipe, 1, false);
  const double omega = modes->omega(0), zeta = 0.003, xb = 0.5 * pipe.length, xf = 0.1 * pipe.length;
  const double phi_b = modes->shape(0, xb), phi_f = modes->shape(0, xf), Mb = 0.08 * 0.332, Cb = 1.2, F = 1.0;
  const ModalSdof sdof = modal_sdof(omega, zeta, phi_b, phi_f, Mb, Cb);
  ModalModel model;
  model.omega = Eigen::VectorXd::Constant(1, omega);
  model.zeta = Eigen::VectorXd::Constant(1, zeta);
  model.shape_at_force = Eigen::VectorXd::Constant(1, phi_f);
  model.shape_at_response = model.shape_at_bag = Eigen::VectorXd::Constant(1, phi_b);
  double worst = 0;
  const double w_res = omega / std::sqrt(1 + Mb * phi_b * phi_b);
  for (int i = -50; i <= 50; ++i) {
    const double w = w_res * (1 + 0.001 * i);
    const cd modal = F * modal_receptance(model, Mb, Cb, w);
    const cd equivalent = sdof_displacement(sdof.system, F * sdof.force_factor, w);
    worst = std::max(worst, rel_diff(modal, equivalent));
  }
  std::printf("  pipe mode 1 (%.2f Hz), M_p at mid-span = %.4f kg, force factor %.4f: max rel. diff. %.2e near "
              "resonance (101 points)\n",
              omega / (2 * kPi), sdof.system.primary_mass, sdof.force_factor, worst);
  EXPECT_LT(worst, 1e-12);
  EXPECT_NEAR(sdof.system.primary_mass * phi_b * phi_b, 1.0, 1e-14);
  // At a free end of a uniform free-free beam every elastic mode normalised to mean square 1 has
  // |phi| = 2 (Blevins 1979, table 8-1), so the mass seen there is a quarter of the beam's mass.
  const ModalSdof at_end = modal_sdof(omega, zeta, modes->shape(0, 0.0), phi_f);
  std::printf("  M_p at the free end = %.6f kg (m/4 = %.6f kg)\n", at_end.system.primary_mass, 0.332 / 4);
  EXPECT_NEAR(at_end.system.primary_mass, 0.332 / 4, 1e-10);
}

// Refusals: a node at the bag, malformed models, a singular system.
TEST(ContinuumModel, Refusals) {
  EXPECT_THROW(modal_sdof(500.0, 0.01, 0.0, 1.0), std::invalid_argument);
  try {
    modal_sdof(500.0, 0.01, 0.0, 1.0);
  } catch (const std::invalid_argument& error) {
    std::printf("  node at the bag: %s\n", error.what());
  }
  ModalModel model;
  model.omega = vec({100, 200});
  model.zeta = vec({0.01, 0.01});
  model.shape_at_force = model.shape_at_response = vec({1, 1});
  model.shape_at_bag = Eigen::VectorXd::Ones(3);
  EXPECT_THROW(modal_receptance(model, 0.1, 0.0, 150.0), std::invalid_argument);
  model.shape_at_bag = vec({1, 1});
  model.mass = Eigen::MatrixXd::Identity(3, 3);
  EXPECT_THROW(modal_receptance(model, 0.1, 0.0, 150.0), std::invalid_argument);
  model.mass.resize(0, 0);
  // A measured impedance may be negative (scatter, contents moving against the cavity): accepted;
  // a non-finite one is not.
  EXPECT_NO_THROW(modal_receptance(model, -0.1, -1e-3, 150.0));
  EXPECT_THROW(modal_receptance(model, std::nan(""), 0.0, 150.0), std::invalid_argument);
  model.zeta.setZero();
  EXPECT_THROW(modal_receptance(model, 0.0, 0.0, 100.0), std::domain_error);  // undamped resonance
  EXPECT_THROW(sdof_displacement(SdofSystem{0.0, 1.0, 0.0, 0.0, 0.0}, 1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(inverse_amplification(-1.0, 0.1, 0.0, 0.0), std::invalid_argument);
  EXPECT_THROW(impact_phase_from_clearance(-0.1, 0.5), std::invalid_argument);
}
