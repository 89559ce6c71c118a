// Finite-element modes and static deflection of a stepped Euler-Bernoulli beam with point masses;
// see include/bagdem/structure/modes.hpp.
//
// Element of length h, nodal unknowns (w1, theta1, w2, theta2), cubic Hermite interpolation
//   w(t) = N1 w1 + N2 theta1 + N3 w2 + N4 theta2,  t = (x - x1) / h,
//   N1 = 1 - 3t^2 + 2t^3, N2 = h (t - 2t^2 + t^3), N3 = 3t^2 - 2t^3, N4 = h (t^3 - t^2),
// gives the stiffness integral EI w''^2 and the consistent mass integral rhoA w^2 as the standard
// matrices (Przemieniecki 1968, ch. 5 and ch. 11):
//   K = EI/h^3 [12 6h -12 6h; 6h 4h^2 -6h 2h^2; -12 -6h 12 -6h; 6h 2h^2 -6h 4h^2]
//   M = rhoA h/420 [156 22h 54 -13h; 22h 4h^2 13h -3h^2; 54 13h 156 -22h; -13h -3h^2 -22h 4h^2].
// A point mass adds m to its node's w diagonal and J to its theta diagonal. Supports remove w
// (pinned) or w and theta (clamped) from the system.
// clang-format off
#include <Eigen/Dense>
// clang-format on
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "bagdem/structure/modes.hpp"

namespace bagdem {

namespace {

struct Mesh {
  std::vector<double> x;         // nodes (unit: m)
  std::vector<double> EI, rhoA;  // per element (unit: N m^2, kg/m)
};

void validate(const FeBeam& b) {
  if (!(b.length > 0)) throw std::invalid_argument("FE beam: length must be positive");
  if (b.elements == 0) throw std::invalid_argument("FE beam: elements must be at least 1");
  if (b.segments.empty()) throw std::invalid_argument("FE beam: no segments");
  for (const BeamSegment& s : b.segments)
    if (!(s.x1 > s.x0 && s.EI > 0 && s.rhoA > 0))
      throw std::invalid_argument("FE beam: a segment needs x1 > x0, EI > 0 and rhoA > 0");
  for (const LumpedMass& m : b.masses)
    if (!(m.x >= 0 && m.x <= b.length && m.mass >= 0 && m.inertia >= 0))
      throw std::invalid_argument("FE beam: a lumped mass must lie in [0, L] with mass, inertia >= 0");
}

// Nodes uniform within each stretch between breakpoints (0, L, segment ends, masses, `extra`),
// about elements * stretch / L elements per stretch (at least one).
Mesh build_mesh(const FeBeam& b, const std::vector<double>& extra) {
  validate(b);
  const double L = b.length;
  std::vector<double> cuts{0, L};
  for (const BeamSegment& s : b.segments)
    for (double x : {s.x0, s.x1})
      if (x > 0 && x < L) cuts.push_back(x);
  for (const LumpedMass& m : b.masses) cuts.push_back(m.x);
  for (double x : extra) cuts.push_back(x);
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end(), [L](double a, double c) { return c - a <= 1e-12 * L; }), cuts.end());
  cuts.back() = L;

  Mesh mesh;
  mesh.x.push_back(0);
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double a = cuts[i], c = cuts[i + 1];
    const auto n = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(static_cast<double>(b.elements) * (c - a) / L)));
    for (std::size_t j = 1; j <= n; ++j)
      mesh.x.push_back(j == n ? c : a + (c - a) * static_cast<double>(j) / static_cast<double>(n));
  }
  for (std::size_t e = 0; e + 1 < mesh.x.size(); ++e) {
    const double mid = 0.5 * (mesh.x[e] + mesh.x[e + 1]);
    const auto s =
        std::find_if(b.segments.begin(), b.segments.end(), [mid](const BeamSegment& g) { return g.x0 <= mid && mid <= g.x1; });
    if (s == b.segments.end()) throw std::invalid_argument("FE beam: no segment covers x = " + std::to_string(mid) + " m");
    mesh.EI.push_back(s->EI);
    mesh.rhoA.push_back(s->rhoA);
  }
  return mesh;
}

