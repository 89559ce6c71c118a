// First-harmonic projection and effective parameters (reduce/harmonic_projection.hpp).
#include "bagdem/reduce/harmonic_projection.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "bagdem/reduce/interval.hpp"

namespace bagdem {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Mean and standard error (sample sd / sqrt(n)) of a list of values; the error is NaN for n < 2.
struct MeanAndError {
  double mean = kNaN, standard_error = kNaN;
};
MeanAndError mean_and_error(const std::vector<double>& v) {
  MeanAndError r;
  if (v.empty()) return r;
  const double n = static_cast<double>(v.size());
  double sum = 0;
  for (double x : v) sum += x;
  r.mean = sum / n;
  if (v.size() < 2) return r;
  double ss = 0;
  for (double x : v) ss += (x - r.mean) * (x - r.mean);
  r.standard_error = std::sqrt(ss / (n - 1)) / std::sqrt(n);
  return r;
}

// Least-squares fit of y_k ~ offset + a c_k + b s_k over the samples [first, last). The constant is
// eliminated by centring (one Gram-Schmidt step), which leaves a 2x2 system solved by Cramer's rule;
// over a cycle of at least 3 samples c and s are far from collinear, so it is well conditioned.
struct CycleFit {
  std::complex<double> Y;
  double offset = 0;
};
CycleFit fit_cycle(const std::vector<double>& t, const std::vector<double>& y, std::size_t first, std::size_t last,
                   double w, double delta, Sampling sampling) {
  // Interval means of cos and sin: e^{i w (t - Delta/2)} sinc(w Delta/2) (see the header).
  const bool mean = sampling == Sampling::interval_mean;
  const double half = 0.5 * w * delta;
  const double gain = mean ? std::sin(half) / half : 1.0;
  const double shift = mean ? 0.5 * delta : 0.0;
  const std::size_t n = last - first;
  std::vector<double> c(n), s(n);
  double mc = 0, ms = 0, my = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double phase = w * (t[first + k] - shift);
    c[k] = gain * std::cos(phase);
    s[k] = gain * std::sin(phase);
    mc += c[k], ms += s[k], my += y[first + k];
  }
  const double nn = static_cast<double>(n);
  mc /= nn, ms /= nn, my /= nn;
  double cc = 0, cs = 0, ss = 0, cy = 0, sy = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double dc = c[k] - mc, ds = s[k] - ms, dy = y[first + k] - my;
    cc += dc * dc, cs += dc * ds, ss += ds * ds, cy += dc * dy, sy += ds * dy;
  }
  const double det = cc * ss - cs * cs;
  const double a = (cy * ss - sy * cs) / det, b = (sy * cc - cy * cs) / det;
  return {{a, -b}, my - a * mc - b * ms};  // y = Re(Y e^{iwt}) = Re Y cos - Im Y sin
}

// The sample index ranges of the whole cycles (header: "Cycles").
struct Cycles {
  std::size_t first = 0;               // i0
  std::vector<std::size_t> bounds;     // cycle j is [bounds[j], bounds[j + 1])
  double delta = 0, period = 0;        // (unit: s)
};
Cycles whole_cycles(const std::vector<double>& t, std::size_t values, double f, double t_skip, const char* who) {
  if (values != t.size())
    throw std::invalid_argument(std::string(who) + ": " + std::to_string(values) + " values for " +
                                std::to_string(t.size()) + " times");
  if (!(f > 0) || !std::isfinite(f))
    throw std::invalid_argument(std::string(who) + ": frequency " + std::to_string(f) + " Hz must be > 0");
  Cycles cy;
  cy.delta = sample_interval(t);
  cy.period = 1 / f;
  const double P = cy.period / cy.delta;  // samples per period
  if (!(P >= 3))
    throw std::invalid_argument(std::string(who) + ": " + std::to_string(P) +
                                " samples per period; the first harmonic needs at least 3");
  while (cy.first < t.size() && t[cy.first] < t_skip) ++cy.first;
  const std::size_t available = t.size() - cy.first;
  constexpr double kBoundaryTolerance = 1e-6;  // of a sample: a whole P gives P samples per cycle
  auto bound = [&](std::size_t j) {
    return static_cast<std::size_t>(std::ceil(static_cast<double>(j) * P - kBoundaryTolerance));
  };
  for (std::size_t j = 0; bound(j) <= available; ++j) cy.bounds.push_back(cy.first + bound(j));
  if (cy.bounds.size() < 2)
    throw std::invalid_argument(std::string(who) + ": the samples after t_skip = " + std::to_string(t_skip) +
                                " s hold " + std::to_string(available) + " samples, fewer than one whole cycle (" +
                                std::to_string(P) + " samples)");
  return cy;
}

