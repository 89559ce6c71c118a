// See include/bagdem/bag/membrane.hpp for the model and its sources.
#include "bagdem/bag/membrane.hpp"
#include "bagdem/contact/lanes.hpp"
#include "bagdem/parallel.hpp"
#include "hinge.hpp"
#include "quadratic_bending.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace bagdem {

namespace {

using namespace hinge;

enum Regime : std::uint8_t { kSlack = 0, kWrinkled = 1, kTaut = 2 };

// The triangles' law is written once over a number type T (contact/lanes.hpp): double for one
// triangle, Lanes for kLanes of them side by side. Every operation rounds as written
// (-ffp-contract=off) in the same order in both, so a lane gives the scalar law's bits.

// A symmetric 2x2 tensor in a triangle's 2-D frame; xy is the tensor (not engineering) shear.
template <class T>
struct Sym2T {
  T xx, yy, xy;
};
using Sym2 = Sym2T<double>;

template <class T>
BAGDEM_INLINE T contract(const Sym2T<T>& a, const Sym2T<T>& b) { return a.xx * b.xx + a.yy * b.yy + 2.0 * a.xy * b.xy; }
template <class T>
BAGDEM_INLINE Sym2T<T> scaled(const Sym2T<T>& a, T s) { return {s * a.xx, s * a.yy, s * a.xy}; }
template <class T>
BAGDEM_INLINE Sym2T<T> select_sym(LanesMaskT<T> m, const Sym2T<T>& a, const Sym2T<T>& b) {
  return {select(m, a.xx, b.xx), select(m, a.yy, b.yy), select(m, a.xy, b.xy)};
}

// The rest edge matrix's inverse Dm^-1 (its four entries) and t A0 of a triangle (or of kLanes).
template <class T>
struct RestFrame {
  T m00, m01, m10, m11, tA0;
};

// The two columns of the 3x2 deformation gradient F = Ds Dm^-1, Ds = [x1 - x0, x2 - x0] (or of its
// rate, from the node velocities).
template <class T>
struct GradientT {
  V3<T> c0, c1;
};

template <class T>
BAGDEM_INLINE GradientT<T> deformation_gradient(const V3<T>& d1, const V3<T>& d2, const RestFrame<T>& r) {
  return {r.m00 * d1 + r.m10 * d2, r.m01 * d1 + r.m11 * d2};
}

// Green-Lagrange strain (F^T F - I) / 2.
template <class T>
BAGDEM_INLINE Sym2T<T> green_strain(const GradientT<T>& F) {
  return {0.5 * (dot(F.c0, F.c0) - 1.0), 0.5 * (dot(F.c1, F.c1) - 1.0), 0.5 * dot(F.c0, F.c1)};
}

// Its rate sym(F^T dF/dt).
template <class T>
BAGDEM_INLINE Sym2T<T> strain_rate(const GradientT<T>& F, const GradientT<T>& dF) {
  return {dot(F.c0, dF.c0), dot(F.c1, dF.c1), 0.5 * (dot(F.c0, dF.c1) + dot(F.c1, dF.c0))};
}

template <class T>
struct PrincipalT {
  T e1, e2;  // e1 >= e2
};
using Principal = PrincipalT<double>;

template <class T>
BAGDEM_INLINE PrincipalT<T> principal(const Sym2T<T>& e) {
  const T m = 0.5 * (e.xx + e.yy), d = 0.5 * (e.xx - e.yy);
  const T r = sqrt_of(d * d + e.xy * e.xy);
  return {m + r, m - r};
}

// Plane-stress St. Venant-Kirchhoff with the tension-field relaxation.
struct Law {
  double E, nu, k;  // k = E / (1 - nu^2) (unit: Pa)
  bool tension_field;

  explicit Law(const MembraneProperties& p)
      : E(p.youngs_modulus), nu(p.poisson_ratio), k(p.youngs_modulus / (1.0 - p.poisson_ratio * p.poisson_ratio)),
        tension_field(p.tension_field) {}

