// Exact natural frequencies of a uniform Euler-Bernoulli beam carrying a point mass; see
// include/bagdem/structure/modes.hpp.
//
// In xi = beta x, lam = beta L, the beam is split at the mass, s = x_m / L: the left stretch has
// length lam_a = s lam, the right lam_b = (1 - s) lam, each with the stable general solution of
// src/structure/beam_basis.hpp (coefficients c0..c3 left, c4..c7 right, right stretch in its own
// coordinate from the mass). Eight conditions: two at each end, continuity of phi, phi', phi'' at
// the mass, and the shear jump of the mass's inertia force,
//   EI [w'''] = m omega^2 w(x_m)  <=>  [phi_xixixi] = mu lam phi(x_m),  mu = m / (rhoA L)
// (integrate EI w'''' + rhoA w_tt = -m w_tt(x_m) delta(x - x_m) across x_m).
// With D0(lam) the bare beam's 8x8 matrix (no mass term) the loaded one is D0 + rank one, so
//   det D = det D0 * h(lam),  h = 1 - mu lam w_hat(lam),  D0 c = e_shear,  w_hat = phi(x_m)[c]
// (matrix determinant lemma). h = 1 - m omega^2 alpha(omega), alpha the point receptance, and
// h / (m omega^2) = 1/(m omega^2) - sum phi_k(x_m)^2 / (omega_k^2 - omega^2) falls monotonically
// from +inf to -inf between consecutive bare frequencies with phi_k(x_m) != 0 (its poles): one root
// in each such interval (interlacing), found by bisection that never evaluates the ends. A bare
// mode with a node at the mass (|phi_k(x_m)| < 1e-9 of the classic shape, max ~1) is no pole and is
// itself a loaded mode. For a free-free beam the two rigid modes stay at omega = 0.
// clang-format off
#include <Eigen/Dense>
// clang-format on
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "bagdem/structure/modes.hpp"
#include "beam_basis.hpp"

namespace bagdem {

namespace {

using namespace beam_detail;

// h(lam) above, for the mass at s = x_m / L with mass ratio mu.
double secular(BeamEnds ends, double s, double mu, double lam) {
  const double la = s * lam, lb = (1 - s) * lam;
  Eigen::Matrix<double, 8, 8> D = Eigen::Matrix<double, 8, 8>::Zero();
  // Row `row` += sign * (order-n derivatives of the stretch's basis at xi), columns col..col+3.
  auto put = [&D](int row, int col, int n, double xi, double len, double sign) {
    const Coeffs b = basis(n, xi, len);
    for (int i = 0; i < 4; ++i) D(row, col + i) += sign * b[static_cast<std::size_t>(i)];
  };
  const auto lo = end_orders(left_end(ends)), hi = end_orders(right_end(ends));
  for (int j = 0; j < 2; ++j) {
    put(j, 0, lo[static_cast<std::size_t>(j)], 0, la, 1);
    put(2 + j, 4, hi[static_cast<std::size_t>(j)], lb, lb, 1);
  }
  for (int n = 0; n < 3; ++n) {  // continuity of phi, phi', phi''
    put(4 + n, 0, n, la, la, 1);
    put(4 + n, 4, n, 0, lb, -1);
  }
  put(7, 4, 3, 0, lb, 1);  // [phi'''] (unit jump on the right-hand side)
  put(7, 0, 3, la, la, -1);
  Eigen::Matrix<double, 8, 1> rhs = Eigen::Matrix<double, 8, 1>::Zero();
  rhs(7) = 1;
  const Eigen::Matrix<double, 8, 1> c = D.fullPivLu().solve(rhs);
  const Coeffs b = basis(0, la, la);
  const double w_hat = b[0] * c(0) + b[1] * c(1) + b[2] * c(2) + b[3] * c(3);
  return 1 - mu * lam * w_hat;
}

// The root of h in (lo, hi), h > 0 just above lo and < 0 just below hi; to the last bit.
double bisect(BeamEnds ends, double s, double mu, double lo, double hi) {
  for (;;) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) return mid;
    (secular(ends, s, mu, mid) > 0 ? lo : hi) = mid;
  }
}

}  // namespace

std::vector<double> lumped_mass_frequencies(const UniformBeam& beam, double x_m, double m, std::size_t count) {
  if (!(beam.length > 0 && beam.EI > 0 && beam.rhoA > 0))
    throw std::invalid_argument("lumped_mass_frequencies: length, EI and rhoA must be positive");
  if (!(x_m >= 0 && x_m <= beam.length && m >= 0))
    throw std::invalid_argument("lumped_mass_frequencies: the mass must be >= 0 and lie on the beam");
  const double L = beam.length, s = x_m / L, mu = m / (beam.rhoA * L);
  const double w0 = std::sqrt(beam.EI / (beam.rhoA * std::pow(L, 4)));  // omega = lam^2 w0
  // A mass on a support (or no mass) changes nothing.
  const bool bare = mu == 0 || (s == 0 && left_end(beam.ends) != End::free) || (s == 1 && right_end(beam.ends) != End::free);

  const std::size_t rigid = beam.ends == BeamEnds::free_free ? std::min<std::size_t>(2, count) : 0;
  std::vector<double> lam;  // loaded roots beta L found so far
  double pole = 0;          // last bare root with phi(x_m) != 0: every loaded root below it is known
  for (std::size_t k = 0;; ++k) {
    const double lk = beam_root(beam.ends, k);
    if (bare || std::abs(eval(classic_shape(beam.ends, lk), 0, s * lk, lk)) < 1e-9) {
      lam.push_back(lk);
      if (bare) pole = lk;
    } else {
      lam.push_back(bisect(beam.ends, s, mu, pole, lk));
      pole = lk;
    }
    if (static_cast<std::size_t>(std::count_if(lam.begin(), lam.end(), [pole](double l) { return l <= pole; })) >= count - rigid)
      break;
  }
  std::sort(lam.begin(), lam.end());
  std::vector<double> omega(rigid, 0.0);
  for (std::size_t j = 0; j + rigid < count; ++j) omega.push_back(lam[j] * lam[j] * w0);
  return omega;
}

}  // namespace bagdem