HarmonicFit fit_cycles(const std::vector<double>& t, const std::vector<double>& y, const Cycles& cy, double f,
                       Sampling sampling) {
  const double w = 2 * std::numbers::pi * f;
  const std::size_t n = cy.bounds.size() - 1;
  HarmonicFit fit;
  fit.per_cycle.reserve(n);
  std::vector<double> re(n), im(n), off(n);
  for (std::size_t j = 0; j < n; ++j) {
    const CycleFit c = fit_cycle(t, y, cy.bounds[j], cy.bounds[j + 1], w, cy.delta, sampling);
    fit.per_cycle.push_back(c.Y);
    re[j] = c.Y.real(), im[j] = c.Y.imag(), off[j] = c.offset;
  }
  const MeanAndError mr = mean_and_error(re), mi = mean_and_error(im);
  fit.amplitude = {mr.mean, mi.mean};
  fit.standard_error = {mr.standard_error, mi.standard_error};
  fit.offset = mean_and_error(off).mean;
  fit.t_begin = t[cy.first];
  fit.t_end = fit.t_begin + static_cast<double>(n) * cy.period;
  return fit;
}

}  // namespace

double sample_interval(const std::vector<double>& t) {
  if (t.size() < 2) throw std::invalid_argument("sample times: " + std::to_string(t.size()) + " samples, need at least 2");
  const double delta = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  if (!(delta > 0) || !std::isfinite(delta))
    throw std::invalid_argument("sample times: the spacing " + std::to_string(delta) + " s must be > 0");
  // Deviation from the uniform grid, not from the previous sample, so that no drift passes.
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double off = t[k] - (t.front() + static_cast<double>(k) * delta);
    if (!(std::abs(off) <= 1e-6 * delta))
      throw std::invalid_argument("sample times are not uniform: t[" + std::to_string(k) + "] = " +
                                  std::to_string(t[k]) + " s lies " + std::to_string(off / delta) +
                                  " intervals off the uniform grid of spacing " + std::to_string(delta) + " s");
  }
  return delta;
}

HarmonicFit first_harmonic(const std::vector<double>& t, const std::vector<double>& y, double f, double t_skip,
                           Sampling sampling) {
  return fit_cycles(t, y, whole_cycles(t, y.size(), f, t_skip, "first_harmonic"), f, sampling);
}

EffectiveParameters effective_parameters(const std::vector<double>& t, const std::vector<double>& x,
                                         const std::vector<double>& force, double f, double t_skip,
                                         Sampling displacement_sampling) {
  const Cycles cy = whole_cycles(t, x.size(), f, t_skip, "effective_parameters (displacement)");
  if (force.size() != t.size())
    throw std::invalid_argument("effective_parameters: " + std::to_string(force.size()) + " force values for " +
                                std::to_string(t.size()) + " times");
  const HarmonicFit X = fit_cycles(t, x, cy, f, displacement_sampling);
  const HarmonicFit F = fit_cycles(t, force, cy, f, Sampling::interval_mean);
  const double w = 2 * std::numbers::pi * f;
  const std::size_t n = X.per_cycle.size();
  std::vector<double> mass(n), damping(n), energy(n);
  for (std::size_t j = 0; j < n; ++j) {
    const std::complex<double> Xj = X.per_cycle[j], Fj = F.per_cycle[j];
    if (std::abs(Xj) == 0)
      throw std::invalid_argument("effective_parameters: cycle " + std::to_string(j) +
                                  " of the displacement has no first harmonic (a still cavity)");
    const std::complex<double> H = Fj / Xj;  // w^2 M_eff - i w C_eff
    mass[j] = H.real() / (w * w);
    damping[j] = -H.imag() / w;
    energy[j] = -std::numbers::pi * (Fj * std::conj(Xj)).imag();  // = pi C w |X_j|^2
  }
  const Interval m = batch_means_interval(mass), c = batch_means_interval(damping), e = batch_means_interval(energy);
  EffectiveParameters p;
  p.frequency = f;
  p.displacement = X.amplitude;
  p.force = F.amplitude;
  p.mass = m.mean, p.mass_se = m.se, p.mass_ci95 = m.ci95;
  p.damping = c.mean, p.damping_se = c.se, p.damping_ci95 = c.ci95;
  p.energy_per_cycle = e.mean, p.energy_per_cycle_se = e.se, p.energy_per_cycle_ci95 = e.ci95;
  p.loss_factor = p.damping / (p.mass * w);
  p.cycles = n;
  return p;
}

double motion_phase(std::complex<double> X_hat, double w, double t) {
  constexpr double two_pi = 2 * std::numbers::pi;
  double theta = std::fmod(w * t + std::arg(X_hat), two_pi);
  if (theta < 0) theta += two_pi;
  return theta < two_pi ? theta : 0.0;  // -tiny + 2 pi rounds to 2 pi
}

}  // namespace bagdem