std::size_t node_at(const Mesh& mesh, double x) {
  const auto it =
      std::min_element(mesh.x.begin(), mesh.x.end(), [x](double a, double c) { return std::abs(a - x) < std::abs(c - x); });
  return static_cast<std::size_t>(it - mesh.x.begin());
}

// Global K and M over all 2 (nodes) unknowns (w_i at 2i, theta_i at 2i + 1), in the scalar type T
// (long double for the static solve).
template <class T>
void assemble(const Mesh& mesh, const FeBeam& b, Eigen::Matrix<T, -1, -1>& K, Eigen::Matrix<T, -1, -1>& M) {
  const Eigen::Index n = 2 * static_cast<Eigen::Index>(mesh.x.size());
  K.setZero(n, n);
  M.setZero(n, n);
  for (std::size_t e = 0; e < mesh.EI.size(); ++e) {
    const T h = static_cast<T>(mesh.x[e + 1]) - static_cast<T>(mesh.x[e]);
    Eigen::Matrix<T, 4, 4> k, m;
    k << 12, 6 * h, -12, 6 * h, 6 * h, 4 * h * h, -6 * h, 2 * h * h, -12, -6 * h, 12, -6 * h, 6 * h, 2 * h * h, -6 * h, 4 * h * h;
    m << 156, 22 * h, 54, -13 * h, 22 * h, 4 * h * h, 13 * h, -3 * h * h, 54, 13 * h, 156, -22 * h, -13 * h, -3 * h * h, -22 * h,
        4 * h * h;
    const auto i = 2 * static_cast<Eigen::Index>(e);
    K.template block<4, 4>(i, i) += static_cast<T>(mesh.EI[e]) / (h * h * h) * k;
    M.template block<4, 4>(i, i) += static_cast<T>(mesh.rhoA[e]) * h / 420 * m;
  }
  for (const LumpedMass& lm : b.masses) {
    const auto i = 2 * static_cast<Eigen::Index>(node_at(mesh, lm.x));
    M(i, i) += static_cast<T>(lm.mass);
    M(i + 1, i + 1) += static_cast<T>(lm.inertia);
  }
}

// Unknowns left free by the supports.
std::vector<Eigen::Index> free_dofs(BeamEnds ends, std::size_t nodes) {
  const auto n = 2 * static_cast<Eigen::Index>(nodes);
  std::vector<bool> fixed(static_cast<std::size_t>(n), false);
  auto fix = [&](Eigen::Index i) { fixed[static_cast<std::size_t>(i)] = true; };
  if (ends == BeamEnds::clamped_free || ends == BeamEnds::clamped_clamped) fix(0), fix(1);
  if (ends == BeamEnds::pinned_pinned) fix(0), fix(n - 2);
  if (ends == BeamEnds::clamped_clamped) fix(n - 2), fix(n - 1);
  std::vector<Eigen::Index> dofs;
  for (Eigen::Index i = 0; i < n; ++i)
    if (!fixed[static_cast<std::size_t>(i)]) dofs.push_back(i);
  return dofs;
}

template <class T>
Eigen::Matrix<T, -1, -1> restrict(const Eigen::Matrix<T, -1, -1>& A, const std::vector<Eigen::Index>& dofs) {
  const auto n = static_cast<Eigen::Index>(dofs.size());
  Eigen::Matrix<T, -1, -1> R(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) R(i, j) = A(dofs[static_cast<std::size_t>(i)], dofs[static_cast<std::size_t>(j)]);
  return R;
}

