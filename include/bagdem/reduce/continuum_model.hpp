// The continuum (single-degree-of-freedom) model of the bean-bag damper study, and the exact linear
// systems it approximates (pure math: no dependency on the DEM stepper).
//
// Source: the study "The effective design of bean bag as a vibroimpact damper", as summarised in
// docs/reference-study.md, section 2 (equation numbers are the study's). The bag is reduced to an equivalent
// mass M_b and viscous damping C_b acting on a primary (M_p, K_p, C_p) driven by F sin(w t):
//   (M_p + M_b) x'' + (C_p + C_b) x' + K_p x = F sin(w t)                              (3)
// Symbols: w drive circular frequency (rad/s), w_n = sqrt(K_p / M_p) (rad/s), lambda = w / w_n,
// X_st = F / K_p (m), mu = M_b / M_p, e the bag's coefficient of restitution against the wall, phi
// the impact phase (rad; the cavity moves as X cos(theta) and phi is theta at impact, so the cavity
// speed at impact is w X sin(phi), Eq. 11a), d the total clearance (m), r = (1 + e) / (1 - e).
// The damping numbers C_b / (M_b w) and C_p / (M_p w) are dimensionless and evaluated at the drive
// frequency w; M_b is the bag's real mass (balls + film).
//
// Formulas and where they come from:
//   Eq. (7)   X_st/X = [1 - lambda^2 (1 + mu)] + i lambda^2 [mu C_b/(M_b w) + C_p/(M_p w)]: (3)
//             divided by K_p (consistent form). The study prints "mu M_b/M_p" where mu is meant;
//             Form::printed evaluates that literally, mu M_b/M_p = mu^2, wherever mu multiplies
//             (the added mass and the bag's damping term).
//   Eq. (19a) C_b/(M_b w) = (4/pi) r sin^2(phi);  Eq. (19b) M_b/M_p = (4/pi) r sin(phi) cos(phi)
//             (as printed);  Eq. (22) d/X = |pi r sin(phi) - 2 cos(phi)|. (22) is the kinematics of
//             two symmetric impacts per cycle: the bag leaves a wall at speed r w X sin(phi), flies
//             for half a period while the cavity moves by -2 X cos(phi), and meets the other wall.
//   Eq. (20)  Eq. (7) with (19a) substituted: the bag's term carries r (consistent) or r^2 (as
//             printed); the real part is that of the consistent (7) in both.
//   Eqs. (24)-(26) as printed (approximations: (25) stays finite without damping, (26) can fall
//             below 1); the exact peak of (3) beside them: with a = 1 + mu and
//             2 zeta = (C_b + C_p) / (M_p w_n), X/X_st = 1 / (1 - a lambda^2 + i 2 zeta lambda),
//             lambda_peak^2 = (a - 2 zeta^2) / a^2, |X/X_st|max = a / (2 zeta sqrt(a - zeta^2)).
//   Beam mode r at the bag (docs/reference-study.md, section 2 conventions; standard modal superposition,
//             e.g. Ewins, Modal Testing, 2nd ed., 2000, ch. 2): with a mass-normalised shape phi_r,
//             M_p = 1 / phi_r(x_b)^2, K_p = omega_r^2 M_p, C_p = 2 zeta_r omega_r M_p, and a force F
//             at x_f acts at the bag as F phi_r(x_f) / phi_r(x_b). Exact for one mode.
//   Multi-mode: H(w) = phi_a^T (K - w^2 (M + M_b phi_b phi_b^T) + i w (C + C_b phi_b phi_b^T))^-1 phi_f,
//             the bag a point mass and dashpot at x_b in modal coordinates (same reference).
//
// Phasors: a harmonic quantity is Re(Y e^{i w t}); the complex displacement X is the response
// phasor per force phasor F, so |X| is the amplitude under F sin(w t) and arg X the lag on the force.
// Bad arguments (negative masses, e outside its range, non-finite values, mismatched sizes) are
// programming errors: std::invalid_argument.
#pragma once
#include <complex>
#include <vector>
#include <optional>

#include <Eigen/Core>

