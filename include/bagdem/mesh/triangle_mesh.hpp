// Triangulated surfaces. The bag's film (moving nodes) and rigid cavities read from STL files share
// this topology. Orientation: a triangle (a, b, c) is counter-clockwise seen from outside, so its
// normal (b - a) x (c - a) points out of the enclosed volume (for an open patch: away from the side
// the balls are on).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "bagdem/vec3.hpp"

namespace bagdem {

inline constexpr std::uint32_t kNoTriangle = 0xffffffffu;

struct TriangleMesh {
  std::vector<Vec3> vertices;                              // (unit: m)
  std::vector<std::array<std::uint32_t, 3>> triangles;     // vertex indices, outward orientation

  // Topology, filled by build_topology():
  std::vector<std::array<std::uint32_t, 2>> edge_vertices;   // unique edges, lower vertex index first
  std::vector<std::array<std::uint32_t, 2>> edge_triangles;  // the one or two triangles of each edge (kNoTriangle)
  std::vector<std::array<std::uint32_t, 3>> triangle_edges;  // edge k of a triangle joins its vertices k and (k+1)%3
  std::vector<std::uint32_t> vertex_triangle_begin;          // CSR: triangles around vertex v are
  std::vector<std::uint32_t> vertex_triangles;               //   vertex_triangles[begin[v] .. begin[v+1]), ascending
  std::vector<std::uint8_t> vertex_on_boundary;              // 1: an end of an edge with one triangle

  std::size_t size() const { return triangles.size(); }
  // Every edge has exactly two triangles (a closed surface).
  bool closed() const;
};

// Fills the topology. Throws std::invalid_argument for an edge shared by more than two triangles,
// for two triangles sharing an edge with inconsistent orientation, for a degenerate triangle
// (zero area or a repeated vertex) and for a vertex index out of range. Vertex, edge and triangle
// counts must stay below 2^30 (they are packed into feature keys with the feature kind). Vertices
// where two surface sheets touch at a point only (a "bow tie") are not detected.
void build_topology(TriangleMesh& mesh);

// Zero area to rounding: |(b - a) x (c - a)| <= 1e-12 L^2, L the longest edge (a sliver whose height
// is below 1e-12 of its length, or a repeated point). build_topology refuses such triangles and
// read_stl drops them.
bool degenerate_triangle(const Vec3& a, const Vec3& b, const Vec3& c);

// Volume enclosed by a closed, outward-oriented surface with vertex positions x (divergence
// theorem: sum over triangles of a . (b x c) / 6) (unit: m^3).
double enclosed_volume(const TriangleMesh& mesh, const std::vector<Vec3>& x);
// Total area (unit: m^2).
double surface_area(const TriangleMesh& mesh, const std::vector<Vec3>& x);

// Generalized winding number of point p: the sum of the signed solid angles of the triangles seen
// from p over 4 pi (Van Oosterom & Strackee, IEEE Trans. Biomed. Eng. 30, 1983). 1 inside a closed
// outward surface, 0 outside; near 1/2 on the surface.
double winding_number(const TriangleMesh& mesh, const std::vector<Vec3>& x, const Vec3& p);

}  // namespace bagdem
