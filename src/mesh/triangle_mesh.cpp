// See include/bagdem/mesh/triangle_mesh.hpp for the conventions (orientation, edge numbering, CSR).
#include "bagdem/mesh/triangle_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace bagdem {

namespace {

// Feature keys (contact/sphere_triangle.hpp) keep the kind in the top 2 bits of 32.
constexpr std::size_t kMaxCount = std::size_t{1} << 30;

std::string tri_name(std::size_t t, const std::array<std::uint32_t, 3>& v) {
  return "triangle " + std::to_string(t) + " (" + std::to_string(v[0]) + ", " + std::to_string(v[1]) + ", " +
         std::to_string(v[2]) + ")";
}

void check_positions(const TriangleMesh& mesh, const std::vector<Vec3>& x, const char* who) {
  if (x.size() != mesh.vertices.size())
    throw std::invalid_argument(std::string(who) + ": " + std::to_string(x.size()) + " positions for " +
                                std::to_string(mesh.vertices.size()) + " vertices");
}

}  // namespace

bool TriangleMesh::closed() const {
  if (triangles.empty() || edge_triangles.empty()) return false;
  return std::all_of(edge_triangles.begin(), edge_triangles.end(),
                     [](const std::array<std::uint32_t, 2>& e) { return e[1] != kNoTriangle; });
}

bool degenerate_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double l2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  const double cross2 = (b - a).cross(c - a).squaredNorm();
  return !(cross2 > 1e-24 * l2 * l2);  // also true for NaN coordinates
}

void build_topology(TriangleMesh& mesh) {
  const std::size_t nv = mesh.vertices.size(), nt = mesh.triangles.size();
  // At most 3 nt edges: below 2^30 with nt < 2^28.
  if (nv >= kMaxCount || nt >= kMaxCount / 4)
    throw std::invalid_argument("build_topology: too many vertices or triangles (limit 2^30 vertices, 2^28 triangles)");

  for (std::size_t t = 0; t < nt; ++t) {
    const auto& v = mesh.triangles[t];
    for (int k = 0; k < 3; ++k)
      if (v[k] >= nv)
        throw std::invalid_argument(tri_name(t, v) + ": vertex index out of range (" + std::to_string(nv) +
                                    " vertices)");
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0])
      throw std::invalid_argument(tri_name(t, v) + " repeats a vertex");
    if (degenerate_triangle(mesh.vertices[v[0]], mesh.vertices[v[1]], mesh.vertices[v[2]]))
      throw std::invalid_argument(tri_name(t, v) + " has zero area");
  }

  // Half-edges sorted by (undirected edge, triangle): the one or two half-edges of an edge are
  // adjacent, the lower triangle first. Sorting (not hashing) keeps the edge numbering independent
  // of the platform.
  struct HalfEdge {
    std::uint64_t edge;  // lower vertex << 32 | higher vertex
    std::uint32_t slot;  // 3 t + k: edge k of triangle t
  };
  std::vector<HalfEdge> half(3 * nt);
  for (std::size_t t = 0; t < nt; ++t)
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
      half[3 * t + k] = {(std::uint64_t{std::min(a, b)} << 32) | std::max(a, b), static_cast<std::uint32_t>(3 * t + k)};
    }
  std::sort(half.begin(), half.end(),
            [](const HalfEdge& x, const HalfEdge& y) { return x.edge != y.edge ? x.edge < y.edge : x.slot < y.slot; });

  std::vector<std::array<std::uint32_t, 2>> edge_vertices, edge_triangles;
  std::vector<std::array<std::uint32_t, 3>> triangle_edges(nt);
  edge_vertices.reserve(3 * nt / 2 + 1);
  edge_triangles.reserve(3 * nt / 2 + 1);
  for (std::size_t i = 0; i < half.size();) {
    std::size_t j = i + 1;
    while (j < half.size() && half[j].edge == half[i].edge) ++j;
    const auto lo = static_cast<std::uint32_t>(half[i].edge >> 32), hi = static_cast<std::uint32_t>(half[i].edge);
    const std::string edge_name = "edge (" + std::to_string(lo) + ", " + std::to_string(hi) + ")";
    if (j - i > 2) {
      std::string list;
      for (std::size_t h = i; h < j; ++h) list += (h > i ? ", " : "") + std::to_string(half[h].slot / 3);
      throw std::invalid_argument(edge_name + " is shared by " + std::to_string(j - i) + " triangles (" + list +
                                  ")");
    }
    // A half-edge runs lo -> hi when the triangle's vertex k is lo.
    auto forward = [&](const HalfEdge& h) { return mesh.triangles[h.slot / 3][h.slot % 3] == lo; };
    if (j - i == 2 && forward(half[i]) == forward(half[i + 1]))
      throw std::invalid_argument("triangles " + std::to_string(half[i].slot / 3) + " and " +
                                  std::to_string(half[i + 1].slot / 3) + " run through " + edge_name +
                                  " in the same direction: inconsistent orientation");
    const auto e = static_cast<std::uint32_t>(edge_vertices.size());
    edge_vertices.push_back({lo, hi});
    edge_triangles.push_back({half[i].slot / 3, j - i == 2 ? half[i + 1].slot / 3 : kNoTriangle});
    for (std::size_t h = i; h < j; ++h) triangle_edges[half[h].slot / 3][half[h].slot % 3] = e;
    i = j;
  }

  // Triangles around each vertex (CSR, ascending since filled in triangle order).
  std::vector<std::uint32_t> begin(nv + 1, 0), around(3 * nt);
  for (const auto& v : mesh.triangles)
    for (std::uint32_t k = 0; k < 3; ++k) ++begin[v[k] + 1];
  for (std::size_t i = 0; i < nv; ++i) begin[i + 1] += begin[i];
  std::vector<std::uint32_t> fill(begin.begin(), begin.end() - 1);
  for (std::size_t t = 0; t < nt; ++t)
    for (std::uint32_t k = 0; k < 3; ++k) around[fill[mesh.triangles[t][k]]++] = static_cast<std::uint32_t>(t);

  std::vector<std::uint8_t> on_boundary(nv, 0);
  for (std::size_t e = 0; e < edge_vertices.size(); ++e)
    if (edge_triangles[e][1] == kNoTriangle) on_boundary[edge_vertices[e][0]] = on_boundary[edge_vertices[e][1]] = 1;

  mesh.edge_vertices = std::move(edge_vertices);
  mesh.edge_triangles = std::move(edge_triangles);
  mesh.triangle_edges = std::move(triangle_edges);
  mesh.vertex_triangle_begin = std::move(begin);
  mesh.vertex_triangles = std::move(around);
  mesh.vertex_on_boundary = std::move(on_boundary);
}

