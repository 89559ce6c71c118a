// Analytic modes of a uniform Euler-Bernoulli beam; see include/bagdem/structure/modes.hpp for the
// model and src/structure/beam_basis.hpp for the stable form of the shapes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "bagdem/structure/modes.hpp"
#include "beam_basis.hpp"

namespace bagdem {

namespace {

constexpr const char* kEndNames[] = {"free-free", "pinned-pinned", "clamped-free", "clamped-clamped"};

// Root of cos x - s / cosh x in [lo, hi] (one sign change there), bisected until the interval
// cannot shrink. f is evaluated without large terms, so the root is good to an ulp or two.
double bisect_root(double s, double lo, double hi) {
  auto f = [s](double x) { return std::cos(x) - s / std::cosh(x); };
  const bool lo_negative = f(lo) < 0;
  for (;;) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) return mid;
    ((f(mid) < 0) == lo_negative ? lo : hi) = mid;
  }
}

// One mode: elastic, phi = scale * sum k_i basis_i(beta x) with lam = beta L; or rigid,
// phi = p0 + p1 x.
struct AnalyticMode {
  double lam = 0;
  beam_detail::Coeffs k{};
  double scale = 0;  // (unit: 1/sqrt(kg))
  bool rigid = false;
  double p0 = 0, p1 = 0;  // (unit: 1/sqrt(kg), 1/(m sqrt(kg)))
};

// integral_0^lam phi^2 dxi from the end values (integrate 4 phi^2 = 4 phi'''' phi by parts):
//   4 integral phi^2 = [xi (phi^2 + phi''^2 - 2 phi' phi''') + 3 phi phi''' - phi' phi'']_0^lam.
double square_integral(const beam_detail::Coeffs& k, double lam) {
  auto F = [&](double xi) {
    const double p0 = beam_detail::eval(k, 0, xi, lam), p1 = beam_detail::eval(k, 1, xi, lam);
    const double p2 = beam_detail::eval(k, 2, xi, lam), p3 = beam_detail::eval(k, 3, xi, lam);
    return xi * (p0 * p0 + p2 * p2 - 2 * p1 * p3) + 3 * p0 * p3 - p1 * p2;
  };
  return 0.25 * (F(lam) - F(0));
}

// Sign convention of the header: on x_i = i L / n the first |phi| within 1e-2 (relative) of the max is > 0.
void fix_sign(beam_detail::Coeffs& k, double lam, std::size_t n) {
  double vmax = 0;
  std::vector<double> v(n + 1);
  for (std::size_t i = 0; i <= n; ++i) {
    v[i] = beam_detail::eval(k, 0, lam * static_cast<double>(i) / static_cast<double>(n), lam);
    vmax = std::max(vmax, std::abs(v[i]));
  }
  for (double vi : v)
    if (std::abs(vi) >= (1 - 1e-2) * vmax) {
      if (vi < 0)
        for (double& ki : k) ki = -ki;
      return;
    }
}

class AnalyticModes final : public ModeSet {
 public:
  AnalyticModes(const UniformBeam& b, std::vector<AnalyticMode> modes) : beam_(b), modes_(std::move(modes)) {}
  std::size_t size() const override { return modes_.size(); }
  double length() const override { return beam_.length; }
  double omega(std::size_t k) const override {
    const double lam = modes_.at(k).lam;
    return lam * lam * std::sqrt(beam_.EI / (beam_.rhoA * std::pow(beam_.length, 4)));
  }
  bool rigid(std::size_t k) const override { return modes_.at(k).rigid; }
  double shape(std::size_t k, double x) const override { return derivative(k, 0, x); }
  double slope(std::size_t k, double x) const override { return derivative(k, 1, x); }
  double curvature(std::size_t k, double x) const override { return derivative(k, 2, x); }
  std::string describe() const override {
    std::size_t nr = 0;
    for (const auto& m : modes_) nr += m.rigid;
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "analytic Euler-Bernoulli beam, %s, L %.4g m, EI %.4g N m^2, rhoA %.4g kg/m: %zu rigid + %zu elastic modes",
                  to_string(beam_.ends), beam_.length, beam_.EI, beam_.rhoA, nr, modes_.size() - nr);
    std::string s = buf;
    for (std::size_t k = nr, shown = 0; k < modes_.size() && shown < 4; ++k, ++shown) {
      std::snprintf(buf, sizeof buf, "%s%.4g", shown ? ", " : ", f = ", omega(k) / (2 * std::numbers::pi));
      s += buf;
    }
    return s + (modes_.size() > nr ? " Hz" : "");
  }

 private:
  double derivative(std::size_t k, int n, double x) const {
    const AnalyticMode& m = modes_.at(k);
    if (m.rigid) return n == 0 ? m.p0 + m.p1 * x : n == 1 ? m.p1 : 0.0;
    const double b = m.lam / beam_.length;  // beta (unit: 1/m)
    return m.scale * std::pow(b, n) * beam_detail::eval(m.k, n, b * x, m.lam);
  }

  UniformBeam beam_;
  std::vector<AnalyticMode> modes_;
};

}  // namespace

const char* to_string(BeamEnds e) { return kEndNames[static_cast<int>(e)]; }

bool parse_beam_ends(const std::string& s, BeamEnds& e) {
  for (int i = 0; i < 4; ++i)
    if (s == kEndNames[i]) {
      e = static_cast<BeamEnds>(i);
      return true;
    }
  return false;
}

double beam_root(BeamEnds ends, std::size_t k) {
  const double pi = std::numbers::pi, kd = static_cast<double>(k);
  switch (ends) {
    case BeamEnds::pinned_pinned:
      return (kd + 1) * pi;
    case BeamEnds::clamped_free:  // cos x cosh x = -1: one root in (k pi, (k + 1) pi)
      return bisect_root(-1, kd * pi, (kd + 1) * pi);
    default:  // cos x cosh x = 1: one root in ((k + 1) pi, (k + 2) pi)
      return bisect_root(1, (kd + 1) * pi, (kd + 2) * pi);
  }
}

std::unique_ptr<ModeSet> analytic_beam_modes(const UniformBeam& beam, std::size_t elastic, bool include_rigid) {
  if (!(beam.length > 0 && beam.EI > 0 && beam.rhoA > 0))
    throw std::invalid_argument("analytic_beam_modes: length, EI and rhoA must be positive");
  const double L = beam.length, mass = beam.rhoA * L;
  std::vector<AnalyticMode> modes;
  if (include_rigid && beam.ends == BeamEnds::free_free) {
    AnalyticMode t, r;
    t.rigid = r.rigid = true;
    t.p0 = 1 / std::sqrt(mass);
    r.p1 = std::sqrt(12 / (mass * L * L));
    r.p0 = -r.p1 * L / 2;
    modes.push_back(t);
    modes.push_back(r);
  }
  for (std::size_t j = 0; j < elastic; ++j) {
    AnalyticMode m;
    m.lam = beam_root(beam.ends, j);
    m.k = beam_detail::classic_shape(beam.ends, m.lam);
    fix_sign(m.k, m.lam, 50 * (j + 2));
    // integral rhoA phi^2 dx = rhoA (L / lam) integral phi^2 dxi = 1
    m.scale = 1 / std::sqrt(beam.rhoA * L / m.lam * square_integral(m.k, m.lam));
    modes.push_back(m);
  }
  return std::make_unique<AnalyticModes>(beam, std::move(modes));
}

}  // namespace bagdem