// Value (n = 0), slope (1) or curvature (2) at x of the Hermite interpolant of nodal values u.
double interpolate(const std::vector<double>& nodes, const Eigen::VectorXd& u, int n, double x) {
  const auto ne = static_cast<std::ptrdiff_t>(nodes.size()) - 1;
  const std::ptrdiff_t e =
      std::clamp<std::ptrdiff_t>(std::upper_bound(nodes.begin(), nodes.end(), x) - nodes.begin() - 1, 0, ne - 1);
  const double h = nodes[e + 1] - nodes[e], t = (x - nodes[e]) / h;
  std::array<double, 4> N;
  if (n == 0)
    N = {1 - 3 * t * t + 2 * t * t * t, h * (t - 2 * t * t + t * t * t), 3 * t * t - 2 * t * t * t, h * (t * t * t - t * t)};
  else if (n == 1)
    N = {(6 * t * t - 6 * t) / h, 1 - 4 * t + 3 * t * t, (6 * t - 6 * t * t) / h, 3 * t * t - 2 * t};
  else
    N = {(12 * t - 6) / (h * h), (6 * t - 4) / h, (6 - 12 * t) / (h * h), (6 * t - 2) / h};
  const Eigen::Index i = 2 * e;
  return N[0] * u(i) + N[1] * u(i + 1) + N[2] * u(i + 2) + N[3] * u(i + 3);
}

class FeModes final : public ModeSet {
 public:
  FeModes(std::vector<double> nodes, std::vector<Eigen::VectorXd> u, std::vector<double> omega, std::size_t rigid,
          std::string text)
      : nodes_(std::move(nodes)), u_(std::move(u)), omega_(std::move(omega)), rigid_(rigid), text_(std::move(text)) {}
  std::size_t size() const override { return u_.size(); }
  double length() const override { return nodes_.back(); }
  double omega(std::size_t k) const override { return omega_.at(k); }
  bool rigid(std::size_t k) const override { return k < rigid_; }
  double shape(std::size_t k, double x) const override { return interpolate(nodes_, u_.at(k), 0, x); }
  double slope(std::size_t k, double x) const override { return interpolate(nodes_, u_.at(k), 1, x); }
  double curvature(std::size_t k, double x) const override { return interpolate(nodes_, u_.at(k), 2, x); }
  std::string describe() const override { return text_; }

 private:
  std::vector<double> nodes_;
  std::vector<Eigen::VectorXd> u_;  // all nodal unknowns (zeros at supports)
  std::vector<double> omega_;
  std::size_t rigid_;
  std::string text_;
};

// The rigid modes of the free beam, exact: translation (w = 1, theta = 0) and rotation about the
// centre of mass (w = x - x_c, theta = 1), each scaled to u^T M u = 1 (M-orthogonal by x_c).
std::array<Eigen::VectorXd, 2> rigid_modes(const Mesh& mesh, const Eigen::MatrixXd& M) {
  const auto n = static_cast<Eigen::Index>(mesh.x.size());
  Eigen::VectorXd t = Eigen::VectorXd::Zero(2 * n), r = Eigen::VectorXd::Zero(2 * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    t(2 * i) = 1;
    r(2 * i) = mesh.x[static_cast<std::size_t>(i)];
    r(2 * i + 1) = 1;
  }
  r -= t.dot(M * r) / t.dot(M * t) * t;
  return {t / std::sqrt(t.dot(M * t)), r / std::sqrt(r.dot(M * r))};
}

// Sign convention of the header: the first node (in x) whose |w| is within 1e-2 (relative) of the max is > 0
void fix_sign(Eigen::VectorXd& u) {
  double wmax = 0;
  for (Eigen::Index i = 0; i < u.size(); i += 2) wmax = std::max(wmax, std::abs(u(i)));
  for (Eigen::Index i = 0; i < u.size(); i += 2)
    if (std::abs(u(i)) >= (1 - 1e-2) * wmax) {
      if (u(i) < 0) u = -u;
      return;
    }
}

std::string describe_fe(const FeBeam& b, const Mesh& mesh, const std::vector<double>& omega, std::size_t rigid) {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "FE Euler-Bernoulli beam, %s, L %.4g m, %zu segment(s), %zu lumped mass(es), %zu cubic Hermite elements: %zu "
                "rigid + %zu elastic modes",
                to_string(b.ends), b.length, b.segments.size(), b.masses.size(), mesh.EI.size(), rigid, omega.size() - rigid);
  std::string s = buf;
  for (std::size_t k = rigid, shown = 0; k < omega.size() && shown < 4; ++k, ++shown) {
    std::snprintf(buf, sizeof buf, "%s%.4g", shown ? ", " : ", f = ", omega[k] / (2 * std::numbers::pi));
    s += buf;
  }
  return s + (omega.size() > rigid ? " Hz" : "");
}

}  // namespace

