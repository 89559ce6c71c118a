// The continuum (SDOF) model of the bean-bag damper study and its exact linear counterparts
// (include/bagdem/reduce/continuum_model.hpp has the formulas and their sources).
#include "bagdem/reduce/continuum_model.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include <Eigen/LU>

namespace bagdem::continuum {

namespace {

constexpr double kPi = std::numbers::pi;

// Programming errors: the function, the argument, its value and what is allowed.
void require(bool ok, const char* function, const char* argument, double value, const char* allowed) {
  if (ok) return;
  char shown[32];
  std::snprintf(shown, sizeof shown, "%.17g", value);
  throw std::invalid_argument(std::string("continuum::") + function + ": " + argument + " = " + shown +
                              ", must be " + allowed);
}

void require_finite(const char* function, const char* argument, double value) {
  require(std::isfinite(value), function, argument, value, "finite");
}

void require_non_negative(const char* function, const char* argument, double value) {
  require(std::isfinite(value) && value >= 0, function, argument, value, "finite and >= 0");
}

void require_restitution(const char* function, double e) {
  require(std::isfinite(e) && e >= 0 && e < 1, function, "e", e, "in [0, 1)");
}

// The mass ratio where Eq. (7) multiplies by it: mu (consistent) or the printed mu M_b/M_p = mu^2.
double mass_factor(double mu, Form form) { return form == Form::printed ? mu * mu : mu; }

}  // namespace

const char* form_name(Form form) { return form == Form::printed ? "printed" : "consistent"; }

std::complex<double> inverse_amplification(double lambda, double mu, double cb_per_mb_w,
                                           double cp_per_mp_w, Form form) {
  require_non_negative("inverse_amplification", "lambda", lambda);
  require_non_negative("inverse_amplification", "mu", mu);
  require_finite("inverse_amplification", "cb_per_mb_w", cb_per_mb_w);
  require_finite("inverse_amplification", "cp_per_mp_w", cp_per_mp_w);
  const double m = mass_factor(mu, form), l2 = lambda * lambda;
  return {1 - l2 * (1 + m), l2 * (m * cb_per_mb_w + cp_per_mp_w)};
}

double amplification(double lambda, double mu, double cb_per_mb_w, double cp_per_mp_w, Form form) {
  return 1 / std::abs(inverse_amplification(lambda, mu, cb_per_mb_w, cp_per_mp_w, form));
}

double restitution_factor(double e) {
  require_restitution("restitution_factor", e);
  return (1 + e) / (1 - e);
}

double bag_damping_number(double e, double phi) {
  require_finite("bag_damping_number", "phi", phi);
  const double s = std::sin(phi);
  return 4 / kPi * restitution_factor(e) * s * s;
}

double mass_ratio_printed(double e, double phi) {
  require_finite("mass_ratio_printed", "phi", phi);
  return 4 / kPi * restitution_factor(e) * std::sin(phi) * std::cos(phi);
}

double clearance_ratio(double e, double phi) {
  require_finite("clearance_ratio", "phi", phi);
  return std::abs(kPi * restitution_factor(e) * std::sin(phi) - 2 * std::cos(phi));
}

std::optional<double> restitution_from_damping(double cb_per_mb_w, double phi) {
  require_finite("restitution_from_damping", "cb_per_mb_w", cb_per_mb_w);
  require_finite("restitution_from_damping", "phi", phi);
  // (19a) as pi c = 4 r s^2 with r = (1 + e)/(1 - e), solved for e without forming r (which is
  // infinite at s = 0).
  const double s = std::sin(phi), four_s2 = 4 * s * s, pi_c = kPi * cb_per_mb_w;
  const double numerator = pi_c - four_s2, denominator = pi_c + four_s2;
  if (!(numerator >= 0) || !(denominator > 0)) return std::nullopt;  // e < 0, or c <= 0 with s = 0
  const double e = numerator / denominator;
  if (!(e < 1)) return std::nullopt;  // s = 0: only e = 1 would do
  return e;
}

std::optional<double> impact_phase_from_clearance(double d_over_X, double e) {
  require_non_negative("impact_phase_from_clearance", "d_over_X", d_over_X);
  const double pr = kPi * restitution_factor(e);
  // pi r sin(phi) - 2 cos(phi) = A sin(phi - delta), A cos(delta) = pi r, A sin(delta) = 2.
  const double A = std::hypot(pr, 2.0), delta = std::atan2(2.0, pr);
  if (d_over_X > A) return std::nullopt;
  return delta + std::asin(d_over_X / A);
}

ImpactModelResult impact_model(double lambda, double mu, double e, double phi, double cp_per_mp_w,
                               Form form) {
  require_non_negative("impact_model", "lambda", lambda);
  require_non_negative("impact_model", "mu", mu);
  require_finite("impact_model", "phi", phi);
  require_finite("impact_model", "cp_per_mp_w", cp_per_mp_w);
  const double r = restitution_factor(e), s = std::sin(phi), l2 = lambda * lambda;
  // The study's printed (20) carries r^2 where substituting (19a) gives r.
  const double r_power = form == Form::printed ? r * r : r;
  const double bag_term = mu * (4 / kPi) * r_power * s * s;
  ImpactModelResult result;
  result.inverse_amplification = {1 - l2 * (1 + mu), l2 * (bag_term + cp_per_mp_w)};
  result.amplification = 1 / std::abs(result.inverse_amplification);
  result.form = form;
  return result;
}

double peak_frequency_ratio_printed(double mu, double damping_number) {
  require_non_negative("peak_frequency_ratio_printed", "mu", mu);
  require_non_negative("peak_frequency_ratio_printed", "damping_number", damping_number);
  return 1 / std::sqrt(1 + mu * mu + damping_number);
}

double peak_amplification_printed(double mu, double damping_number) {
  require_non_negative("peak_amplification_printed", "mu", mu);
  require_non_negative("peak_amplification_printed", "damping_number", damping_number);
  return (1 + mu * mu + damping_number) / (std::numbers::sqrt2 * mu + damping_number);
}

double peak_amplification_impacts_printed(double mu, double e) {
  require(std::isfinite(mu) && mu > 0, "peak_amplification_impacts_printed", "mu", mu, "finite and > 0");
  require(std::isfinite(e) && e >= 0 && e <= 1, "peak_amplification_impacts_printed", "e", e, "in [0, 1]");
  return (1 - e) / (4 * std::numbers::sqrt2 * mu * (1 + e)) + 1 / std::numbers::sqrt2;
}

ExactPeak exact_peak(double mu, double zeta) {
  require_non_negative("exact_peak", "mu", mu);
  require_non_negative("exact_peak", "zeta", zeta);
  const double a = 1 + mu, z2 = zeta * zeta;
  ExactPeak peak;
  // d/d(lambda^2) of |1 - a lambda^2 + i 2 zeta lambda|^2 vanishes at lambda^2 = (a - 2 zeta^2)/a^2;
  // for a <= 2 zeta^2 the modulus grows from lambda = 0 and the maximum of |X/X_st| is 1 there.
  if (a - 2 * z2 <= 0) {
    peak.resonant = false;
    peak.lambda = 0;
    peak.amplification = 1;
    return peak;
  }
  peak.resonant = true;
  peak.lambda = std::sqrt(a - 2 * z2) / a;
  peak.amplification = zeta > 0 ? a / (2 * zeta * std::sqrt(a - z2)) : std::numeric_limits<double>::infinity();
  return peak;
}

namespace {

void require_sdof(const SdofSystem& s, const char* function) {
  require(std::isfinite(s.primary_mass) && s.primary_mass > 0, function, "primary_mass", s.primary_mass,
          "finite and > 0 (unit: kg)");
  require_non_negative(function, "primary_stiffness", s.primary_stiffness);
  require_non_negative(function, "primary_damping", s.primary_damping);
  require_non_negative(function, "bag_mass", s.bag_mass);
  require_non_negative(function, "bag_damping", s.bag_damping);
}

}  // namespace

std::complex<double> sdof_displacement(const SdofSystem& system, double force, double w) {
  require_sdof(system, "sdof_displacement");
  require_finite("sdof_displacement", "force", force);
  require_non_negative("sdof_displacement", "w", w);
  const std::complex<double> dynamic_stiffness{
      system.primary_stiffness - w * w * (system.primary_mass + system.bag_mass),
      w * (system.primary_damping + system.bag_damping)};
  if (dynamic_stiffness == 0.0) return {std::numeric_limits<double>::infinity(), 0};
  return force / dynamic_stiffness;
}

double sdof_amplitude(const SdofSystem& system, double force, double w) {
  return std::abs(sdof_displacement(system, force, w));
}

ModalSdof modal_sdof(double omega, double zeta, double shape_at_bag, double shape_at_force,
                     double bag_mass, double bag_damping) {
  require_non_negative("modal_sdof", "omega", omega);
  require_non_negative("modal_sdof", "zeta", zeta);
  require_finite("modal_sdof", "shape_at_force", shape_at_force);
  require(std::isfinite(shape_at_bag) && shape_at_bag != 0, "modal_sdof", "shape_at_bag", shape_at_bag,
          "finite and non-zero (a node of the mode at the bag: the bag does not move in it)");
  ModalSdof m;
  m.system.primary_mass = 1 / (shape_at_bag * shape_at_bag);
  m.system.primary_stiffness = omega * omega * m.system.primary_mass;
  m.system.primary_damping = 2 * zeta * omega * m.system.primary_mass;
  m.system.bag_mass = bag_mass;
  m.system.bag_damping = bag_damping;
  require_sdof(m.system, "modal_sdof");
  m.force_factor = shape_at_force / shape_at_bag;
  return m;
}

namespace {
// The modal model's own figures, checked (the bags' and w by the callers).
void require_model(const ModalModel& model, const char* fn) {
  const Eigen::Index n = model.omega.size();
  require(n > 0, fn, "modes", static_cast<double>(n), "at least 1");
  require(model.zeta.size() == n, fn, "zeta.size()", static_cast<double>(model.zeta.size()), "omega.size()");
  require(model.shape_at_force.size() == n, fn, "shape_at_force.size()",
          static_cast<double>(model.shape_at_force.size()), "omega.size()");
  require(model.shape_at_response.size() == n, fn, "shape_at_response.size()",
          static_cast<double>(model.shape_at_response.size()), "omega.size()");
  const bool full_mass = model.mass.size() > 0;
  if (full_mass)
    require(model.mass.rows() == n && model.mass.cols() == n, fn, "mass.rows()", static_cast<double>(model.mass.rows()),
            "omega.size(), square (or empty for the identity)");
  require(model.omega.allFinite() && (model.omega.array() >= 0).all(), fn, "omega", model.omega.minCoeff(),
          "finite and >= 0 (unit: rad/s)");
  require(model.zeta.allFinite() && (model.zeta.array() >= 0).all(), fn, "zeta", model.zeta.minCoeff(),
          "finite and >= 0");
  require(model.shape_at_force.allFinite() && model.shape_at_response.allFinite() && (!full_mass || model.mass.allFinite()), fn,
          "shapes/mass", std::numeric_limits<double>::quiet_NaN(), "finite");
}
}  // namespace

std::complex<double> modal_receptance(const ModalModel& model, double bag_mass, double bag_damping,
                                      double w) {
  const char* fn = "modal_receptance";
  require_model(model, fn);
  const Eigen::Index n = model.omega.size();
  require(model.shape_at_bag.size() == n && model.shape_at_bag.allFinite(), fn, "shape_at_bag.size()",
          static_cast<double>(model.shape_at_bag.size()), "omega.size(), finite");
  // A measured impedance (reduce/compare.hpp) may have a negative effective mass (the contents moving
  // against the cavity) or a slightly negative damping (scatter): only finiteness is required.
  require_finite(fn, "bag_mass", bag_mass);
  require_finite(fn, "bag_damping", bag_damping);
  return modal_receptance(model, std::vector<BagAt>{{model.shape_at_bag, bag_mass, bag_damping}}, w);
}

std::complex<double> modal_receptance(const ModalModel& model, const std::vector<BagAt>& bags, double w) {
  const char* fn = "modal_receptance";
  require_model(model, fn);
  const Eigen::Index n = model.omega.size();
  const bool full_mass = model.mass.size() > 0;
  for (const BagAt& b : bags) {
    require(b.shape.size() == n && b.shape.allFinite(), fn, "a bag's shape.size()", static_cast<double>(b.shape.size()), "omega.size(), finite");
    require_finite(fn, "a bag's mass", b.mass);
    require_finite(fn, "a bag's damping", b.damping);
  }
  require_non_negative(fn, "w", w);

  // Dynamic stiffness in modal coordinates: K - w^2 M + i w C, then each bag's rank-one terms.
  Eigen::MatrixXd real_part = full_mass ? Eigen::MatrixXd(model.mass) : Eigen::MatrixXd::Identity(n, n);
  real_part *= -w * w;
  Eigen::MatrixXd imag_part = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index r = 0; r < n; ++r) {
    real_part(r, r) += model.omega(r) * model.omega(r);
    imag_part(r, r) += w * 2 * model.zeta(r) * model.omega(r);
  }
  for (const BagAt& b : bags) {
    const Eigen::MatrixXd bag_outer = b.shape * b.shape.transpose();
    real_part -= (w * w * b.mass) * bag_outer;
    imag_part += (w * b.damping) * bag_outer;
  }

  Eigen::MatrixXcd dynamic_stiffness(n, n);
  dynamic_stiffness.real() = real_part;
  dynamic_stiffness.imag() = imag_part;
  const Eigen::VectorXcd modal_response =
      dynamic_stiffness.partialPivLu().solve(model.shape_at_force.cast<std::complex<double>>());
  // phi_a^T q (no conjugation: Eigen's dot() would conjugate its left operand).
  const std::complex<double> h =
      (model.shape_at_response.cast<std::complex<double>>().array() * modal_response.array()).sum();
  if (!std::isfinite(h.real()) || !std::isfinite(h.imag()))
    throw std::domain_error("continuum::modal_receptance: the system is singular at w = " + std::to_string(w) +
                            " rad/s (an undamped resonance, or a rigid mode at w = 0)");
  return h;
}

}  // namespace bagdem::continuum
