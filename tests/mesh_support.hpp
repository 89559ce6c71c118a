// Test support for triangulated walls: flat floors made from rectangle_mesh with the orientation an
// STL wall needs (normals away from the balls), closed boxes as triangle soups, and ASCII STL text.
#pragma once
#include <array>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "bagdem/mesh/shapes.hpp"
#include "bagdem/mesh/triangle_mesh.hpp"
#include "bagdem/vec3.hpp"
#include "case_texts.hpp"

namespace bagdem::testing {

// A flat floor in the plane z = centre.z, lx by ly, nx by ny cells (two right triangles each,
// alternating diagonals), balls above it: rectangle_mesh turned over so its normals point along -z
// (an STL wall's normals point away from the balls).
inline TriangleMesh floor_mesh(const Vec3& centre, double lx, double ly, std::size_t nx, std::size_t ny) {
  const TriangleMesh up = rectangle_mesh(centre, lx, ly, nx, ny);
  TriangleMesh m;
  m.vertices = up.vertices;
  m.triangles = up.triangles;
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  build_topology(m);
  return m;
}

using Soup = std::vector<std::array<Vec3, 3>>;

// The inner surface of the box [lo, hi] as a cavity wall: each face cut into n x n cells of two
// triangles, normals pointing out of the box (out of the cavity, away from the balls inside).
inline Soup box_soup(const Vec3& lo, const Vec3& hi, int n) {
  Soup s;
  for (int k = 0; k < 3; ++k)
    for (int side : {-1, 1}) {
      const int a = (k + 1) % 3, b = (k + 2) % 3;  // e_a x e_b = e_k
      // Outward normal side * e_k: walk (a, b) for +, (b, a) for -.
      const int u = side > 0 ? a : b, v = side > 0 ? b : a;
      auto point = [&](int i, int j) {
        Vec3 p;
        p[k] = side > 0 ? hi[k] : lo[k];
        p[u] = lo[u] + (hi[u] - lo[u]) * i / n;
        p[v] = lo[v] + (hi[v] - lo[v]) * j / n;
        return p;
      };
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const Vec3 p00 = point(i, j), p10 = point(i + 1, j), p11 = point(i + 1, j + 1), p01 = point(i, j + 1);
          s.push_back({p00, p10, p11});
          s.push_back({p00, p11, p01});
        }
    }
  return s;
}

inline Soup soup_of(const TriangleMesh& m) {
  Soup s;
  for (const auto& t : m.triangles) s.push_back({m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]});
  return s;
}

// ASCII STL with coordinates multiplied by `factor` (e.g. 1000 for a file in millimetres), printed
// to 17 significant digits (exact round trip).
inline std::string ascii_stl(const Soup& s, double factor = 1.0, const std::string& name = "test") {
  std::string out = "solid " + name + "\n";
  char line[160];
  for (const auto& t : s) {
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
    std::snprintf(line, sizeof line, "  facet normal %.9g %.9g %.9g\n    outer loop\n", n.x(), n.y(), n.z());
    out += line;
    for (const Vec3& p : t) {
      std::snprintf(line, sizeof line, "      vertex %.17g %.17g %.17g\n", factor * p.x(), factor * p.y(), factor * p.z());
      out += line;
    }
    out += "    endloop\n  endfacet\n";
  }
  return out + "endsolid " + name + "\n";
}

// 10 steel balls (2 GPa, 4 mm) in a cavity read from the STL file `file` with `scale` (none when
// empty), for 1 ms without gravity; e 0.5.
inline std::string stl_case(const std::string& file, const Value& scale = "1 mm") {
  return CaseText()
      .set("simulation", "duration", "1 ms")
      .steel("2 GPa")
      .interactions(0.5)
      .stl("steel", file, scale)
      .balls("balls", "steel", "4 mm", 10);
}

}  // namespace bagdem::testing
