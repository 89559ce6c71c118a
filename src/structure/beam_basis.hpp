// Internal to src/structure: the numerically stable solution basis of phi'''' = beta^4 phi shared
// by the analytic modes (beam_analytic.cpp) and the point-mass frequency equation
// (beam_lumped_mass.cpp).
//
// In xi = beta x on a stretch of length lam = beta l, the general solution is
//   phi = a cos xi + b sin xi + c e^(-xi) + d e^(-(lam - xi)),
// the usual cosh/sinh pair rewritten as exponentials decaying from either end. Every basis function
// is bounded by 1 on [0, lam], so no term is large and nothing cancels, at any lam (with cosh and
// sinh, terms of size e^lam cancel to O(1): all digits are gone by lam ~ 37).
#pragma once
#include <array>
#include <cmath>

#include "bagdem/structure/modes.hpp"

namespace bagdem::beam_detail {

using Coeffs = std::array<double, 4>;  // a, b, c, d above

// The four basis functions' derivatives of order n (0..3) at xi.
inline Coeffs basis(int n, double xi, double lam) {
  const double c = std::cos(xi), s = std::sin(xi);
  static constexpr double cos_d[4][2] = {{1, 0}, {0, -1}, {-1, 0}, {0, 1}};  // d^n cos = p cos + q sin
  static constexpr double sin_d[4][2] = {{0, 1}, {1, 0}, {0, -1}, {-1, 0}};
  return {cos_d[n][0] * c + cos_d[n][1] * s, sin_d[n][0] * c + sin_d[n][1] * s, (n % 2 ? -1.0 : 1.0) * std::exp(-xi),
          std::exp(xi - lam)};
}

// d^n phi / d xi^n at xi for the coefficients k.
inline double eval(const Coeffs& k, int n, double xi, double lam) {
  const Coeffs b = basis(n, xi, lam);
  return k[0] * b[0] + k[1] * b[1] + k[2] * b[2] + k[3] * b[3];
}

enum class End { free, pinned, clamped };
inline End left_end(BeamEnds e) {
  return e == BeamEnds::free_free ? End::free : e == BeamEnds::pinned_pinned ? End::pinned : End::clamped;
}
inline End right_end(BeamEnds e) {
  return e == BeamEnds::clamped_clamped ? End::clamped : e == BeamEnds::pinned_pinned ? End::pinned : End::free;
}
// Derivative orders that vanish at an end: free phi'' = phi''' = 0, pinned phi = phi'' = 0,
// clamped phi = phi' = 0.
inline std::array<int, 2> end_orders(End e) {
  return e == End::free ? std::array<int, 2>{2, 3} : e == End::pinned ? std::array<int, 2>{0, 2} : std::array<int, 2>{0, 1};
}

// The classic mode shape at the root lam = beam_root(ends, k), in the basis above (Blevins 1979,
// table 8-1; Rao 2007, ch. 11):
//   free-free        cosh + cos - sigma (sinh + sin),  sigma = (cosh L - cos L) / (sinh L - sin L)
//   clamped-clamped  cosh - cos - sigma (sinh - sin),  same sigma
//   clamped-free     cosh - cos - sigma (sinh - sin),  sigma = (sinh L - sin L) / (cosh L + cos L)
//   pinned-pinned    sin
// (arguments beta x, beta L). With e = e^(-lam): cosh xi - sigma sinh xi
// = (1 + sigma)/2 e^(-xi) + P/2 e^(-(lam - xi)), P = (1 - sigma) e^lam, and sigma and P in closed
// form in e, without cancellation:
//   ff, cc: sigma = (1 + e^2 - 2 e cos lam) / D,  P = 2 (cos lam - sin lam - e) / D,  D = 1 - e^2 - 2 e sin lam
//   cf:     sigma = (1 - e^2 - 2 e sin lam) / D,  P = 2 (cos lam + sin lam + e) / D,  D = 1 + e^2 + 2 e cos lam
inline Coeffs classic_shape(BeamEnds ends, double lam) {
  if (ends == BeamEnds::pinned_pinned) return {0, 1, 0, 0};
  const double e = std::exp(-lam), c = std::cos(lam), s = std::sin(lam);
  double sigma, P;
  if (ends == BeamEnds::clamped_free) {
    const double D = 1 + e * e + 2 * e * c;
    sigma = (1 - e * e - 2 * e * s) / D;
    P = 2 * (c + s + e) / D;
  } else {
    const double D = 1 - e * e - 2 * e * s;
    sigma = (1 + e * e - 2 * e * c) / D;
    P = 2 * (c - s - e) / D;
  }
  const double trig = ends == BeamEnds::free_free ? 1.0 : -1.0;  // + (cos - sigma sin) or - (cos - sigma sin)
  return {trig, -trig * sigma, 0.5 * (1 + sigma), 0.5 * P};
}

}  // namespace bagdem::beam_detail