  // C is isotropic, so the taut law's principal stresses are k (e1 + nu e2) >= k (e2 + nu e1): the
  // film is taut while the smaller one is not compressive.
  BAGDEM_INLINE std::uint8_t regime(const Principal& p) const {
    if (!tension_field) return kTaut;
    if (p.e1 <= 0) return kSlack;
    return p.e2 + nu * p.e1 >= 0 ? kTaut : kWrinkled;
  }
  template <class T>
  BAGDEM_INLINE Sym2T<T> taut(const Sym2T<T>& e) const {  // C : e
    return {k * (e.xx + nu * e.yy), k * (e.yy + nu * e.xx), k * (1.0 - nu) * e.xy};
  }
};

// Second Piola-Kirchhoff stress S = dpsi/dEg (unit: Pa), the energy density psi (unit: J/m^3) and,
// when wrinkled, the projector n1 n1^T on the taut direction; per lane, which regime (masks).
template <class T>
struct StressT {
  Sym2T<T> S, P1;
  T psi;
  LanesMaskT<T> taut, slack;  // wrinkled: neither
};

// Wrinkled: psi = E e1^2 / 2 and S = E e1 n1 n1^T (de1/dEg = n1 n1^T). At the taut boundary
// e2 = -nu e1 the taut psi = k (e1^2 + 2 nu e1 e2 + e2^2) / 2 = E e1^2 / 2 and its stress
// k (e1 + nu e2) n1 n1^T + k (e2 + nu e1) n2 n2^T = E e1 n1 n1^T: energy and stress are continuous.
// Every regime's value is formed and the lane's own is kept (a division by zero in another's is
// discarded).
template <class T>
BAGDEM_INLINE StressT<T> stress(const Law& law, const Sym2T<T>& e) {
  const PrincipalT<T> p = principal(e);
  const LanesMaskT<T> none = mask_of<T>(false);
  const LanesMaskT<T> slack = law.tension_field ? p.e1 <= 0.0 : none;
  const LanesMaskT<T> taut = law.tension_field ? and_not(p.e2 + law.nu * p.e1 >= 0.0, slack) : mask_of<T>(true);
  const Sym2T<T> St = law.taut(e);
  // n1 n1^T = (Eg - e2 I) / (e1 - e2) (spectral decomposition; no angle needed). Wrinkled means
  // e2 < -nu e1 < 0 < e1, so e1 - e2 > (1 + nu) e1 > 0.
  const T inv = 1.0 / (p.e1 - p.e2);
  const Sym2T<T> P1{(e.xx - p.e2) * inv, (e.yy - p.e2) * inv, e.xy * inv};
  const T s = law.E * p.e1;
  const Sym2T<T> zero{splat<T>(0), splat<T>(0), splat<T>(0)};
  return {select_sym(taut, St, select_sym(slack, zero, scaled(P1, s))), P1,
          select(taut, 0.5 * contract(St, e), select(slack, splat<T>(0), 0.5 * s * p.e1)), taut, slack};
}

// Kelvin-Voigt stress beta C : dEg/dt with the elastic stress's C: none when slack, uniaxial along
// n1 when wrinkled. Its power -t A0 S_v : dEg/dt is never positive.
template <class T>
BAGDEM_INLINE Sym2T<T> viscous_stress(const Law& law, const StressT<T>& st, const Sym2T<T>& rate, double beta) {
  const Sym2T<T> zero{splat<T>(0), splat<T>(0), splat<T>(0)};
  return select_sym(st.taut, scaled(law.taut(rate), splat<T>(beta)),
                    select_sym(st.slack, zero, scaled(st.P1, beta * law.E * contract(st.P1, rate))));
}

// Node forces of stress S: H = -t A0 F S Dm^-T, f1 and f2 its columns, f0 = -(f1 + f2) (the
// derivative of t A0 psi with respect to Ds is t A0 F S Dm^-T).
template <class T>
BAGDEM_INLINE std::array<V3<T>, 3> node_forces(const GradientT<T>& F, const Sym2T<T>& S, const RestFrame<T>& r) {
  const V3<T> p0 = S.xx * F.c0 + S.xy * F.c1, p1 = S.xy * F.c0 + S.yy * F.c1;  // columns of F S
  const T minus = -r.tA0;
  const V3<T> f1 = minus * (r.m00 * p0 + r.m01 * p1);
  const V3<T> f2 = minus * (r.m10 * p0 + r.m11 * p1);
  return {-(f1 + f2), f1, f2};
}

BAGDEM_INLINE RestFrame<double> rest_frame(const Eigen::Matrix2d& m, double tA0) {
  return {m(0, 0), m(0, 1), m(1, 0), m(1, 1), tA0};
}

// The deformation gradient of triangle tr at x (for the scalar callers).
BAGDEM_INLINE GradientT<double> gradient_at(const std::vector<Vec3>& x, const std::array<std::uint32_t, 3>& tr,
                                            const Eigen::Matrix2d& m) {
  return deformation_gradient<double>(x[tr[1]] - x[tr[0]], x[tr[2]] - x[tr[0]], rest_frame(m, 0.0));
}

void check_properties(const MembraneProperties& p) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("Membrane: " + what); };
  if (!(p.youngs_modulus > 0)) fail("youngs_modulus must be > 0");
  if (!(p.poisson_ratio > -1.0 && p.poisson_ratio <= 0.5)) fail("poisson_ratio must be in (-1, 0.5]");
  if (!(p.thickness > 0)) fail("thickness must be > 0");
  if (!(p.density > 0)) fail("density must be > 0");
  if (!(p.bending_stiffness >= 0)) fail("bending_stiffness must be >= 0");
  if (!(p.damping_time >= 0)) fail("damping_time must be >= 0");
}

