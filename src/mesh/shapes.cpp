// See include/bagdem/mesh/shapes.hpp. Each generator places its nodes so that triangles come out
// near equilateral (they are the film's membrane elements: a sliver is stiff in one direction and
// limits the explicit time step), orients them outward by construction, and builds the topology.
#include "bagdem/mesh/shapes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "remesh.hpp"

namespace bagdem {

namespace {

using Tri = std::array<std::uint32_t, 3>;

std::uint32_t add_vertex(TriangleMesh& m, const Vec3& x) {
  m.vertices.push_back(x);
  return static_cast<std::uint32_t>(m.vertices.size() - 1);
}

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

// |log(count / target)|: how far a triangle count is from the target, as a factor.
double log_miss(double count, double target) { return std::abs(std::log(count / target)); }

// Splits the quad (a, b, c, d), counter-clockwise seen from outside, along its shorter diagonal
// (at positions x): the split with the larger smallest angle for near-rhombic quads.
void add_quad(TriangleMesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
  const auto& x = m.vertices;
  if ((x[a] - x[c]).squaredNorm() <= (x[b] - x[d]).squaredNorm()) {
    m.triangles.push_back({a, b, c});
    m.triangles.push_back({a, c, d});
  } else {
    m.triangles.push_back({a, b, d});
    m.triangles.push_back({b, c, d});
  }
}

// The two rings of a capsule strip, joined by a zip: walking both rings in the direction of
// increasing angle, each step adds the triangle on the shorter of the two candidate diagonals
// (advance the lower ring, or the upper), so every triangle spans about one node spacing of each
// ring.
struct Ring {
  std::uint32_t first;  // index of node 0
  std::size_t n;        // node count
  double phase;         // angle of node 0 (unit: rad)
};

void zip(TriangleMesh& m, const Ring& lo, const Ring& hi) {
  const double two_pi = 2 * std::numbers::pi;
  // Start the upper ring at its node nearest in angle to the lower ring's node 0.
  const double dh = two_pi / static_cast<double>(hi.n), dl = two_pi / static_cast<double>(lo.n);
  const long j0 = std::lround((lo.phase - hi.phase) / dh);
  const double hi0 = hi.phase + static_cast<double>(j0) * dh;
  auto lo_node = [&](std::size_t i) { return lo.first + static_cast<std::uint32_t>(i % lo.n); };
  auto hi_node = [&](std::size_t j) {
    const long k = ((j0 + static_cast<long>(j)) % static_cast<long>(hi.n) + static_cast<long>(hi.n)) % static_cast<long>(hi.n);
    return hi.first + static_cast<std::uint32_t>(k);
  };
  std::size_t i = 0, j = 0;
  while (i < lo.n || j < hi.n) {
    // The shorter of the two candidate diagonals; the angles decide a tie (at hexagon corners
    // the two are equal to rounding, and the wrong pick makes a 31-degree triangle).
    const double next_lo = lo.phase + static_cast<double>(i + 1) * dl;
    const double next_hi = hi0 + static_cast<double>(j + 1) * dh;
    const double d_lo = (m.vertices[lo_node(i + 1)] - m.vertices[hi_node(j)]).squaredNorm();
    const double d_hi = (m.vertices[lo_node(i)] - m.vertices[hi_node(j + 1)]).squaredNorm();
    const bool shorter_lo = std::abs(d_lo - d_hi) > 1e-9 * (d_lo + d_hi) ? d_lo < d_hi : next_lo <= next_hi;
    const bool advance_lo = j == hi.n || (i < lo.n && shorter_lo);
    // Outward: (lower k, lower k+1, upper) and (lower, upper k+1, upper k) (shapes.hpp frame: the
    // angle runs counter-clockwise about the axis, the profile from the lower pole to the upper).
    if (advance_lo) {
      m.triangles.push_back({lo_node(i), lo_node(i + 1), hi_node(j)});
      ++i;
    } else {
      m.triangles.push_back({lo_node(i), hi_node(j + 1), hi_node(j)});
      ++j;
    }
  }
}

// Capsule profile: arc length s from the lower pole -> (axial position, radius).
struct Profile {
  double r, straight;
  double total() const { return std::numbers::pi * r + straight; }
  void at(double s, double& z, double& rho) const {
    const double half = 0.5 * straight, cap = 0.5 * std::numbers::pi * r;
    if (s <= cap) {
      const double a = s / r;  // angle from the lower pole
      z = -half - r * std::cos(a);
      rho = r * std::sin(a);
    } else if (s <= cap + straight) {
      z = -half + (s - cap);
      rho = r;
    } else {
      const double a = (total() - s) / r;  // angle from the upper pole
      z = half + r * std::cos(a);
      rho = r * std::sin(a);
    }
  }
};

// Ring node counts of a capsule whose profile is cut into m equal arc-length intervals: nodes
// spaced 2/sqrt(3) of the ring spacing apart make equilateral triangles (spacing = height).
std::vector<std::size_t> capsule_rings(const Profile& pr, std::size_t m) {
  const double ds = pr.total() / static_cast<double>(m);
  std::vector<std::size_t> n(m + 1, 1);
  for (std::size_t i = 1; i < m; ++i) {
    double z, rho;
    pr.at(ds * static_cast<double>(i), z, rho);
    const double nodes = 2 * std::numbers::pi * rho / (ds * 2 / std::sqrt(3.0));
    n[i] = std::max<std::size_t>(3, static_cast<std::size_t>(std::lround(nodes)));
    // On the caps the ideal counts near a pole, 5.4, 10.9, 16.3 ... (ring k at arc k ds), round
    // to 5, 11, 16, and a 5-to-11 zip has 27-degree angles. The hexagonal counts 6 k (rings of a
    // triangular lattice around a node of valence 6) are within 15 % there and zip 6 to 12 into
    // near equilateral triangles.
    const double hex = 6.0 * std::round(nodes / 6.0);
    const bool on_cap = rho < pr.r;
    if (on_cap && hex >= 6 && std::abs(hex - nodes) < 0.15 * nodes) n[i] = static_cast<std::size_t>(hex);
  }
  return n;
}

std::size_t capsule_count(const std::vector<std::size_t>& n) {
  // Pole fans: n[1] and n[m-1] triangles; a zip between rings: n[i] + n[i+1].
  std::size_t c = 0;
  const std::size_t m = n.size() - 1;
  for (std::size_t i = 0; i < m; ++i) c += (i == 0 || i == m - 1) ? (i == 0 ? n[1] : n[m - 1]) : n[i] + n[i + 1];
  return c;
}

// Orthonormal frame (x = axis, y, z = x cross y).
void frame(const Vec3& axis, Vec3& x, Vec3& y, Vec3& z) {
  require(axis.allFinite() && axis.norm() > 0, "shape axis must be a nonzero vector");
  x = axis.normalized();
  y = x.unitOrthogonal();
  z = x.cross(y);
}

}  // namespace

TriangleMesh capsule_mesh(const Vec3& centre, const Vec3& axis, double radius, double length, std::size_t triangles) {
  require(std::isfinite(radius) && radius > 0, "capsule_mesh: radius must be > 0");
  require(std::isfinite(length) && length >= 2 * radius, "capsule_mesh: length must be >= 2 radius (tip to tip)");
  require(centre.allFinite(), "capsule_mesh: centre must be finite");
  Vec3 e, u, v;
  frame(axis, e, u, v);
  const Profile pr{radius, length - 2 * radius};

  // Edge length h of equilateral triangles tiling the area A with the target count, ring spacing
  // h sqrt(3)/2; then the interval count m that comes nearest the target (the count grows with m
  // about as m^2, and rounding of ring counts makes it slightly irregular: try neighbours).
  const double target = static_cast<double>(std::max<std::size_t>(triangles, 1));
  const double area = 4 * std::numbers::pi * radius * radius + 2 * std::numbers::pi * radius * pr.straight;
  const double h = std::sqrt(4 * area / (std::sqrt(3.0) * target));
  const auto m0 = static_cast<std::size_t>(std::max(2.0, std::round(pr.total() / (h * std::sqrt(3.0) / 2))));
  std::size_t best_m = 2;
  double best_miss = std::numeric_limits<double>::infinity();
  for (std::size_t m = std::max<std::size_t>(2, m0 > 4 ? m0 - 4 : 2); m <= m0 + 4; ++m) {
    const double miss = log_miss(static_cast<double>(capsule_count(capsule_rings(pr, m))), target);
    if (miss < best_miss - 1e-12) best_miss = miss, best_m = m;
  }
  const std::size_t m = best_m;
  const std::vector<std::size_t> n = capsule_rings(pr, m);
  const double ds = pr.total() / static_cast<double>(m);

  TriangleMesh mesh;
  auto at = [&](double z, double rho, double angle) {
    return Vec3(centre + z * e + rho * (std::cos(angle) * u + std::sin(angle) * v));
  };
  const std::uint32_t bottom = add_vertex(mesh, centre - 0.5 * length * e);
  std::vector<Ring> rings(m + 1);
  rings[0] = {bottom, 1, 0.0};
  double phase = 0;
  for (std::size_t i = 1; i < m; ++i) {
    // Stagger: a ring with as many nodes as the previous one is turned by half a node spacing, so
    // that the triangles between them are isosceles with the apex between two nodes; a ring with
    // a different count keeps the phase (hexagonal rings 6k -> 6(k+1) then align at the corners of
    // the hexagons, as in a triangular lattice).
    if (i > 1 && n[i] == n[i - 1]) phase += std::numbers::pi / static_cast<double>(n[i]);
    double z, rho;
    pr.at(ds * static_cast<double>(i), z, rho);
    rings[i] = {static_cast<std::uint32_t>(mesh.vertices.size()), n[i], phase};
    for (std::size_t k = 0; k < n[i]; ++k)
      add_vertex(mesh, at(z, rho, phase + 2 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(n[i])));
  }
  const std::uint32_t top = add_vertex(mesh, centre + 0.5 * length * e);
  rings[m] = {top, 1, 0.0};

  for (std::size_t k = 0; k < n[1]; ++k)  // lower pole fan
    mesh.triangles.push_back({bottom, rings[1].first + static_cast<std::uint32_t>((k + 1) % n[1]),
                              rings[1].first + static_cast<std::uint32_t>(k)});
  for (std::size_t i = 1; i + 1 < m; ++i) zip(mesh, rings[i], rings[i + 1]);
  for (std::size_t k = 0; k < n[m - 1]; ++k)  // upper pole fan
    mesh.triangles.push_back({rings[m - 1].first + static_cast<std::uint32_t>(k),
                              rings[m - 1].first + static_cast<std::uint32_t>((k + 1) % n[m - 1]), top});
  build_topology(mesh);
  return mesh;
}

namespace {

// Cells per axis of a pillow's grid, proportional to the semi-axes, scaled so that
// 4 (nx ny + ny nz + nz nx) (two triangles per cell on six faces) comes nearest the target.
std::array<std::size_t, 3> pillow_cells(const Vec3& semi, double target) {
  std::array<std::size_t, 3> cells{1, 1, 1};
  const double s0 = std::sqrt(target / (4 * (semi.x() * semi.y() + semi.y() * semi.z() + semi.z() * semi.x())));
  double best_miss = std::numeric_limits<double>::infinity();
  for (int k = -200; k <= 200; ++k) {
    const double s = s0 * std::exp(0.005 * k);
    std::array<std::size_t, 3> c;
    for (int a = 0; a < 3; ++a) c[a] = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(s * semi[a])));
    const double count = 4.0 * static_cast<double>(c[0] * c[1] + c[1] * c[2] + c[2] * c[0]);
    const double miss = log_miss(count, target);
    if (miss < best_miss - 1e-12) best_miss = miss, cells = c;
  }
  return cells;
}

