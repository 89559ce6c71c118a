// The harmonic balance of several dampers on one structure (reduce/predict.hpp, predict_at with
// MappedDamper): n equations in the cavities' log-amplitudes, solved by Newton's method.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "bagdem/reduce/predict.hpp"

namespace bagdem {

namespace {

constexpr int kScales = 12;  // the bare amplitudes times 2^12 ... 2^-12: starts
constexpr int kWalk = 12;    // starts along every map's range at one Gamma

// The balance at one frequency, in y = log X (one per damper).
class Balance {
 public:
  Balance(const Primary& p, const std::vector<MappedDamper>& d, double F, double f, int m_sign, int c_sign)
      : p_(p), d_(d), F_(F), f_(f), w_(2 * std::numbers::pi * f), m_sign_(m_sign), c_sign_(c_sign) {
    for (const MappedDamper& x : d) {
      const auto [a, b] = x.map->amplitude_range(f);
      lo_.push_back(std::log(a * (1 + 1e-12))), hi_.push_back(std::log(b * (1 - 1e-12)));  // a hair inside, as predict_at's
      at_.push_back(x.at_cavity);
    }
    Z_.resize(d.size());
  }
  std::size_t size() const { return d_.size(); }
  double lo(std::size_t k) const { return lo_[k]; }
  double hi(std::size_t k) const { return hi_[k]; }

  // The structure's amplitudes with each damper's impedance read at X = e^y; nullopt when a map
  // has no figure there (`gap` then names the damper).
  std::optional<Eigen::VectorXcd> amplitudes(const Eigen::VectorXd& y, std::size_t* gap = nullptr) const {
    for (std::size_t k = 0; k < d_.size(); ++k) {
      const auto mc = d_[k].map->at(std::exp(y[static_cast<Eigen::Index>(k)]), f_, m_sign_, c_sign_);
      if (!mc) {
        if (gap) *gap = k;
        return std::nullopt;
      }
      Z_[k] = std::complex<double>(-w_ * w_ * mc->first, w_ * mc->second);
    }
    return p_.steady_amplitudes(F_, w_, at_, Z_);
  }
  // r_k = log |U_k| - y_k: zero at a steady solution.
  std::optional<Eigen::VectorXd> residual(const Eigen::VectorXd& y, std::size_t* gap = nullptr) const {
    const auto Q = amplitudes(y, gap);
    if (!Q) return std::nullopt;
    Eigen::VectorXd r(y.size());
    for (std::size_t k = 0; k < d_.size(); ++k) {
      const auto i = static_cast<Eigen::Index>(k);
      r[i] = std::log(std::abs(at_[k].cast<std::complex<double>>().dot(*Q))) - y[i];
    }
    return r;
  }
  // The amplitudes held inside every map's range.
  Eigen::VectorXd inside(Eigen::VectorXd y) const {
    for (std::size_t k = 0; k < d_.size(); ++k) {
      const auto i = static_cast<Eigen::Index>(k);
      y[i] = std::clamp(std::isfinite(y[i]) ? y[i] : lo_[k], lo_[k], hi_[k]);
    }
    return y;
  }