// CSR of (record << 2 | slot) per node, in ascending record order.
template <std::size_t N>
void build_csr(std::size_t nodes, const std::vector<std::array<std::uint32_t, N>>& records,
               std::vector<std::uint32_t>& begin, std::vector<std::uint32_t>& entries) {
  begin.assign(nodes + 1, 0);
  for (const auto& r : records)
    for (std::uint32_t v : r) ++begin[v + 1];
  for (std::size_t i = 0; i < nodes; ++i) begin[i + 1] += begin[i];
  entries.resize(begin[nodes]);
  std::vector<std::uint32_t> fill(begin.begin(), begin.end() - 1);
  for (std::size_t r = 0; r < records.size(); ++r)
    for (std::uint32_t s = 0; s < N; ++s) entries[fill[records[r][s]]++] = static_cast<std::uint32_t>(r << 2) | s;
}

}  // namespace

Membrane::Membrane(const TriangleMesh& mesh, const MembraneProperties& props) : props_(props), tri_(mesh.triangles) {
  check_properties(props);
  if (mesh.vertices.size() >= (1u << 30) || tri_.size() >= (1u << 30))
    throw std::invalid_argument("Membrane: mesh too large");
  for (const auto& t : tri_)
    for (std::uint32_t v : t)
      if (v >= mesh.vertices.size()) throw std::invalid_argument("Membrane: vertex index out of range");
  build_rest_frames(mesh.vertices);
  build_hinges(mesh.vertices);
  build_gather();
  compute_frequencies(mesh.vertices);
}

