// What every primary kind shares (structure/primary.hpp): the mass matrix with the cavity's mass,
// the load fit, and the bare structure's steady state and receptance.
#include "bagdem/structure/primary.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace bagdem {

void finish_primary(Primary& p, const std::vector<Eigen::VectorXd>& shapes, double l) {
  const Eigen::Index n = p.stiffness.size();
  if (p.mass.rows() != n) p.mass = Eigen::MatrixXd::Identity(n, n);
  p.mass += p.cavity_mass * p.at_cavity * p.at_cavity.transpose();
  p.mass_inverse = p.mass.inverse();
  // shapes: phi at x_b - l, x_b, x_b + l. The quadratic through them, c0 + c1 s + c2 s^2.
  p.load_fit.resize(n, 3);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double lo = shapes[0][k], mid = shapes[1][k], hi = shapes[2][k];
    p.load_fit(k, 0) = mid;
    p.load_fit(k, 1) = l > 0 ? (hi - lo) / (2 * l) : 0.0;
    p.load_fit(k, 2) = l > 0 ? (hi - 2 * mid + lo) / (2 * l * l) : 0.0;
  }
}

double Primary::omega_max() const {
  // Largest eigenvalue of M^-1 K (K diagonal, M symmetric positive definite).
  const Eigen::MatrixXd K = stiffness.asDiagonal();
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, mass, Eigen::EigenvaluesOnly);
  return std::sqrt(std::max(0.0, es.eigenvalues().maxCoeff()));
}

namespace {
Eigen::MatrixXcd dynamic_stiffness(const Primary& p, double w) {
  using C = std::complex<double>;
  const Eigen::Index n = p.stiffness.size();
  Eigen::MatrixXcd D = (-w * w) * p.mass.cast<C>();
  for (Eigen::Index k = 0; k < n; ++k) D(k, k) += C(p.stiffness[k], w * p.damping[k]);
  return D;
}
Eigen::VectorXcd solve_bare(const Primary& p, double w, const Eigen::VectorXd& f) {
  return dynamic_stiffness(p, w).partialPivLu().solve(f.cast<std::complex<double>>());
}
}  // namespace

std::complex<double> Primary::bare_receptance(double w) const {
  return at_response.cast<std::complex<double>>().dot(solve_bare(*this, w, at_force));
}

// f = F sin(w t) = Re(-i F e^{iwt}): q(t) = Re(Q e^{iwt}) with Q = D^-1 (-i F phi_f); at t = 0,
// q = Re Q and v = Re(i w Q).
void Primary::bare_steady_state(double F, double w, Eigen::VectorXd& q, Eigen::VectorXd& v) const {
  const Eigen::VectorXcd Q = solve_bare(*this, w, at_force) * std::complex<double>(0, -F);
  q = Q.real();
  v = (Q * std::complex<double>(0, w)).real();
}

// (K - w^2 M + i w C + Z phi_b phi_b^T) Q = -i F phi_f: the contents' force on the cavity is
// Re(-Z U e^{iwt}), U = phi_b . Q.
Eigen::VectorXcd Primary::steady_amplitudes(double F, double w, std::complex<double> Z) const {
  const Eigen::VectorXcd b = at_cavity.cast<std::complex<double>>();
  const Eigen::MatrixXcd D = dynamic_stiffness(*this, w) + Z * b * b.transpose();
  return D.partialPivLu().solve(at_force.cast<std::complex<double>>()) * std::complex<double>(0, -F);
}

void Primary::carry_cavity(double m, const Eigen::VectorXd& at) {
  mass += m * at * at.transpose();
  mass_inverse = mass.inverse();
}

Eigen::VectorXcd Primary::steady_amplitudes(double F, double w, const std::vector<Eigen::VectorXd>& at,
                                            const std::vector<std::complex<double>>& Z) const {
  Eigen::MatrixXcd D = dynamic_stiffness(*this, w);
  for (std::size_t k = 0; k < at.size(); ++k) {
    const Eigen::VectorXcd b = at[k].cast<std::complex<double>>();
    D += Z[k] * b * b.transpose();
  }
  return D.partialPivLu().solve(at_force.cast<std::complex<double>>()) * std::complex<double>(0, -F);
}

double Primary::bare_cavity_amplitude_max(double F, const std::vector<double>& f, double& w_at) const {
  double best = 0;
  w_at = 0;
  auto consider = [&](double hz) {
    const double w = 2 * std::numbers::pi * hz, a = bare_cavity_amplitude(F, w);
    if (a > best) best = a, w_at = w;
  };
  if (f.empty()) return 0.0;
  const auto [lo, hi] = std::minmax_element(f.begin(), f.end());
  for (double hz : f) consider(hz);
  const int n = 4000;
  for (int k = 0; k <= n && *hi > *lo; ++k) consider(*lo * std::pow(*hi / *lo, static_cast<double>(k) / n));
  return best;
}

std::vector<double> Primary::bare_frequencies() const {
  const Eigen::MatrixXd K = stiffness.asDiagonal();
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, mass, Eigen::EigenvaluesOnly);
  std::vector<double> f;
  for (Eigen::Index k = 0; k < es.eigenvalues().size(); ++k)
    f.push_back(std::sqrt(std::max(0.0, es.eigenvalues()[k])) / (2 * std::numbers::pi));
  return f;
}

double Primary::bare_cavity_amplitude(double F, double w) const {
  Eigen::VectorXd q, v;
  bare_steady_state(F, w, q, v);
  return std::hypot(at_cavity.dot(q), at_cavity.dot(v) / w);
}

std::size_t Primary::nearest_elastic_mode(double f, std::size_t* number) const {
  std::size_t best = size(), count = 0;
  for (std::size_t k = 0; k < size(); ++k) {
    if (rigid_body[k]) continue;
    ++count;
    if (best == size() || std::abs(std::log(f / natural_frequency[k])) < std::abs(std::log(f / natural_frequency[best]))) {
      best = k;
      if (number) *number = count;
    }
  }
  return best;
}

std::size_t Primary::elastic_mode_number(std::size_t k) const {
  if (rigid_body[k]) return 0;
  std::size_t n = 0;
  for (std::size_t j = 0; j <= k; ++j) n += rigid_body[j] ? 0 : 1;
  return n;
}

std::vector<std::size_t> Primary::evaluated_modes(double lo, double hi) const {
  if (stepped_sine && !stepped_sine->modes.empty()) return stepped_sine->modes;
  std::vector<std::size_t> modes;
  for (std::size_t k = 0; k < size(); ++k)
    if (!rigid_body[k] && natural_frequency[k] >= lo && natural_frequency[k] <= hi) modes.push_back(k);
  return modes;
}

}  // namespace bagdem