// The superellipsoid |x/a|^p + |y/b|^p + |z/c|^p = 1 in its own frame (centre at 0, axes x y z).
struct Superellipsoid {
  Vec3 semi;
  double p;
  // f(q) = (|x/a|^p + |y/b|^p + |z/c|^p)^(1/p) is homogeneous of degree 1, so q / f(q) is q moved
  // along its ray from the centre onto the surface f = 1.
  Vec3 radial(const Vec3& q) const {
    double F = 0;
    for (int a = 0; a < 3; ++a) F += std::pow(std::abs(q[a] / semi[a]), p);
    return Vec3(q * std::pow(F, -1.0 / p));
  }
  // Nearest surface point of a point near the surface: Newton steps along the gradient of f
  // (df/dq_a = F^(1/p - 1) |t_a|^(p-1) sign(t_a) / semi_a, t = q / semi), then the radial step for
  // the last rounding.
  Vec3 nearest(Vec3 q) const {
    for (int it = 0; it < 3; ++it) {
      double F = 0;
      Vec3 w;
      for (int a = 0; a < 3; ++a) F += (w[a] = std::pow(std::abs(q[a] / semi[a]), p));
      Vec3 grad;
      for (int a = 0; a < 3; ++a) grad[a] = q[a] == 0 ? 0.0 : w[a] / (q[a] / semi[a]) / semi[a];
      grad *= std::pow(F, 1.0 / p - 1.0);
      q -= (std::pow(F, 1.0 / p) - 1.0) / grad.squaredNorm() * grad;
    }
    return radial(q);
  }
};

