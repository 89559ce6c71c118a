// Frequency-response and decay figures (structure/response.hpp).
#include "bagdem/structure/response.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <unsupported/Eigen/FFT>

#include "bagdem/structure/primary.hpp"

namespace bagdem {

std::size_t steps_per_cycle(double f, double dt) {
  return std::max<std::size_t>(8, static_cast<std::size_t>(std::llround(1.0 / (f * dt))));
}

void CycleHarmonic::add(double y, std::complex<double> e) {
  ++n_;
  const double n = static_cast<double>(n_);
  sum_ += y * e, e0_ += e, e1_ += n * e, e2_ += n * n * e, total_ += y;
}

double CycleHarmonic::mean() const { return n_ ? total_ / static_cast<double>(n_) : 0.0; }

double CycleHarmonic::Drift::at(std::size_t n, std::size_t N) const {
  const double u = static_cast<double>(n) - 0.5 * (static_cast<double>(N) + 1);
  return slope * u + 0.5 * curvature * u * u;
}

CycleHarmonic::Drift CycleHarmonic::drift(double before, double before_that) const {
  Drift d;
  if (n_ == 0 || std::isnan(before)) return d;
  const double N = static_cast<double>(n_), m = mean();
  if (std::isnan(before_that)) {
    d.slope = (m - before) / N;
  } else {
    d.slope = (3 * m - 4 * before + before_that) / (2 * N);
    d.curvature = (m - 2 * before + before_that) / (N * N);
  }
  return d;
}

std::complex<double> CycleHarmonic::harmonic(const Drift& d) const {
  if (n_ == 0) return {0, 0};
  const double N = static_cast<double>(n_), c = 0.5 * (N + 1);
  const std::complex<double> u1 = e1_ - c * e0_, u2 = e2_ - 2 * c * e1_ + c * c * e0_;  // sum u e, sum u^2 e
  return (2 / N) * (sum_ - d.slope * u1 - 0.5 * d.curvature * u2);
}

void SteadyStateDetector::add(std::complex<double> Y) {
  window_.push_back(Y);
  while (window_.size() > 2 * K_) window_.pop_front();
}

std::complex<double> SteadyStateDetector::block_mean(std::size_t first, std::size_t count) const {
  std::complex<double> m(0, 0);
  for (std::size_t i = first; i < first + count; ++i) m += window_[i];
  return count ? m / static_cast<double>(count) : m;
}

std::complex<double> SteadyStateDetector::mean() const {
  const std::size_t n = std::min(K_, window_.size());
  return block_mean(window_.size() - n, n);
}

double SteadyStateDetector::last_change() const {
  if (window_.size() < 2 * K_) return 1.0;
  const std::complex<double> last = block_mean(K_, K_), before = block_mean(0, K_);
  const double d = std::abs(last - before);
  return std::abs(last) > 0 ? d / std::abs(last) : (d > 0 ? 1.0 : 0.0);
}

bool SteadyStateDetector::within_scatter() const {
  if (K_ < 2 || window_.size() < 2 * K_) return false;
  const std::complex<double> a = block_mean(0, K_), b = block_mean(K_, K_);
  // Deviations from each half's mean; their lag-1 autocorrelation over the window.
  double sa = 0, sb = 0, lag = 0, fourth = 0;
  for (std::size_t i = 0; i < 2 * K_; ++i) {
    const std::complex<double> d = window_[i] - (i < K_ ? a : b);
    (i < K_ ? sa : sb) += std::norm(d);
    fourth += std::norm(d) * std::norm(d);
    if (i + 1 < 2 * K_ && i + 1 != K_) lag += (std::conj(d) * (window_[i + 1] - (i + 1 < K_ ? a : b))).real();
  }
  if (!(sa + sb > 0) || lag > kMaxScatterCorrelation * (sa + sb)) return false;
  const double k = static_cast<double>(K_);
  // Moduli that vary as noise's do: mean |d|^4 / (mean |d|^2)^2 is 2 for complex Gaussian scatter,
  // 1 for a phasor turning at a constant modulus (a fast beat).
  if (fourth * 2 * k < kMinScatterKurtosis * (sa + sb) * (sa + sb)) return false;
  // The first half no noisier than the second by more than chance allows: a one-sided F test at
  // 10 % with nu = 2 (K - 1) degrees of freedom each, ln F ~ N(0, 4 / nu) (2.47 at K = 5).
  if (sa > std::exp(1.2816 * std::sqrt(2.0 / (k - 1))) * sb) return false;
  constexpr double kChi2TwoDof95 = 5.991464547107979;  // -2 ln 0.05
  return std::norm(b - a) <= kChi2TwoDof95 * (sa + sb) / (k - 1) / (2 * k);
}

bool SteadyStateDetector::steady() const {
  return window_.size() >= 2 * K_ && (last_change() <= tol_ || within_scatter());
}

double SteadyStateDetector::spread() const {
  const std::size_t n = std::min(K_, window_.size());
  if (n == 0) return 0.0;
  const std::complex<double> m = mean();
  double s = 0;
  for (std::size_t i = window_.size() - n; i < window_.size(); ++i) s += std::norm(window_[i] - m);
  return std::abs(m) > 0 ? std::sqrt(s / static_cast<double>(n)) / std::abs(m) : 0.0;
}

std::complex<double> sdof_receptance(double M, double C, double K, double w) {
  return 1.0 / std::complex<double>(K - w * w * M, w * C);
}

double reduction_db(double bare_peak, double damped_peak) { return 20 * std::log10(bare_peak / damped_peak); }
double reduction_percent(double db) { return 100 * (1 - std::pow(10.0, -db / 20)); }

Peak find_peak(const std::vector<double>& f, const std::vector<double>& mag, double f_lo, double f_hi) {
  std::size_t best = f.size();
  for (std::size_t k = 0; k < f.size(); ++k)
    if (f[k] >= f_lo && f[k] <= f_hi && (best == f.size() || mag[k] > mag[best])) best = k;
  if (best == f.size()) return {};
  Peak p{f[best], mag[best]};
  if (best == 0 || best + 1 >= f.size() || f[best - 1] < f_lo || f[best + 1] > f_hi) return p;
  if (!(mag[best - 1] > 0 && mag[best + 1] > 0)) return p;
  // A single mode's 1/|H|^2 = K^2 [(1 - f^2/f_n^2)^2 + (2 zeta f/f_n)^2] is a parabola in u = f^2:
  // the parabola v(u) through the three points is exact for one mode however sharp its peak is
  // against the spacing of the samples (one in |H| against f overshoots a sharp one). u and v are
  // taken relative to the middle point.
  auto u = [&](std::size_t k) { return f[k] * f[k] - f[best] * f[best]; };
  auto v = [&](std::size_t k) { return 1 / (mag[k] * mag[k]) - 1 / (mag[best] * mag[best]); };
  const double u0 = u(best - 1), u2 = u(best + 1), v0 = v(best - 1), v2 = v(best + 1);
  if (!(u0 < 0 && u2 > 0)) return p;  // repeated frequencies: no parabola
  // v = a u^2 + b u through (u0, v0), (0, 0), (u2, v2); its minimum at um = -b / (2a).
  const double a = (v0 * u2 - v2 * u0) / (u0 * u2 * (u0 - u2)), b = (v0 - a * u0 * u0) / u0;
  if (!(a > 0)) return p;
  const double um = -b / (2 * a), vm = 1 / (mag[best] * mag[best]) + a * um * um + b * um;
  if (um < u0 || um > u2 || !(vm > 0)) return p;
  return {std::sqrt(f[best] * f[best] + um), 1 / std::sqrt(vm)};
}

DecayFit fit_decay(const std::vector<double>& y, double dt, double factor, double t_skip) {
  DecayFit d;
  const auto first = static_cast<std::size_t>(std::ceil(t_skip / dt));
  std::vector<double> t, lp;
  for (std::size_t k = std::max<std::size_t>(first, 1); k + 1 < y.size(); ++k) {
    if (!(y[k] > 0 && y[k] > y[k - 1] && y[k] >= y[k + 1])) continue;
    // Parabola through the three samples: the peak's time and height.
    const double a = 0.5 * (y[k - 1] - 2 * y[k] + y[k + 1]), b = 0.5 * (y[k + 1] - y[k - 1]);
    const double x = a < 0 ? -b / (2 * a) : 0.0;
    t.push_back((static_cast<double>(k) + x) * dt);
    lp.push_back(std::log(y[k] + b * x + a * x * x));
  }
  d.peaks = t.size();
  if (t.size() < 3) return d;
  const double n = static_cast<double>(t.size());
  double st = 0, sl = 0, stt = 0, stl = 0;
  for (std::size_t k = 0; k < t.size(); ++k) st += t[k], sl += lp[k], stt += t[k] * t[k], stl += t[k] * lp[k];
  const double slope = (n * stl - st * sl) / (n * stt - st * st);
  d.rate = -slope;
  const double Td = (t.back() - t.front()) / (n - 1);
  d.damped_frequency = 1.0 / Td;
  const double wd = 2 * std::numbers::pi * d.damped_frequency;
  d.zeta = d.rate / std::sqrt(d.rate * d.rate + wd * wd);
  d.decay_time = d.rate > 0 ? std::log(factor) / d.rate : 0.0;
  const double limit = lp.front() - std::log(factor);
  for (std::size_t k = t.size(); k-- > 0;) {
    if (lp[k] > limit) {
      d.measured_decay_time = k + 1 < t.size() ? t[k + 1] - t.front() : 0.0;
      break;
    }
  }
  return d;
}

double rms(const std::vector<double>& y, double dt, double t_skip) {
  const auto first = static_cast<std::size_t>(std::ceil(t_skip / dt));
  double s = 0;
  std::size_t n = 0;
  for (std::size_t k = first; k < y.size(); ++k) s += y[k] * y[k], ++n;
  return n ? std::sqrt(s / static_cast<double>(n)) : 0.0;
}

double band_rms(const std::vector<double>& y, double dt, double lo, double hi, double t_skip) {
  const std::size_t after = y.size() - std::min(y.size(), static_cast<std::size_t>(std::ceil(t_skip / dt)));
  if (after < 4) return 0;
  // The last n samples, n the largest 2^a 3^b 5^c not above them (within 7%): the FFT's cost stays
  // n log n whatever the run's length.
  std::size_t n = 1;
  for (std::size_t p2 = 1; p2 <= after; p2 *= 2)
    for (std::size_t p3 = p2; p3 <= after; p3 *= 3)
      for (std::size_t p5 = p3; p5 <= after; p5 *= 5) n = std::max(n, p5);
  const std::size_t first = y.size() - n;
  const double T = static_cast<double>(n) * dt;
  const auto k_lo = static_cast<std::size_t>(std::max(1.0, std::ceil(lo * T)));
  const auto k_hi = static_cast<std::size_t>(std::min(std::floor(hi * T), std::ceil(static_cast<double>(n) / 2) - 1));
  // Eigen's FFT (kissfft, any n): the half spectrum Y_0 .. Y_{n/2}.
  const std::vector<double> x(y.begin() + static_cast<std::ptrdiff_t>(first), y.end());
  std::vector<std::complex<double>> Y;
  Eigen::FFT<double> fft;
  fft.fwd(Y, x);
  double power = 0;
  for (std::size_t k = k_lo; k <= k_hi && k < Y.size(); ++k) power += 2 * std::norm(Y[k]);
  return std::sqrt(power) / static_cast<double>(n);
}

Peak bare_peak(const Primary& p, double lo, double hi) {
  auto mag = [&](double f) { return std::abs(p.bare_receptance(2 * std::numbers::pi * f)); };
  const int n = 400;
  double best = lo, best_m = -1;
  for (int k = 0; k <= n; ++k) {
    const double f = lo + (hi - lo) * k / n, m = mag(f);
    if (m > best_m) best = f, best_m = m;
  }
  double a = std::max(lo, best - (hi - lo) / n), b = std::min(hi, best + (hi - lo) / n);
  const double g = 0.5 * (std::sqrt(5.0) - 1);
  for (int it = 0; it < 80; ++it) {
    const double c = b - g * (b - a), d = a + g * (b - a);
    if (mag(c) > mag(d)) b = d; else a = c;
  }
  const double f = 0.5 * (a + b);
  return {f, mag(f)};
}

}  // namespace bagdem