namespace bagdem::continuum {

// Which version of a formula of the study: dimensionally consistent (default) or as printed.
enum class Form { consistent, printed };
// "consistent" or "printed": the label for output.
const char* form_name(Form form);

// ---- Eq. (7) -------------------------------------------------------------------------------------

// X_st/X of Eq. (7) (dimensionless, complex): lambda = w/w_n >= 0, mu = M_b/M_p >= 0,
// cb_per_mb_w = C_b/(M_b w), cp_per_mp_w = C_p/(M_p w) (dimensionless, at the drive frequency).
// Form::printed replaces mu by mu M_b/M_p = mu^2 in both places it appears.
std::complex<double> inverse_amplification(double lambda, double mu, double cb_per_mb_w,
                                           double cp_per_mp_w, Form form = Form::consistent);
// |X/X_st| = 1 / |X_st/X| of Eq. (7) (dimensionless; +inf at an undamped resonance).
double amplification(double lambda, double mu, double cb_per_mb_w, double cp_per_mp_w,
                     Form form = Form::consistent);

// ---- Eqs. (19a), (19b), (22) and their inverses --------------------------------------------------

// r = (1 + e)/(1 - e) for e in [0, 1) (dimensionless).
double restitution_factor(double e);

// Eq. (19a): C_b/(M_b w) = (4/pi) r sin^2(phi) (dimensionless); e in [0, 1), phi (rad).
double bag_damping_number(double e, double phi);
// Eq. (19b) as printed: M_b/M_p = (4/pi) r sin(phi) cos(phi) (dimensionless; negative for phi in
// (pi/2, pi)).
double mass_ratio_printed(double e, double phi);
// Eq. (22): d/X = |pi r sin(phi) - 2 cos(phi)| (dimensionless).
double clearance_ratio(double e, double phi);

// Inverse of (19a): e = (pi c - 4 sin^2 phi) / (pi c + 4 sin^2 phi) for c = C_b/(M_b w) and phi
// (rad). Empty when no e in [0, 1) gives c: c < (4/pi) sin^2(phi) (the bag would need e < 0), or
// sin(phi) = 0. c must be finite (a negative c, e.g. a noisy measurement, has no solution).
std::optional<double> restitution_from_damping(double cb_per_mb_w, double phi);

// Inverse of (22): the impact phase phi in (0, pi) (rad) for the clearance ratio d/X >= 0 and
// e in [0, 1). With A = sqrt((pi r)^2 + 4) and delta = atan2(2, pi r) in (0, 0.567], (22) reads
// d/X = |A sin(phi - delta)|. In the convention of (22) the bag leaves one wall and crosses the
// clearance to the other in half a period, so pi r sin(phi) - 2 cos(phi) = +d/X (the sign inside
// the bars is positive for phi in (0, pi)). The root returned is phi = delta + asin((d/X) / A), in
// [delta, delta + pi/2], the one on the rising side of A sin(phi - delta). When 2 < d/X < A a
// second root pi + delta - asin((d/X) / A) lies beyond pi/2 + delta (there (19b) gives a negative
// mass ratio); it is not returned. Empty when d/X > A: no impact phase gives that clearance.
std::optional<double> impact_phase_from_clearance(double d_over_X, double e);

// ---- Eq. (20) ------------------------------------------------------------------------------------

// Eq. (7) with (19a) substituted, and which form was used.
struct ImpactModelResult {
  std::complex<double> inverse_amplification;  // X_st/X (dimensionless)
  double amplification = 0;                    // |X/X_st| (dimensionless)
  Form form = Form::consistent;                // which Eq. (20) produced it
};
// X_st/X = [1 - lambda^2 (1 + mu)] + i lambda^2 [mu (4/pi) r^p sin^2(phi) + C_p/(M_p w)],
// p = 1 (Form::consistent: (19a) substituted into (7)) or p = 2 (Form::printed: the study's (20)).
// lambda, mu, cp_per_mp_w as in Eq. (7); e in [0, 1); phi (rad).
ImpactModelResult impact_model(double lambda, double mu, double e, double phi, double cp_per_mp_w,
                               Form form = Form::consistent);

// ---- Eqs. (24)-(26) as printed, and the exact peak -----------------------------------------------

// Eq. (24) as printed: lambda_peak = 1 / sqrt(1 + mu M_b/M_p + (C_b + C_p)/(M_p w)), with
// mu M_b/M_p = mu^2 literally; damping_number = (C_b + C_p)/(M_p w) >= 0 (dimensionless).
double peak_frequency_ratio_printed(double mu, double damping_number);
// Eq. (25) as printed: |X/X_st|max = (1 + mu^2 + D) / (sqrt(2) mu + D), D = (C_b + C_p)/(M_p w).
double peak_amplification_printed(double mu, double damping_number);
// Eq. (26) as printed (C_p ~ 0): |X/X_st|max = (1 - e) / (4 sqrt(2) mu (1 + e)) + 1/sqrt(2);
// mu > 0, e in [0, 1]. Falls below 1 for large mu: not a bound on a real damper.
double peak_amplification_impacts_printed(double mu, double e);

// The exact maximum of |X/X_st| = 1/|1 - a lambda^2 + i 2 zeta lambda| over lambda >= 0.
struct ExactPeak {
  bool resonant = false;     // false when a < 2 zeta^2: |X/X_st| falls from lambda = 0, no peak
  double lambda = 0;         // where the maximum is: sqrt(a - 2 zeta^2) / a, or 0 (dimensionless)
  double amplification = 0;  // a / (2 zeta sqrt(a - zeta^2)), or 1; +inf for zeta = 0
};
// mu = M_b/M_p >= 0; zeta >= 0 with 2 zeta = (C_b + C_p)/(M_p w_n) (dimensionless).
ExactPeak exact_peak(double mu, double zeta);

// ---- The dimensional linear systems --------------------------------------------------------------

// The linear equivalent system (3).
struct SdofSystem {
  double primary_mass = 0;       // M_p (unit: kg), > 0
  double primary_stiffness = 0;  // K_p (unit: N/m), >= 0
  double primary_damping = 0;    // C_p (unit: N s/m), >= 0
  double bag_mass = 0;           // M_b (unit: kg), >= 0
  double bag_damping = 0;        // C_b (unit: N s/m), >= 0
};
// X = F / (K_p - w^2 (M_p + M_b) + i w (C_p + C_b)) (unit: m) for a force amplitude F (unit: N)
// at w >= 0 (unit: rad/s). Infinite at an undamped resonance.
std::complex<double> sdof_displacement(const SdofSystem& system, double force, double w);
// |X| (unit: m).
double sdof_amplitude(const SdofSystem& system, double force, double w);

// Mode r of a beam seen at the bag: the SDOF whose displacement is the beam's at x_b.
struct ModalSdof {
  SdofSystem system;          // M_p = 1/phi_b^2, K_p = omega^2 M_p, C_p = 2 zeta omega M_p, the bag's M_b, C_b
  double force_factor = 0;    // phi_r(x_f) / phi_r(x_b): a force F at x_f acts on the SDOF as F force_factor
};
// omega_r (unit: rad/s) >= 0, zeta_r >= 0 (dimensionless), shape values of the mass-normalised
// mode (modal mass 1 kg) at the bag and at the force (unit: 1/sqrt(kg)), the bag's mass (unit: kg)
// and damping (unit: N s/m). Derivation: q'' + 2 zeta omega q' + omega^2 q = phi_f F; the bag point
// y = phi_b q; dividing by phi_b^2 gives (3) in y. A node at the bag (phi_b = 0, the bag does not
// move in that mode) is refused: std::invalid_argument.
ModalSdof modal_sdof(double omega, double zeta, double shape_at_bag, double shape_at_force,
                     double bag_mass = 0, double bag_damping = 0);

// A modal model of the primary: unit modal masses (or a full modal mass matrix), diagonal modal
// stiffness k_r = omega_r^2 and damping c_r = 2 zeta_r omega_r. All vectors have one entry per mode.
struct ModalModel {
  Eigen::VectorXd omega;              // omega_r (unit: rad/s), >= 0
  Eigen::VectorXd zeta;               // zeta_r (dimensionless), >= 0
  Eigen::VectorXd shape_at_force;     // phi_r(x_f) (unit: 1/sqrt(kg))
  Eigen::VectorXd shape_at_response;  // phi_r(x_a) (unit: 1/sqrt(kg))
  Eigen::VectorXd shape_at_bag;       // phi_r(x_b) (unit: 1/sqrt(kg))
  // Modal mass matrix (unit: kg; symmetric positive definite), e.g. I + m_c phi_c phi_c^T for a
  // cavity mass m_c at x_c that couples the modes. Empty (the default): the identity.
  Eigen::MatrixXd mass;
};
// The receptance at x_a (unit: m/N) with the bag a point mass (unit: kg) and dashpot (unit: N s/m)
// at x_b: H(w) = phi_a^T (K - w^2 (M + M_b phi_b phi_b^T) + i w (C + C_b phi_b phi_b^T))^-1 phi_f,
// w >= 0 (unit: rad/s); dense complex LU with partial pivoting. The bag's mass and damping may be
// measured values (reduce/compare.hpp): any finite values, negative ones included, are accepted. A singular system (an undamped
// resonance, a rigid mode at w = 0) throws std::domain_error.
std::complex<double> modal_receptance(const ModalModel& model, double bag_mass, double bag_damping,
                                      double w);
// The same with several bags, each a point mass and dashpot at its own place (shape: phi_r there,
// unit: 1/sqrt(kg)): H(w) = phi_a^T (K - w^2 M + i w C + sum_d (-w^2 M_d + i w C_d) phi_d phi_d^T)^-1
// phi_f (model.shape_at_bag unused). One bag at model.shape_at_bag gives modal_receptance's bits.
struct BagAt {
  Eigen::VectorXd shape;
  double mass = 0, damping = 0;  // (unit: kg, N s/m)
};
std::complex<double> modal_receptance(const ModalModel& model, const std::vector<BagAt>& bags, double w);

}  // namespace bagdem::continuum
