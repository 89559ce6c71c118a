// The symmetric two-impact motion of the single-ball impact damper (reduce/impact_damper_theory.hpp,
// where the formulas are derived; section numbers below refer to that header).
#include "bagdem/reduce/impact_damper_theory.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace bagdem {
namespace {

constexpr double kPi = std::numbers::pi;

void require_restitution(double e, const char* where) {
  if (!(e > 0 && e < 1))
    throw std::invalid_argument(std::string(where) + ": restitution e = " + std::to_string(e) +
                                " must lie in (0, 1)");
}

// The dimensionless motion at D = d/X: the phase alpha of the stable-candidate root of (2), or
// has_root = false when D > R.
struct Dimensionless {
  bool has_root = false, admissible = false;
  double alpha = 0;
  double spectral_radius = 0;
};

// Section 1: 0 < f(theta) < D between the impacts, f = U (theta - alpha) - sin(theta) + sin(alpha).
// f(alpha) = 0 and f(alpha + pi) = D with f' > 0 at both ends (e > 0), so only interior extremes,
// where cos(theta) = U, can leave the interval. alpha + pi < 3 pi/2, so the candidates are +-acos(U).
bool admissible(double alpha, double U, double D) {
  if (U >= 1) return true;  // f' = U - cos(theta) >= 0: monotone
  const double c = std::acos(U);
  for (double theta : {-c, c}) {
    if (theta <= alpha) continue;
    const double f = U * (theta - alpha) - std::sin(theta) + std::sin(alpha);
    if (!(f > 0 && f < D)) return false;
  }
  return true;
}

Dimensionless solve(double D, double e) {
  const double r = (1 + e) / (1 - e);
  const double R = std::hypot(kPi * r, 2.0), psi = std::atan2(2.0, kPi * r);
  Dimensionless s;
  if (D > R) return s;
  s.has_root = true;
  s.alpha = psi - std::acos(D / R);
  const double U = r * std::cos(s.alpha);
  s.admissible = admissible(s.alpha, U, D);
  // Section 4: lambda^2 - T lambda + e^2 = 0.
  const double T = 2 * e + 0.5 * kPi * (1 - e * e) * std::tan(s.alpha);
  const double disc = 0.25 * T * T - e * e;
  s.spectral_radius = disc < 0 ? e : 0.5 * std::abs(T) + std::sqrt(disc);
  return s;
}

}  // namespace

TwoImpactMotion two_impact_motion(double m, double X, double w, double d, double e) {
  for (double v : {m, X, w, d})
    if (!(v > 0) || !std::isfinite(v))
      throw std::invalid_argument("two_impact_motion: m, X, w, d must be finite and > 0 (got m = " + std::to_string(m) +
                                  ", X = " + std::to_string(X) + ", w = " + std::to_string(w) +
                                  ", d = " + std::to_string(d) + ")");
  require_restitution(e, "two_impact_motion");
  const Dimensionless s = solve(d / X, e);
  TwoImpactMotion out;
  if (!s.has_root) return out;
  const double r = (1 + e) / (1 - e), wall_speed = X * w * std::cos(s.alpha);
  out.exists = s.admissible;
  out.max_eigenvalue = s.spectral_radius;
  out.stable = out.exists && s.spectral_radius < 1;
  out.phase = s.alpha;
  out.study_phase = s.alpha + kPi / 2;
  out.ball_speed = r * wall_speed;                        // (1)
  out.impact_speed = out.ball_speed + wall_speed;         // = 2 X w cos(alpha)/(1 - e)
  out.energy_per_impact = 2 * m * out.ball_speed * wall_speed;  // impulse 2 m u times the wall's speed
  out.energy_per_cycle = 2 * out.energy_per_impact;
  out.equivalent_damping = out.energy_per_cycle / (kPi * w * X * X);
  out.effective_mass = -(4 / kPi) * m * r * std::sin(s.alpha) * std::cos(s.alpha);
  return out;
}

ClearanceRatioRange stable_clearance_ratio(double e) {
  require_restitution(e, "stable_clearance_ratio");
  const double r = (1 + e) / (1 - e);
  ClearanceRatioRange range;
  range.hi = std::hypot(kPi * r, 2.0);
  range.lo = r * (kPi * kPi - 4) / std::sqrt(kPi * kPi + 4 * r * r);
  if (solve(range.lo, e).admissible) return range;
  // Small e: the wall the ball left catches it again below some D (admissibility holds above it up
  // to R for every e tried, 1e-6 to 0.99), so bisect between D_min and R.
  double bad = range.lo, good = range.hi;
  if (!solve(good, e).admissible) return {0, 0};  // never met; refuse to guess
  for (int k = 0; k < 100 && good - bad > 1e-14 * good; ++k) {
    const double mid = 0.5 * (bad + good);
    (solve(mid, e).admissible ? good : bad) = mid;
  }
  range.lo = good;
  return range;
}

}  // namespace bagdem
