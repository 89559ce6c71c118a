// Force time histories (structure/excitation.hpp).
#include "bagdem/structure/excitation.hpp"

#include <cmath>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace bagdem {
namespace {

constexpr double kPi = std::numbers::pi;

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(5);
  s << v;
  return s.str();
}

class Harmonic final : public Excitation {
 public:
  Harmonic(double F, double f, double phase) : F_(F), f_(f), phase_(phase) {}
  double force(double t) const override { return F_ * std::sin(2 * kPi * f_ * t + phase_); }
  std::string describe() const override { return "harmonic force " + fmt(F_) + " N at " + fmt(f_) + " Hz"; }
  double frequency() const override { return f_; }

 private:
  double F_, f_, phase_;
};

class Impulse final : public Excitation {
 public:
  Impulse(double J, double tau, double t0) : J_(J), tau_(tau), t0_(t0) {}
  double force(double t) const override {
    const double s = t - t0_;
    return s >= 0 && s <= tau_ ? kPi * J_ / (2 * tau_) * std::sin(kPi * s / tau_) : 0.0;
  }
  std::string describe() const override {
    return "impulse (half-sine blow) " + fmt(J_) + " N s over " + fmt(tau_) + " s at t = " + fmt(t0_) + " s";
  }

 private:
  double J_, tau_, t0_;
};

class None final : public Excitation {
 public:
  double force(double) const override { return 0.0; }
  std::string describe() const override { return "no force (free response)"; }
};

class Random final : public Excitation {
 public:
  Random(double rms, double lo, double hi, std::uint64_t seed, double period) : rms_(rms), lo_(lo), hi_(hi), seed_(seed) {
    if (!(rms > 0 && lo > 0 && hi > lo)) throw std::invalid_argument("random force: need rms > 0 and 0 < f_lo < f_hi");
    T_ = period > 0 ? period : 200.0 / (hi - lo);
    std::mt19937_64 gen(seed);
    const auto k0 = static_cast<long long>(std::ceil(lo * T_ - 1e-9)), k1 = static_cast<long long>(std::floor(hi * T_ + 1e-9));
    if (k1 < k0) throw std::invalid_argument("random force: no frequency line k/T inside the band; lengthen the period");
    for (long long k = k0; k <= k1; ++k) {
      const double u = static_cast<double>(gen() >> 11) * 0x1.0p-53;  // [0, 1), 53 bits
      w_.push_back(2 * kPi * static_cast<double>(k) / T_);
      phi_.push_back(2 * kPi * u);
    }
    // Equal amplitudes a with RMS a sqrt(n/2).
    a_ = rms * std::sqrt(2.0 / static_cast<double>(w_.size()));
    // One period tabulated with exact values and slopes, unless that table would pass 2^20 rows
    // (a narrow band at a high frequency): then the sum is evaluated at each call.
    const auto n = static_cast<std::size_t>(std::ceil(64 * hi * T_));
    if (n > (1u << 20)) return;
    h_ = T_ / static_cast<double>(n);
    f_.resize(n + 1), d_.resize(n + 1);
    for (std::size_t i = 0; i <= n; ++i) exact(static_cast<double>(i) * h_, f_[i], d_[i]);
  }
  double force(double t) const override {
    if (f_.empty()) {
      double f, df;
      exact(t, f, df);
      return f;
    }
    double s = std::fmod(t, T_);
    if (s < 0) s += T_;
    auto i = static_cast<std::size_t>(s / h_);
    if (i >= f_.size() - 1) i = f_.size() - 2;
    const double x = (s - static_cast<double>(i) * h_) / h_, x2 = x * x, x3 = x2 * x;
    return (2 * x3 - 3 * x2 + 1) * f_[i] + (x3 - 2 * x2 + x) * h_ * d_[i] + (-2 * x3 + 3 * x2) * f_[i + 1] +
           (x3 - x2) * h_ * d_[i + 1];
  }
  // The sum itself (tests, the table).
  void exact(double t, double& f, double& df) const {
    f = df = 0;
    for (std::size_t k = 0; k < w_.size(); ++k) {
      f += a_ * std::cos(w_[k] * t + phi_[k]);
      df -= a_ * w_[k] * std::sin(w_[k] * t + phi_[k]);
    }
  }
  std::string describe() const override {
    return "random force, RMS " + fmt(rms_) + " N in " + fmt(lo_) + "-" + fmt(hi_) + " Hz (" + std::to_string(w_.size()) +
           " lines, period " + fmt(T_) + " s, seed " + std::to_string(seed_) + ")";
  }

 private:
  double rms_, lo_, hi_;
  std::uint64_t seed_;
  double T_ = 0, a_ = 0, h_ = 0;
  std::vector<double> w_, phi_, f_, d_;
};

}  // namespace

std::unique_ptr<Excitation> make_harmonic_force(double amplitude, double frequency_hz, double phase) {
  return std::make_unique<Harmonic>(amplitude, frequency_hz, phase);
}
std::unique_ptr<Excitation> make_impulse_force(double impulse, double duration, double start) {
  return std::make_unique<Impulse>(impulse, duration, start);
}
std::unique_ptr<Excitation> make_random_force(double rms, double f_lo, double f_hi, std::uint64_t seed, double period) {
  return std::make_unique<Random>(rms, f_lo, f_hi, seed, period);
}
std::unique_ptr<Excitation> make_no_force() { return std::make_unique<None>(); }

}  // namespace bagdem