double enclosed_volume(const TriangleMesh& mesh, const std::vector<Vec3>& x) {
  check_positions(mesh, x, "enclosed_volume");
  if (mesh.triangles.empty()) return 0.0;
  // Relative to a vertex of the surface (the sum does not depend on the origin for a closed
  // surface): no cancellation between large terms when the body sits far from the origin.
  const Vec3 o = x[mesh.triangles[0][0]];
  double six_v = 0;
  for (const auto& t : mesh.triangles) six_v += (x[t[0]] - o).dot((x[t[1]] - o).cross(x[t[2]] - o));
  return six_v / 6.0;
}

double surface_area(const TriangleMesh& mesh, const std::vector<Vec3>& x) {
  check_positions(mesh, x, "surface_area");
  double two_a = 0;
  for (const auto& t : mesh.triangles) two_a += (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]).norm();
  return 0.5 * two_a;
}

double winding_number(const TriangleMesh& mesh, const std::vector<Vec3>& x, const Vec3& p) {
  check_positions(mesh, x, "winding_number");
  // Solid angle of a triangle seen from p (Van Oosterom & Strackee 1983):
  //   tan(Omega / 2) = a . (b x c) / (|a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|),
  // a, b, c the vertices relative to p; atan2 keeps the quadrant, so |Omega| up to 2 pi is right.
  double omega = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3 a = x[t[0]] - p, b = x[t[1]] - p, c = x[t[2]] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    // p inside the triangle, in its plane: the solid angle is +-2 pi by the sign of a rounded
    // zero; count it as 0, the mean of the two sides (the winding number is then 1/2 on a face).
    if (num == 0 && den < 0) continue;
    omega += 2.0 * std::atan2(num, den);
  }
  return omega / (4.0 * std::numbers::pi);
}

}  // namespace bagdem