std::vector<double> fe_beam_nodes(const FeBeam& beam) { return build_mesh(beam, {}).x; }

std::unique_ptr<ModeSet> fe_beam_modes(const FeBeam& beam, std::size_t count) {
  const Mesh mesh = build_mesh(beam, {});
  Eigen::MatrixXd K, M;
  assemble(mesh, beam, K, M);
  const std::vector<Eigen::Index> dofs = free_dofs(beam.ends, mesh.x.size());
  if (count > dofs.size()) throw std::invalid_argument("fe_beam_modes: more modes asked for than the mesh has unknowns");
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(restrict(K, dofs), restrict(M, dofs));
  if (es.info() != Eigen::Success) throw std::runtime_error("fe_beam_modes: eigensolver failed");
  const Eigen::VectorXd& lambda = es.eigenvalues();  // omega^2, ascending

  const std::size_t rigid = beam.ends == BeamEnds::free_free ? std::min<std::size_t>(2, count) : 0;
  if (rigid && dofs.size() > 2 && !(std::abs(lambda(1)) <= 1e-6 * lambda(2)))
    throw std::logic_error("fe_beam_modes: the free beam's two lowest eigenvalues are not at round-off level");
  std::vector<Eigen::VectorXd> u;
  std::vector<double> omega;
  const auto R = rigid_modes(mesh, M);
  for (std::size_t k = 0; k < count; ++k) {
    if (k < rigid) {
      u.push_back(R[k]);
      omega.push_back(0);
      continue;
    }
    Eigen::VectorXd full = Eigen::VectorXd::Zero(K.rows());  // u^T M u = 1 from the solver
    for (std::size_t i = 0; i < dofs.size(); ++i)
      full(dofs[i]) = es.eigenvectors()(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k));
    fix_sign(full);
    u.push_back(full);
    omega.push_back(std::sqrt(std::max(0.0, lambda(static_cast<Eigen::Index>(k)))));
  }
  std::string text = describe_fe(beam, mesh, omega, rigid);
  return std::make_unique<FeModes>(mesh.x, std::move(u), std::move(omega), rigid, std::move(text));
}

double fe_static_deflection(const FeBeam& beam, double x_f, double P, double x) {
  if (beam.ends == BeamEnds::free_free)
    throw std::invalid_argument("fe_static_deflection: a free-free beam has no static deflection");
  if (!(x_f >= 0 && x_f <= beam.length)) throw std::invalid_argument("fe_static_deflection: the force must act on the beam");
  const Mesh mesh = build_mesh(beam, {x_f});
  // K's condition number grows like (L/h)^4 (2e9 at 200 elements): in double the deflection would
  // carry ~1e-7 of round-off; long double (64-bit mantissa) keeps it near 1e-11.
  using Mat = Eigen::Matrix<long double, -1, -1>;
  using Vec = Eigen::Matrix<long double, -1, 1>;
  Mat K, M;
  assemble(mesh, beam, K, M);
  const std::vector<Eigen::Index> dofs = free_dofs(beam.ends, mesh.x.size());
  Vec f = Vec::Zero(static_cast<Eigen::Index>(dofs.size()));
  const Eigen::Index load = 2 * static_cast<Eigen::Index>(node_at(mesh, x_f));
  for (std::size_t i = 0; i < dofs.size(); ++i)
    if (dofs[i] == load) f(static_cast<Eigen::Index>(i)) = P;
  const Vec ur = restrict(K, dofs).ldlt().solve(f);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(K.rows());
  for (std::size_t i = 0; i < dofs.size(); ++i) u(dofs[i]) = static_cast<double>(ur(static_cast<Eigen::Index>(i)));
  return interpolate(mesh.x, u, 0, x);
}

}  // namespace bagdem