// The cube's grid of `cells` projected radially onto the surface. Lattice coordinate -> box
// coordinate in [-1, 1]: tan(theta0 t) / tan(theta0), the equiangular spacing of cubed spheres
// (Ronchi, Iacono & Paolucci, J. Comput. Phys. 124, 1996) at p = 2, blending to uniform spacing as
// the shape becomes a box (p -> infinity). Radial projection of a uniform grid would shrink the
// cells near the cube's corners 5-fold on a sphere.
TriangleMesh pillow_grid(const Superellipsoid& shape, const std::array<std::size_t, 3>& cells) {
  const double theta0 = 0.25 * std::numbers::pi * std::min(1.0, 2.0 / shape.p);
  auto spacing = [&](std::size_t i, std::size_t n) {
    const double t = 2.0 * static_cast<double>(i) / static_cast<double>(n) - 1.0;
    return std::tan(theta0 * t) / std::tan(theta0);
  };
  TriangleMesh mesh;
  std::unordered_map<std::uint64_t, std::uint32_t> index;  // lattice point (i, j, k) -> vertex
  auto node = [&](std::array<std::size_t, 3> l) {
    const std::uint64_t key = (std::uint64_t{l[0]} << 42) | (std::uint64_t{l[1]} << 21) | std::uint64_t{l[2]};
    const auto it = index.find(key);
    if (it != index.end()) return it->second;
    Vec3 q;
    for (int a = 0; a < 3; ++a) q[a] = shape.semi[a] * spacing(l[a], cells[a]);
    const std::uint32_t id = add_vertex(mesh, shape.radial(q));
    index.emplace(key, id);
    return id;
  };
  // Six faces: normal axis a at the high (+) or low (-) end, in-plane axes (u, v) with
  // e_u x e_v = outward normal, so (i, j), (i+1, j), (i+1, j+1), (i, j+1) is counter-clockwise
  // seen from outside.
  struct Face {
    int a, u, v;
    bool high;
  };
  const Face faces[6] = {{0, 1, 2, true}, {0, 2, 1, false}, {1, 2, 0, true},
                         {1, 0, 2, false}, {2, 0, 1, true}, {2, 1, 0, false}};
  for (const Face& f : faces) {
    for (std::size_t i = 0; i < cells[f.u]; ++i)
      for (std::size_t j = 0; j < cells[f.v]; ++j) {
        auto lattice = [&](std::size_t di, std::size_t dj) {
          std::array<std::size_t, 3> l{};
          l[f.a] = f.high ? cells[f.a] : 0;
          l[f.u] = i + di;
          l[f.v] = j + dj;
          return node(l);
        };
        // One statement each: vertices are numbered in the order they are first met.
        const std::uint32_t q00 = lattice(0, 0), q10 = lattice(1, 0), q11 = lattice(1, 1), q01 = lattice(0, 1);
        add_quad(mesh, q00, q10, q11, q01);
      }
  }
  build_topology(mesh);
  return mesh;
}

}  // namespace