 private:
  const Primary& p_;
  const std::vector<MappedDamper>& d_;
  double F_, f_, w_;
  int m_sign_, c_sign_;
  std::vector<double> lo_, hi_;
  std::vector<Eigen::VectorXd> at_;
  mutable std::vector<std::complex<double>> Z_;
};

// Where a start that found no root ended: against a map's upper end with the response above it
// ("above"), its lower end below it ("below"), or among cells without figures ("gap").
struct Stuck {
  std::string why;
  std::size_t damper = 0;
};

// Newton's method from y0: the root, or nullopt (and where it stuck).
std::optional<Eigen::VectorXd> newton(const Balance& b, Eigen::VectorXd y, Stuck& stuck) {
  constexpr double kTolerance = 1e-11, kDifference = 1e-7;
  const auto n = static_cast<Eigen::Index>(b.size());
  y = b.inside(y);
  std::optional<Eigen::VectorXd> r = b.residual(y, &stuck.damper);
  if (!r) return stuck.why = "gap", std::nullopt;
  for (int it = 0; it < 60; ++it) {
    if (r->lpNorm<Eigen::Infinity>() < kTolerance) return y;
    Eigen::MatrixXd J(n, n);
    for (Eigen::Index j = 0; j < n; ++j) {  // a forward difference, backward at a range's upper end
      Eigen::VectorXd z = y;
      const double h = z[j] + kDifference > b.hi(static_cast<std::size_t>(j)) ? -kDifference : kDifference;
      z[j] += h;
      const auto rz = b.residual(z);
      if (!rz) return stuck.why = "gap", stuck.damper = static_cast<std::size_t>(j), std::nullopt;
      J.col(j) = (*rz - *r) / h;
    }
    const Eigen::VectorXd step = J.partialPivLu().solve(-*r);
    if (!step.allFinite()) return stuck.why = "unsolved", std::nullopt;
    // The longest step (halved) that lowers the largest residual, held inside the maps.
    bool lowered = false;
    for (double s = 1; s > 1e-4; s *= 0.5) {
      const Eigen::VectorXd z = b.inside(y + s * step);
      const auto rz = b.residual(z);
      if (rz && rz->lpNorm<Eigen::Infinity>() < r->lpNorm<Eigen::Infinity>()) {
        y = z, r = rz, lowered = true;
        break;
      }
    }
    if (!lowered) {
      // Against an end of a map's range with the balance pushing beyond it: the response is outside.
      for (std::size_t k = 0; k < b.size(); ++k) {
        const auto i = static_cast<Eigen::Index>(k);
        if (y[i] >= b.hi(k) - 1e-9 && (*r)[i] > 0) return stuck = {"above", k}, std::nullopt;
        if (y[i] <= b.lo(k) + 1e-9 && (*r)[i] < 0) return stuck = {"below", k}, std::nullopt;
      }
      return stuck.why = "unsolved", std::nullopt;
    }
  }
  if (r->lpNorm<Eigen::Infinity>() < kTolerance) return y;
  return stuck.why = "unsolved", std::nullopt;
}

}  // namespace

FrequencyPrediction predict_at(const Primary& p, const std::vector<MappedDamper>& dampers, double F, double f, int m_sign, int c_sign,
                               const std::vector<HarmonicSolution>* near) {
  FrequencyPrediction out;
  out.frequency = f;
  for (std::size_t k = 0; k < dampers.size(); ++k)
    if (!dampers[k].map->covers(f)) {
      out.outside = "band", out.outside_damper = k;
      return out;
    }
  const Balance b(p, dampers, F, f, m_sign, c_sign);
  const auto n = static_cast<Eigen::Index>(dampers.size());
  std::vector<Eigen::VectorXd> starts;
  if (near)
    for (const HarmonicSolution& h : *near) {
      Eigen::VectorXd y(n);
      for (Eigen::Index k = 0; k < n; ++k) y[k] = std::log(h.cavities[static_cast<std::size_t>(k)]);
      starts.push_back(y);
    }
  const Eigen::VectorXcd bare = p.steady_amplitudes(F, 2 * std::numbers::pi * f, std::complex<double>(0));
  Eigen::VectorXd y_bare(n);
  for (Eigen::Index k = 0; k < n; ++k) y_bare[k] = std::log(std::abs(dampers[static_cast<std::size_t>(k)].at_cavity.cast<std::complex<double>>().dot(bare)));
  // The bare amplitudes scaled over the maps' whole range (a damper's mass may move the resonance, so
  // the damped response can lie far above the bare one as well as below), and every map's range
  // walked at one Gamma (where a damper near a node makes the bare shape a poor guide).
  for (int s = kScales; s >= -kScales; --s) starts.push_back(b.inside(y_bare + Eigen::VectorXd::Constant(n, s * std::log(2.0))));
  for (int s = 0; s < kWalk; ++s) {
    Eigen::VectorXd y(n);
    for (Eigen::Index k = 0; k < n; ++k) {
      const auto d = static_cast<std::size_t>(k);
      y[k] = b.lo(d) + (b.hi(d) - b.lo(d)) * (s + 0.5) / kWalk;
    }
    starts.push_back(y);
  }
  std::vector<Stuck> stuck;
  std::vector<Eigen::VectorXd> roots, tried;
  for (const Eigen::VectorXd& y0 : starts) {
    // A start already tried (the scaled bare amplitudes held at a map's end) is not tried again.
    if (std::any_of(tried.begin(), tried.end(), [&](const Eigen::VectorXd& t) { return (t - y0).lpNorm<Eigen::Infinity>() < 1e-9; })) continue;
    tried.push_back(y0);
    Stuck why;
    const auto y = newton(b, y0, why);
    if (!y) {
      if (!why.why.empty()) stuck.push_back(why);
      continue;
    }
    const bool known = std::any_of(roots.begin(), roots.end(), [&](const Eigen::VectorXd& r) { return (r - *y).lpNorm<Eigen::Infinity>() < 1e-6; });
    if (!known) roots.push_back(*y);
  }
  std::sort(roots.begin(), roots.end(), [](const Eigen::VectorXd& a, const Eigen::VectorXd& c) { return a[0] < c[0]; });
  for (const Eigen::VectorXd& y : roots) {
    const Eigen::VectorXcd Q = *b.amplitudes(y);
    HarmonicSolution h;
    for (Eigen::Index k = 0; k < n; ++k) h.cavities.push_back(std::exp(y[k]));
    h.cavity_amplitude = h.cavities[0];
    h.response = std::abs(p.at_response.cast<std::complex<double>>().dot(Q));
    out.solutions.push_back(std::move(h));
  }
  if (out.solutions.empty()) {
    out.outside = "unsolved";
    for (const char* why : {"above", "below", "gap", "unsolved"}) {  // the most telling reason any start met
      const auto it = std::find_if(stuck.begin(), stuck.end(), [&](const Stuck& s) { return s.why == why; });
      if (it != stuck.end()) {
        out.outside = it->why, out.outside_damper = it->damper;
        break;
      }
    }
  }
  return out;
}

}  // namespace bagdem