// Each triangle's 2-D frame: x along its first edge, y in its plane, so the rest edge matrix
// Dm = [X1 - X0, X2 - X0] in that frame is upper triangular with a positive determinant 2 A0.
void Membrane::build_rest_frames(const std::vector<Vec3>& x0) {
  const std::size_t nt = tri_.size();
  area0_.resize(nt);
  dm_inv_.resize(nt);
  node_mass_.assign(x0.size(), 0.0);
  for (std::size_t i = 0; i < nt; ++i) {
    const auto& t = tri_[i];
    const Vec3 d1 = x0[t[1]] - x0[t[0]], d2 = x0[t[2]] - x0[t[0]];
    const Vec3 n = d1.cross(d2);
    const double l1 = d1.norm(), nn = n.norm();
    // Repeated vertices or collinear ones (relative to the edge lengths) have no frame.
    if (!(nn > 1e-12 * l1 * d2.norm()))
      throw std::invalid_argument("Membrane: degenerate triangle " + std::to_string(i));
    const Vec3 ex = d1 / l1, ey = (n / nn).cross(ex);
    Eigen::Matrix2d dm;
    dm << l1, d2.dot(ex), 0.0, d2.dot(ey);
    dm_inv_[i] = dm.inverse();
    area0_[i] = 0.5 * nn;
    const double m = props_.density * props_.thickness * area0_[i] / 3.0;
    for (std::uint32_t v : t) node_mass_[v] += m;
  }
  tri_elastic_.assign(nt, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  tri_damping_.assign(props_.damping_time > 0 ? nt : 0, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  tri_energy_.assign(nt, 0.0);
}

// Hinges from the triangle list: every directed edge (t[k], t[k+1]) keyed by its vertex pair,
// sorted, so the two triangles of an interior edge come together (in a fixed order).
void Membrane::build_hinges(const std::vector<Vec3>& x0) {
  struct DirectedEdge {
    std::uint64_t key;  // lower vertex << 32 | higher vertex
    std::uint32_t tri, k;
  };
  std::vector<DirectedEdge> edges;
  edges.reserve(3 * tri_.size());
  for (std::uint32_t i = 0; i < tri_.size(); ++i)
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint64_t a = tri_[i][k], b = tri_[i][(k + 1) % 3];
      edges.push_back({std::min(a, b) << 32 | std::max(a, b), i, k});
    }
  std::sort(edges.begin(), edges.end(), [](const DirectedEdge& p, const DirectedEdge& q) {
    return p.key != q.key ? p.key < q.key : p.tri < q.tri;
  });
  hinges_.clear();
  const double D = props_.bending_stiffness;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    if (j - i > 2) throw std::invalid_argument("Membrane: an edge shared by more than two triangles");
    if (j - i == 2) {
      const auto& A = tri_[edges[i].tri];
      const auto& B = tri_[edges[i + 1].tri];
      const std::uint32_t ka = edges[i].k, kb = edges[i + 1].k;
      const Hinge h{A[ka], A[(ka + 1) % 3], A[(ka + 2) % 3], B[(kb + 2) % 3], 0.0, 0.0, 0.0, 0.0, {}};
      if (B[kb] != h.v1) throw std::invalid_argument("Membrane: inconsistent triangle orientation");
      if (D > 0) hinges_.push_back(h);
    }
    i = j;
  }
  for (Hinge& h : hinges_) {
    h.theta0 = hinge_angle(x0[h.v0], x0[h.v1], x0[h.a], x0[h.b]);
    // k_e = D |e|^2 / (2 (A1 + A2)) (Grinspun et al. 2003 edge weight; calibrated, see the header).
    const Vec3 e = x0[h.v1] - x0[h.v0];
    const double a1 = 0.5 * e.cross(x0[h.a] - x0[h.v0]).norm(), a2 = 0.5 * e.cross(x0[h.b] - x0[h.v0]).norm();
    h.k = 0.5 * D * e.squaredNorm() / (a1 + a2);
    h.fade_a = std::pow(0.1 * 2 * a1, 2), h.fade_b = std::pow(0.1 * 2 * a2, 2);
    h.w = quadratic_bending::weights(x0[h.v0], x0[h.v1], x0[h.a], x0[h.b]);
  }
  hinge_force_.assign(hinges_.size(), {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  hinge_energy_.assign(hinges_.size(), 0.0);
}

void Membrane::build_gather() {
  build_csr(nodes(), tri_, tri_gather_begin_, tri_gather_);
  std::vector<std::array<std::uint32_t, 4>> hv(hinges_.size());
  for (std::size_t i = 0; i < hinges_.size(); ++i) hv[i] = {hinges_[i].v0, hinges_[i].v1, hinges_[i].a, hinges_[i].b};
  build_csr(nodes(), hv, hinge_gather_begin_, hinge_gather_);
}

// Gershgorin: every eigenvalue of M^-1 K lies in a disc centred on a diagonal entry with radius
// the rest of its row, so omega^2 <= max over rows of sum_j |K_ij| / m_i. K is linearised at rest
// (zero stress: no geometric stiffness; taut C, the stiffest regime), and each element's absolute
// row sums are added, which bounds the assembled matrix's. Membrane element: K = t A0 B^T C B with
// B the 3x9 map from node displacements to (dExx, dEyy, 2 dExy) (Belytschko et al. 2000, ch. 9).
// Hinge: K = 2 k g g^T (g the angle's gradient; the (theta - theta0) term vanishes at rest).
// The hinges' rows alone bound the bending's own highest frequency.
void Membrane::compute_frequencies(const std::vector<Vec3>& x0) {
  std::vector<double> row(3 * nodes(), 0.0), bend(3 * nodes(), 0.0);
  const Law law(props_);
  Eigen::Matrix3d C;
  C << law.k, law.k * law.nu, 0, law.k * law.nu, law.k, 0, 0, 0, law.k * (1 - law.nu) / 2;
  for (std::size_t i = 0; i < tri_.size(); ++i) {
    const auto& t = tri_[i];
    const Vec3 d1 = x0[t[1]] - x0[t[0]], d2 = x0[t[2]] - x0[t[0]];
    const Vec3 ex = d1.normalized(), ey = d1.cross(d2).normalized().cross(ex);
    const Eigen::Matrix2d& g = dm_inv_[i];
    const Eigen::Vector2d grad[3] = {-(g.row(0) + g.row(1)).transpose(), g.row(0).transpose(), g.row(1).transpose()};
    Eigen::Matrix<double, 3, 9> B;
    for (int a = 0; a < 3; ++a) {
      B.block<1, 3>(0, 3 * a) = grad[a].x() * ex.transpose();
      B.block<1, 3>(1, 3 * a) = grad[a].y() * ey.transpose();
      B.block<1, 3>(2, 3 * a) = grad[a].y() * ex.transpose() + grad[a].x() * ey.transpose();
    }
    // lazyProduct: coefficient-wise products (Eigen's blocked GEMM path is overkill at 9 x 9).
    const Eigen::Matrix<double, 3, 9> CB = C.lazyProduct(B);
    const Eigen::Matrix<double, 9, 9> K = (props_.thickness * area0_[i]) * B.transpose().lazyProduct(CB);
    for (int a = 0; a < 3; ++a)
      for (int r = 0; r < 3; ++r) row[3 * t[a] + r] += K.row(3 * a + r).cwiseAbs().sum();
  }
  const bool quadratic = props_.bending_model == BendingModel::Quadratic;
  for (const Hinge& h : hinges_) {
    const std::uint32_t v[4] = {h.v0, h.v1, h.a, h.b};
    // The quadratic model's Hessian is 2 k w w^T (x) I: a row's absolute sum 2 k |w_s| sum_j |w_j|
    // (one axis: it does not couple x, y and z).
    if (quadratic) {
      double wsum = 0;
      for (double wj : h.w) wsum += std::abs(wj);
      for (int s = 0; s < 4; ++s)
        for (int r = 0; r < 3; ++r) {
          const double k = 2.0 * h.k * std::abs(h.w[s]) * wsum;
          row[3 * v[s] + r] += k;
          bend[3 * v[s] + r] += k;
        }
      continue;
    }
    const auto g = hinge_eval<double>(x0[h.v0], x0[h.v1], x0[h.a], x0[h.b]).grad;
    double gsum = 0;
    for (const Vec3& gi : g) gsum += gi.cwiseAbs().sum();
    for (int s = 0; s < 4; ++s)
      for (int r = 0; r < 3; ++r) {
        const double k = 2.0 * h.k * std::abs(g[s][r]) * gsum;
        row[3 * v[s] + r] += k;
        bend[3 * v[s] + r] += k;
      }
  }
  double w2 = 0, b2 = 0;
  for (std::size_t i = 0; i < nodes(); ++i)
    if (node_mass_[i] > 0)
      for (int r = 0; r < 3; ++r) {
        w2 = std::max(w2, row[3 * i + r] / node_mass_[i]);
        b2 = std::max(b2, bend[3 * i + r] / node_mass_[i]);
      }
  max_frequency_ = std::sqrt(w2);
  bending_frequency_ = std::sqrt(b2);
}

double Membrane::max_frequency() const { return max_frequency_; }
double Membrane::bending_frequency() const { return bending_frequency_; }

double Membrane::add_forces(const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& f_elastic,
                            std::vector<Vec3>& f_damping, double bending_weight) {
  const std::size_t n = nodes(), nt = tri_.size(), nh = bending_weight > 0 ? hinges_.size() : 0;
  if (x.size() != n || v.size() != n || f_elastic.size() != n || f_damping.size() != n)
    throw std::invalid_argument("Membrane::add_forces: every vector must have nodes() entries");
  const Law law(props_);
  const double t = props_.thickness, beta = props_.damping_time;
  const bool damped = beta > 0;

  // The triangles kLanes at a time (lanes.hpp); a short last group repeats its last triangle.
  const std::size_t groups = (nt + kLanes - 1) / kLanes;
  parallel_for(groups, [&](std::size_t g) {
    std::size_t id[kLanes];
    for (int l = 0; l < kLanes; ++l) id[l] = std::min(g * kLanes + l, nt - 1);
    auto corner = [&](const std::vector<Vec3>& at, int a) {
      const double* p[kLanes] = {at[tri_[id[0]][a]].data(), at[tri_[id[1]][a]].data(), at[tri_[id[2]][a]].data(),
                                 at[tri_[id[3]][a]].data()};
      return gather3(p);
    };
    auto each = [&](auto field) { return Lanes{field(id[0]), field(id[1]), field(id[2]), field(id[3])}; };
    const RestFrame<Lanes> r{each([&](std::size_t i) { return dm_inv_[i](0, 0); }), each([&](std::size_t i) { return dm_inv_[i](0, 1); }),
                             each([&](std::size_t i) { return dm_inv_[i](1, 0); }), each([&](std::size_t i) { return dm_inv_[i](1, 1); }),
                             each([&](std::size_t i) { return t * area0_[i]; })};
    const Lanes3 x0 = corner(x, 0);
    const GradientT<Lanes> F = deformation_gradient(corner(x, 1) - x0, corner(x, 2) - x0, r);
    const StressT<Lanes> st = stress(law, green_strain(F));
    const Lanes energy = r.tA0 * st.psi;
    const std::array<Lanes3, 3> fe = node_forces(F, st.S, r);
    std::array<Lanes3, 3> fd{};
    if (damped) {
      const Lanes3 v0 = corner(v, 0);
      const GradientT<Lanes> dF = deformation_gradient(corner(v, 1) - v0, corner(v, 2) - v0, r);
      fd = node_forces(F, viscous_stress(law, st, strain_rate(F, dF), beta), r);
    }
    for (int l = 0; l < kLanes && g * kLanes + l < nt; ++l) {
      const std::size_t i = g * kLanes + l;
      tri_energy_[i] = energy[l];
      tri_elastic_[i] = {lane(fe[0], l), lane(fe[1], l), lane(fe[2], l)};
      if (damped) tri_damping_[i] = {lane(fd[0], l), lane(fd[1], l), lane(fd[2], l)};
    }
  });

  if (nh > 0) hinge_forces(x, bending_weight);

  parallel_for(n, [&](std::size_t i) {
    Vec3 fe = Vec3::Zero(), fd = Vec3::Zero();
    for (std::uint32_t k = tri_gather_begin_[i]; k < tri_gather_begin_[i + 1]; ++k) {
      const std::uint32_t r = tri_gather_[k] >> 2, s = tri_gather_[k] & 3;
      fe += tri_elastic_[r][s];
      if (damped) fd += tri_damping_[r][s];
    }
    if (nh > 0)
      for (std::uint32_t k = hinge_gather_begin_[i]; k < hinge_gather_begin_[i + 1]; ++k)
        fe += hinge_force_[hinge_gather_[k] >> 2][hinge_gather_[k] & 3];
    f_elastic[i] += fe;
    if (damped) f_damping[i] += fd;
  });

  // Totals in index order, as elastic_energy() sums them: the same bits for any thread count.
  double energy = 0;
  for (double e : tri_energy_) energy += e;
  if (nh > 0)
    for (double e : hinge_energy_) energy += e;
  return energy;
}

// Each hinge's force (x bending_weight) and energy into its record (hinge_force_, hinge_energy_).
void Membrane::hinge_forces(const std::vector<Vec3>& x, double bending_weight) {
  const std::size_t nh = hinges_.size();
  if (props_.bending_model == BendingModel::Quadratic) {
    // W = k |s|^2, s = sum w_j x_j: f_j = -2 k w_j s (quadratic_bending.hpp).
    parallel_for(nh, [&](std::size_t i) {
      const Hinge& h = hinges_[i];
      const Vec3 s = quadratic_bending::curvature(h.w, x[h.v0], x[h.v1], x[h.a], x[h.b]);
      hinge_energy_[i] = h.k * s.squaredNorm();
      const Vec3 c = (-2.0 * h.k * bending_weight) * s;
      hinge_force_[i] = {h.w[0] * c, h.w[1] * c, h.w[2] * c, h.w[3] * c};
    });
    return;
  }
  // The hinges kLanes at a time, as the triangles.
  parallel_for((nh + kLanes - 1) / kLanes, [&](std::size_t g) {
    const Hinge* h[kLanes];
    for (int l = 0; l < kLanes; ++l) h[l] = &hinges_[std::min(g * kLanes + l, nh - 1)];
    auto node = [&](std::uint32_t Hinge::*v) {
      const double* p[kLanes] = {x[h[0]->*v].data(), x[h[1]->*v].data(), x[h[2]->*v].data(), x[h[3]->*v].data()};
      return gather3(p);
    };
    auto each = [&](double Hinge::*f) { return Lanes{h[0]->*f, h[1]->*f, h[2]->*f, h[3]->*f}; };
    const HingeEval<Lanes> he = hinge_eval<Lanes>(node(&Hinge::v0), node(&Hinge::v1), node(&Hinge::a), node(&Hinge::b));
    const Lanes k = each(&Hinge::k), d = angle_change(he.theta, each(&Hinge::theta0));
    const Lanes c = -2.0 * k * d * bending_weight;  // f = -dW/dx = -2 k (theta - theta0) dtheta/dx, weighted
    const Lanes energy = k * d * d;
    for (int l = 0; l < kLanes && g * kLanes + l < nh; ++l) {
      const std::size_t i = g * kLanes + l;
      const Hinge& hi = *h[l];
      if (he.nA2[l] < hi.fade_a || he.nB2[l] < hi.fade_b) {  // a wing near collapse: faded (rare)
        const FadedHinge f = faded_hinge(x[hi.v0], x[hi.v1], x[hi.a], x[hi.b], hi.k, hi.theta0, hi.fade_a, hi.fade_b);
        hinge_energy_[i] = f.energy;
        for (int s = 0; s < 4; ++s) hinge_force_[i][s] = bending_weight * f.force[s];
        continue;
      }
      hinge_energy_[i] = energy[l];
      hinge_force_[i] = {lane(c * he.grad[0], l), lane(c * he.grad[1], l), lane(c * he.grad[2], l), lane(c * he.grad[3], l)};
    }
  });
}

double Membrane::elastic_energy(const std::vector<Vec3>& x) const {
  if (x.size() != nodes()) throw std::invalid_argument("Membrane::elastic_energy: x must have nodes() entries");
  const Law law(props_);
  double energy = 0;
  for (std::size_t i = 0; i < tri_.size(); ++i) {
    energy += props_.thickness * area0_[i] * stress(law, green_strain(gradient_at(x, tri_[i], dm_inv_[i]))).psi;
  }
  for (const Hinge& h : hinges_) {
    if (props_.bending_model == BendingModel::Quadratic) {
      energy += h.k * quadratic_bending::curvature(h.w, x[h.v0], x[h.v1], x[h.a], x[h.b]).squaredNorm();
      continue;
    }
    const HingeEval<double> he = hinge_eval<double>(x[h.v0], x[h.v1], x[h.a], x[h.b]);
    if (he.nA2 < h.fade_a || he.nB2 < h.fade_b) {
      energy += faded_hinge(x[h.v0], x[h.v1], x[h.a], x[h.b], h.k, h.theta0, h.fade_a, h.fade_b).energy;
      continue;
    }
    const double d = angle_change<double>(he.theta, h.theta0);  // hinge_angle's own arithmetic
    energy += h.k * d * d;
  }
  return energy;
}

Membrane::TriangleState Membrane::triangle_state(const std::vector<Vec3>& x, std::size_t tri) const {
  if (x.size() != nodes()) throw std::out_of_range("Membrane::triangle_state: x must have nodes() entries");
  const Principal p = principal(green_strain(gradient_at(x, tri_.at(tri), dm_inv_[tri])));
  return {Law(props_).regime(p), p.e1, p.e2};
}

}  // namespace bagdem