TriangleMesh pillow_mesh(const Vec3& centre, const Vec3& axis, const Vec3& side, const Vec3& size, double exponent,
                         std::size_t triangles) {
  require(centre.allFinite(), "pillow_mesh: centre must be finite");
  require(size.allFinite() && size.minCoeff() > 0, "pillow_mesh: size must be > 0 along every axis");
  require(std::isfinite(exponent) && exponent >= 2, "pillow_mesh: exponent must be >= 2 (2 = ellipsoid)");
  require(axis.allFinite() && axis.norm() > 0, "pillow_mesh: axis must be a nonzero vector");
  const Vec3 ex = axis.normalized();
  const Vec3 side_perp = side - side.dot(ex) * ex;
  require(side.allFinite() && side_perp.norm() > 1e-9 * side.norm() && side.norm() > 0,
          "pillow_mesh: side must be a nonzero vector not parallel to the axis");
  const Vec3 ey = side_perp.normalized(), ez = ex.cross(ey);
  const Superellipsoid shape{0.5 * size, exponent};
  const double target = static_cast<double>(std::max<std::size_t>(triangles, 1));
  TriangleMesh mesh = pillow_grid(shape, pillow_cells(shape.semi, target));
  // The grid's cells differ in size and shape where the shape is far from a sphere (on a flat
  // pillow's rim they are 3 to 10 times longer than wide), and smoothing with the grid's
  // connectivity kept trades that for a concentration of small cells at the cube's corners (the
  // area ratio grows with resolution). Remeshing with free connectivity gives both: edge length L
  // of equilateral triangles of the target count, corrected by the count it gave (up to 3 times).
  const double area = surface_area(mesh, mesh.vertices);
  const std::function<Vec3(const Vec3&)> onto = [&shape](const Vec3& q) { return shape.nearest(q); };
  // Below a few tens of triangles the remesher's count is erratic (a flat pillow can collapse to a
  // tetrahedron): the grid itself is kept unless a remeshed surface comes within a factor 1.5.
  double L = std::sqrt(4 * area / (std::sqrt(3.0) * target));
  TriangleMesh out = std::move(mesh);
  for (int attempt = 0; attempt < 4; ++attempt) {
    TriangleMesh r = detail::remesh(out, L, onto, 8);
    const double miss = log_miss(static_cast<double>(r.size()), target);
    if (miss < std::log(1.5) || attempt == 3) {
      if (miss < std::log(1.5)) out = std::move(r);
      break;
    }
    L *= std::sqrt(static_cast<double>(r.size()) / target);
  }
  for (Vec3& x : out.vertices) x = centre + x.x() * ex + x.y() * ey + x.z() * ez;
  return out;
}

TriangleMesh sphere_mesh(const Vec3& centre, double radius, std::size_t triangles) {
  require(std::isfinite(radius) && radius > 0, "sphere_mesh: radius must be > 0");
  require(centre.allFinite(), "sphere_mesh: centre must be finite");
  // Icosahedron (outward, counter-clockwise), each face cut into n^2 triangles (geodesic class I,
  // frequency n), points projected radially: 20 n^2 triangles.
  const double g = 0.5 * (1 + std::sqrt(5.0));
  const Vec3 ico[12] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                        {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  const Tri faces[20] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                         {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                         {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  const double target = static_cast<double>(std::max<std::size_t>(triangles, 1));
  std::size_t n = std::max<std::size_t>(1, static_cast<std::size_t>(std::floor(std::sqrt(target / 20))));
  if (log_miss(20.0 * static_cast<double>((n + 1) * (n + 1)), target) < log_miss(20.0 * static_cast<double>(n * n), target)) ++n;

  TriangleMesh mesh;
  // A point of the subdivided icosahedron is a combination of 1 to 3 corners with integer weights
  // summing to n; keyed by (corner, weight) pairs in corner order it is the same from every face
  // that holds it, and its position is summed in that order, so shared points are bitwise equal.
  std::map<std::array<std::uint32_t, 6>, std::uint32_t> index;
  auto node = [&](const Tri& f, std::size_t i, std::size_t j) {
    std::array<std::pair<std::uint32_t, std::uint32_t>, 3> w{{{f[0], static_cast<std::uint32_t>(n - i - j)},
                                                                {f[1], static_cast<std::uint32_t>(i)},
                                                                {f[2], static_cast<std::uint32_t>(j)}}};
    std::sort(w.begin(), w.end());
    std::array<std::uint32_t, 6> key{};
    key.fill(0xffffffffu);
    int used = 0;
    for (const auto& [corner, weight] : w)
      if (weight > 0) key[2 * used] = corner, key[2 * used + 1] = weight, ++used;
    const auto it = index.find(key);
    if (it != index.end()) return it->second;
    Vec3 q = Vec3::Zero();
    for (int k = 0; k < used; ++k) q += static_cast<double>(key[2 * k + 1]) * ico[key[2 * k]];
    const std::uint32_t id = add_vertex(mesh, centre + radius * q.normalized());
    index.emplace(key, id);
    return id;
  };
  for (const Tri& f : faces)
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; i + j < n; ++j) {
        // Up triangle at (i, j); down triangle beside it. Both keep the face's orientation.
        mesh.triangles.push_back({node(f, i, j), node(f, i + 1, j), node(f, i, j + 1)});
        if (i + j + 2 <= n) mesh.triangles.push_back({node(f, i + 1, j), node(f, i + 1, j + 1), node(f, i, j + 1)});
      }
  build_topology(mesh);
  return mesh;
}

TriangleMesh rectangle_mesh(const Vec3& centre, double lx, double ly, std::size_t nx, std::size_t ny) {
  require(std::isfinite(lx) && std::isfinite(ly) && lx > 0 && ly > 0, "rectangle_mesh: lx and ly must be > 0");
  require(nx >= 1 && ny >= 1, "rectangle_mesh: nx and ny must be >= 1");
  require(centre.allFinite(), "rectangle_mesh: centre must be finite");
  TriangleMesh mesh;
  mesh.vertices.reserve((nx + 1) * (ny + 1));
  for (std::size_t j = 0; j <= ny; ++j)
    for (std::size_t i = 0; i <= nx; ++i)
      mesh.vertices.emplace_back(centre.x() + lx * (static_cast<double>(i) / static_cast<double>(nx) - 0.5),
                                 centre.y() + ly * (static_cast<double>(j) / static_cast<double>(ny) - 0.5), centre.z());
  auto id = [&](std::size_t i, std::size_t j) { return static_cast<std::uint32_t>(j * (nx + 1) + i); };
  mesh.triangles.reserve(2 * nx * ny);
  for (std::size_t j = 0; j < ny; ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      const std::uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if ((i + j) % 2 == 0) {  // diagonal a-c
        mesh.triangles.push_back({a, b, c});
        mesh.triangles.push_back({a, c, d});
      } else {  // diagonal b-d
        mesh.triangles.push_back({a, b, d});
        mesh.triangles.push_back({b, c, d});
      }
    }
  build_topology(mesh);
  return mesh;
}

}  // namespace bagdem
