// Triangle meshes: topology (mesh/triangle_mesh.hpp), generated shapes (mesh/shapes.hpp) and STL
// files (mesh/stl.hpp).
//
// References and tolerances:
//   Topology: Euler characteristic V - E + F = 2 for closed genus-0 shapes (1 for a disc), exact;
//     every edge of a closed shape has two triangles; the maps agree with each other, exact.
//   Volume and area of inscribed polyhedra approach the analytic values from below with error
//     O(h^2): each 4-fold refinement of the triangle count cuts the error by > 3 (4 expected);
//     at ~2000 triangles within 1 % (sphere 4/3 pi r^3 and 4 pi r^2; capsule; ellipsoid 4/3 pi abc,
//     oblate spheroid area 2 pi a^2 (1 + (1 - e^2)/e atanh e); superellipsoid of exponent p:
//     V = 8 abc Gamma(1 + 1/p)^3 / Gamma(1 + 3/p)).
//   Quality, measured for targets 200..8000 (printed): smallest angle sphere 54.0, capsule 40.4,
//     pillow 35.0 degrees (bounds 50, 36, 30); largest/smallest area sphere 1.88, capsule 1.62,
//     pillow 2.10 (bounds 2.0, 1.8, 2.5); counts within a factor 1.5 of the target from 54 up,
//     within 10 % from 200 up for capsule and pillow (the sphere has 20 n^2).
//   Orientation: every triangle's normal points away from the centre (convex shapes); volume > 0.
//   Winding number: 1 inside, 0 outside for points 1 % of the size from the surface, to 1e-9.
//   STL: a 10 mm cube read with scale 0.1 has 8 vertices, 12 triangles, volume 1 and area 6 to
//     1e-12, the same from ASCII and binary; errors name the file (and the line for ASCII).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "bagdem/error.hpp"
#include "bagdem/mesh/shapes.hpp"
#include "bagdem/mesh/stl.hpp"
#include "bagdem/mesh/triangle_mesh.hpp"
#include "rng.hpp"
#include "support.hpp"

using namespace bagdem;
using bagdem::testing::Rng;
using bagdem::testing::TempDir;

namespace {

constexpr double kPi = std::numbers::pi;

// Checks the topology maps against each other and the triangles; returns V - E + F.
long check_topology(const TriangleMesh& m) {
  const std::size_t nv = m.vertices.size(), ne = m.edge_vertices.size(), nt = m.triangles.size();
  EXPECT_EQ(m.edge_triangles.size(), ne);
  EXPECT_EQ(m.triangle_edges.size(), nt);
  EXPECT_EQ(m.vertex_triangle_begin.size(), nv + 1);
  EXPECT_EQ(m.vertex_triangles.size(), 3 * nt);
  for (std::size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      const auto e = m.triangle_edges[t][k];
      const std::uint32_t a = m.triangles[t][k], b = m.triangles[t][(k + 1) % 3];
      EXPECT_EQ(m.edge_vertices[e][0], std::min(a, b));
      EXPECT_EQ(m.edge_vertices[e][1], std::max(a, b));
      EXPECT_TRUE(m.edge_triangles[e][0] == t || m.edge_triangles[e][1] == t);
    }
  for (std::size_t e = 0; e < ne; ++e) {
    EXPECT_LT(m.edge_vertices[e][0], m.edge_vertices[e][1]);
    if (m.edge_triangles[e][1] != kNoTriangle) {
      EXPECT_LT(m.edge_triangles[e][0], m.edge_triangles[e][1]);
    }
  }
  for (std::size_t v = 0; v < nv; ++v)
    for (auto i = m.vertex_triangle_begin[v]; i < m.vertex_triangle_begin[v + 1]; ++i) {
      const auto t = m.vertex_triangles[i];
      if (i > m.vertex_triangle_begin[v]) {
        EXPECT_LT(m.vertex_triangles[i - 1], t);
      }
      EXPECT_TRUE(m.triangles[t][0] == v || m.triangles[t][1] == v || m.triangles[t][2] == v);
    }
  return static_cast<long>(nv) - static_cast<long>(ne) + static_cast<long>(nt);
}

struct Quality {
  double min_angle = 180;  // (unit: degrees)
  double area_ratio = 0;   // largest / smallest triangle area
};

Quality quality(const TriangleMesh& m) {
  Quality q;
  double amin = 1e300, amax = 0;
  for (const auto& t : m.triangles) {
    const Vec3 x[3] = {m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]};
    for (int k = 0; k < 3; ++k) {
      const Vec3 u = x[(k + 1) % 3] - x[k], v = x[(k + 2) % 3] - x[k];
      q.min_angle = std::min(q.min_angle, std::atan2(u.cross(v).norm(), u.dot(v)) * 180 / kPi);
    }
    const double a = 0.5 * (x[1] - x[0]).cross(x[2] - x[0]).norm();
    amin = std::min(amin, a);
    amax = std::max(amax, a);
  }
  q.area_ratio = amax / amin;
  return q;
}

// Every triangle faces away from `centre` (for convex shapes around it).
void expect_outward(const TriangleMesh& m, const Vec3& centre) {
  int inward = 0;
  for (const auto& t : m.triangles) {
    const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    if (!((b - a).cross(c - a).dot((a + b + c) / 3 - centre) > 0)) ++inward;
  }
  EXPECT_EQ(inward, 0);
}

TriangleMesh tetrahedron() {
  TriangleMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

// Axis-aligned unit cube, 8 corners, 12 outward triangles, scaled by s.
struct Soup {
  std::vector<Vec3> corners;  // 3 per facet
};
Soup cube_soup(double s) {
  const Vec3 v[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                        {3, 7, 6}, {3, 6, 2}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};
  Soup soup;
  for (const auto& t : f)
    for (int k = 0; k < 3; ++k) soup.corners.push_back(s * v[t[k]]);
  return soup;
}

std::string ascii_stl(const Soup& s) {
  std::string out = "solid cube made by a test\n";
  char buf[200];
  for (std::size_t i = 0; i < s.corners.size(); i += 3) {
    const Vec3 n = (s.corners[i + 1] - s.corners[i]).cross(s.corners[i + 2] - s.corners[i]).normalized();
    std::snprintf(buf, sizeof buf, "  facet normal %g %g %g\n    outer loop\n", n.x(), n.y(), n.z());
    out += buf;
    for (int k = 0; k < 3; ++k) {
      const Vec3& x = s.corners[i + k];
      std::snprintf(buf, sizeof buf, "      vertex %.17g %.17g %.17g\n", x.x(), x.y(), x.z());
      out += buf;
    }
    out += "    endloop\n  endfacet\n";
  }
  return out + "endsolid cube made by a test\n";
}

std::string binary_stl(const Soup& s, const std::string& header = "binary cube") {
  std::string out(80, ' ');
  std::copy(header.begin(), header.end(), out.begin());
  auto put32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
  };
  auto putf = [&](double x) { put32(std::bit_cast<std::uint32_t>(static_cast<float>(x))); };
  put32(static_cast<std::uint32_t>(s.corners.size() / 3));
  for (std::size_t i = 0; i < s.corners.size(); i += 3) {
    const Vec3 n = (s.corners[i + 1] - s.corners[i]).cross(s.corners[i + 2] - s.corners[i]).normalized();
    for (int a = 0; a < 3; ++a) putf(n[a]);
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) putf(s.corners[i + k][a]);
    out.push_back(0);
    out.push_back(0);
  }
  return out;
}

void write_file(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream f(p, std::ios::binary);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// The message of the InputError that read_stl throws (fails the test when it throws none).
std::string stl_error(const std::string& path) {
  try {
    read_stl(path, 1.0);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "read_stl(" << path << ") did not throw";
  return "";
}

}  // namespace

// ------------------------------------------------------------------------------------------------
// Topology

TEST(MeshTopology, TetrahedronMapsAndMeasures) {
  TriangleMesh m = tetrahedron();
  build_topology(m);
  EXPECT_EQ(m.edge_vertices.size(), 6u);
  EXPECT_EQ(check_topology(m), 2);
  EXPECT_TRUE(m.closed());
  EXPECT_NEAR(enclosed_volume(m, m.vertices), 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(surface_area(m, m.vertices), 1.5 + std::sqrt(3.0) / 2, 1e-15);
  // Vertex 0 is in triangles 0, 1, 2; vertex 3 in 1, 2, 3.
  EXPECT_EQ(std::vector<std::uint32_t>(m.vertex_triangles.begin() + m.vertex_triangle_begin[0],
                                       m.vertex_triangles.begin() + m.vertex_triangle_begin[1]),
            (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_EQ(std::vector<std::uint32_t>(m.vertex_triangles.begin() + m.vertex_triangle_begin[3],
                                       m.vertex_triangles.begin() + m.vertex_triangle_begin[4]),
            (std::vector<std::uint32_t>{1, 2, 3}));
  // The volume is independent of where the body is, and turns negative when inverted.
  std::vector<Vec3> moved = m.vertices;
  for (Vec3& x : moved) x += Vec3(1e3, -2e3, 5e2);
  EXPECT_NEAR(enclosed_volume(m, moved), 1.0 / 6.0, 1e-12);
  TriangleMesh inv = tetrahedron();
  for (auto& t : inv.triangles) std::swap(t[1], t[2]);
  build_topology(inv);
  EXPECT_NEAR(enclosed_volume(inv, inv.vertices), -1.0 / 6.0, 1e-15);
  EXPECT_THROW(enclosed_volume(m, std::vector<Vec3>(3)), std::invalid_argument);
}

TEST(MeshTopology, OpenPatchHasBoundaryEdges) {
  TriangleMesh m = tetrahedron();
  m.triangles.pop_back();  // remove one face: a disc of 3 triangles
  build_topology(m);
  EXPECT_FALSE(m.closed());
  EXPECT_EQ(check_topology(m), 1);
  int boundary = 0;
  for (const auto& e : m.edge_triangles) boundary += e[1] == kNoTriangle;
  EXPECT_EQ(boundary, 3);
  EXPECT_FALSE(TriangleMesh{}.closed());
}

TEST(MeshTopology, RejectsNonManifoldEdge) {
  TriangleMesh m = tetrahedron();
  m.vertices.push_back(Vec3(1, 1, -1));
  m.triangles.push_back({0, 1, 4});  // a fin on edge (0, 1): three triangles there
  try {
    build_topology(m);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("edge (0, 1) is shared by 3 triangles"), std::string::npos) << e.what();
  }
}

TEST(MeshTopology, RejectsInconsistentOrientation) {
  TriangleMesh m = tetrahedron();
  std::swap(m.triangles[3][1], m.triangles[3][2]);  // one face turned inside out
  try {
    build_topology(m);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("inconsistent orientation"), std::string::npos) << e.what();
  }
}

TEST(MeshTopology, RejectsDegenerateTriangles) {
  auto message = [](TriangleMesh m) -> std::string {
    try {
      build_topology(m);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  TriangleMesh repeated = tetrahedron();
  repeated.triangles[0] = {0, 2, 2};
  EXPECT_NE(message(repeated).find("repeats a vertex"), std::string::npos);
  TriangleMesh flat = tetrahedron();
  flat.vertices.push_back(Vec3(0.5, 0.5, 0));  // on the segment 1-2: collinear with it
  flat.triangles.push_back({1, 4, 2});
  EXPECT_NE(message(flat).find("zero area"), std::string::npos);
  TriangleMesh range = tetrahedron();
  range.triangles[0][1] = 7;
  EXPECT_NE(message(range).find("out of range"), std::string::npos);
  EXPECT_TRUE(degenerate_triangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 1e-13, 0)));
  EXPECT_FALSE(degenerate_triangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 1e-10, 0)));
}

// ------------------------------------------------------------------------------------------------
// Shapes

TEST(MeshShapes, ClosedWithEulerCharacteristicTwo) {
  for (std::size_t target : {20, 80, 500, 2000}) {
    const TriangleMesh s = sphere_mesh(Vec3(0.1, 0.2, 0.3), 0.05, target);
    EXPECT_TRUE(s.closed());
    EXPECT_EQ(check_topology(s), 2);
    const TriangleMesh c = capsule_mesh(Vec3(0, 0, 0), Vec3(0, 1, 1), 0.02, 0.15, target);
    EXPECT_TRUE(c.closed());
    EXPECT_EQ(check_topology(c), 2);
    const TriangleMesh p = pillow_mesh(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.2, 0.1, 0.03), 4, target);
    EXPECT_TRUE(p.closed());
    EXPECT_EQ(check_topology(p), 2);
  }
  // A capsule as short as it can be (a sphere) and the coarsest ones.
  EXPECT_EQ(check_topology(capsule_mesh(Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0, 2.0, 100)), 2);
  EXPECT_EQ(check_topology(capsule_mesh(Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0, 3.0, 1)), 2);
  EXPECT_EQ(check_topology(pillow_mesh(Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(1, 1, 1), 2, 1)), 2);
}

TEST(MeshShapes, SphereVolumeAndAreaConverge) {
  const double r = 0.05;
  const double V = 4.0 / 3.0 * kPi * r * r * r, A = 4 * kPi * r * r;
  double prev_v = 1, prev_a = 1;
  std::printf("  sphere: triangles, volume error, area error\n");
  for (std::size_t target : {80, 320, 1280, 5120}) {  // n = 2, 4, 8, 16
    const TriangleMesh m = sphere_mesh(Vec3(1, 2, 3), r, target);
    ASSERT_EQ(m.size(), target);
    const double ev = enclosed_volume(m, m.vertices) / V - 1, ea = surface_area(m, m.vertices) / A - 1;
    std::printf("  %6zu %+.3e %+.3e\n", m.size(), ev, ea);
    EXPECT_LT(ev, 0);  // inscribed
    EXPECT_LT(ea, 0);
    EXPECT_LT(std::abs(ev), prev_v / 3);
    EXPECT_LT(std::abs(ea), prev_a / 3);
    prev_v = std::abs(ev);
    prev_a = std::abs(ea);
  }
  const TriangleMesh m = sphere_mesh(Vec3(1, 2, 3), r, 2000);
  EXPECT_EQ(m.size(), 2000u);  // n = 10
  EXPECT_LT(std::abs(enclosed_volume(m, m.vertices) / V - 1), 0.01);
  EXPECT_LT(std::abs(surface_area(m, m.vertices) / A - 1), 0.01);
}

TEST(MeshShapes, CapsuleVolumeAndAreaConverge) {
  const double r = 0.03, L = 0.2;
  const double V = kPi * r * r * (L - 2 * r) + 4.0 / 3.0 * kPi * r * r * r;
  const double A = 4 * kPi * r * r + 2 * kPi * r * (L - 2 * r);
  double prev_v = 1, prev_a = 1;
  std::printf("  capsule: triangles, volume error, area error\n");
  for (std::size_t target : {125, 500, 2000, 8000}) {
    const TriangleMesh m = capsule_mesh(Vec3(0.5, 0, -1), Vec3(1, 1, 0), r, L, target);
    const double ev = enclosed_volume(m, m.vertices) / V - 1, ea = surface_area(m, m.vertices) / A - 1;
    std::printf("  %6zu %+.3e %+.3e\n", m.size(), ev, ea);
    EXPECT_LT(std::abs(ev), prev_v / 3);
    EXPECT_LT(std::abs(ea), prev_a / 3);
    prev_v = std::abs(ev);
    prev_a = std::abs(ea);
    if (target == 2000) {
      EXPECT_LT(std::abs(ev), 0.01);
      EXPECT_LT(std::abs(ea), 0.01);
    }
  }
}

TEST(MeshShapes, EllipsoidPillowConverges) {
  // Oblate spheroid a = b = 0.1, c = 0.04 (p = 2): volume 4/3 pi a^2 c, area
  // 2 pi a^2 (1 + (1 - e^2)/e atanh(e)), e^2 = 1 - c^2/a^2. (Uniform triangles resolve a flatter
  // rim less well: at c = 0.025 the volume error is -1.06 % at 1990 triangles, -0.27 % at 7926.)
  const double a = 0.1, c = 0.04;
  const double e = std::sqrt(1 - c * c / (a * a));
  const double V = 4.0 / 3.0 * kPi * a * a * c, A = 2 * kPi * a * a * (1 + (1 - e * e) / e * std::atanh(e));
  double prev_v = 1, prev_a = 1;
  std::printf("  oblate spheroid pillow: triangles, volume error, area error\n");
  for (std::size_t target : {125, 500, 2000, 8000}) {
    const TriangleMesh m = pillow_mesh(Vec3(0, 0, 0.1), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(2 * a, 2 * a, 2 * c), 2, target);
    const double ev = enclosed_volume(m, m.vertices) / V - 1, ea = surface_area(m, m.vertices) / A - 1;
    std::printf("  %6zu %+.3e %+.3e\n", m.size(), ev, ea);
    EXPECT_LT(std::abs(ev), prev_v / 3);
    EXPECT_LT(std::abs(ea), prev_a / 3);
    prev_v = std::abs(ev);
    prev_a = std::abs(ea);
    if (target == 2000) {
      EXPECT_LT(std::abs(ev), 0.01);
      EXPECT_LT(std::abs(ea), 0.01);
    }
  }
  // A rounded box (p = 4, triaxial): V = 8 abc Gamma(5/4)^3 / Gamma(7/4).
  const Vec3 size(0.2, 0.1, 0.05);
  const double V4 = size.prod() * std::pow(std::tgamma(1.25), 3) / std::tgamma(1.75);
  const TriangleMesh box = pillow_mesh(Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(0, 0, 1), size, 4, 2000);
  const double ev4 = enclosed_volume(box, box.vertices) / V4 - 1;
  std::printf("  p = 4 pillow, %zu triangles: volume error %+.3e\n", box.size(), ev4);
  EXPECT_LT(ev4, 0);
  EXPECT_GT(ev4, -0.015);
}

TEST(MeshShapes, TriangleCountsNearTarget) {
  std::printf("  target: triangles of sphere, capsule, flat pillow, round pillow\n");
  double worst = 1;
  for (std::size_t target : {54, 60, 100, 150, 200, 350, 500, 1000, 2000, 5000}) {
    const std::size_t n[4] = {
        sphere_mesh(Vec3(0, 0, 0), 1, target).size(),
        capsule_mesh(Vec3(0, 0, 0), Vec3(0, 0, 1), 0.01, 0.08, target).size(),
        pillow_mesh(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.2, 0.1, 0.03), 4, target).size(),
        pillow_mesh(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.1, 0.1, 0.1), 2, target).size()};
    std::printf("  %5zu: %5zu %5zu %5zu %5zu\n", target, n[0], n[1], n[2], n[3]);
    for (std::size_t k = 0; k < 4; ++k) {
      const double ratio = static_cast<double>(n[k]) / static_cast<double>(target);
      worst = std::max({worst, ratio, 1 / ratio});
      EXPECT_LE(ratio, 1.5) << "shape " << k << " target " << target;
      EXPECT_GE(ratio, 1 / 1.5) << "shape " << k << " target " << target;
      if (k > 0 && target >= 200) {
        EXPECT_NEAR(ratio, 1, 0.1) << "shape " << k << " target " << target;
      }
    }
  }
  std::printf("  worst count / target (or inverse): %.3f\n", worst);
}

TEST(MeshShapes, TrianglesAreWellShaped) {
  struct Bound {
    const char* name;
    double min_angle, area_ratio;
  };
  const Bound bounds[3] = {{"sphere", 50, 2.0}, {"capsule", 36, 1.8}, {"pillow", 30, 2.5}};
  for (int shape = 0; shape < 3; ++shape) {
    Quality worst{180, 0};
    for (std::size_t target : {200, 500, 2000, 8000}) {
      std::vector<TriangleMesh> ms;
      if (shape == 0) ms.push_back(sphere_mesh(Vec3(0, 0, 0), 0.05, target));
      if (shape == 1) {
        ms.push_back(capsule_mesh(Vec3(0, 0, 0), Vec3(0, 0, 1), 0.03, 0.2, target));
        ms.push_back(capsule_mesh(Vec3(0, 0, 0), Vec3(1, 0, 0), 0.01, 0.02, target));  // a sphere
      }
      if (shape == 2 && target <= 2000) {
        ms.push_back(pillow_mesh(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.2, 0.1, 0.03), 2, target));
        ms.push_back(pillow_mesh(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.2, 0.2, 0.02), 4, target));
        ms.push_back(pillow_mesh(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.1, 0.1, 0.1), 8, target));
      }
      for (const auto& m : ms) {
        const Quality q = quality(m);
        worst.min_angle = std::min(worst.min_angle, q.min_angle);
        worst.area_ratio = std::max(worst.area_ratio, q.area_ratio);
      }
    }
    std::printf("  %-8s smallest angle %.1f degrees, largest/smallest area %.2f\n", bounds[shape].name,
                worst.min_angle, worst.area_ratio);
    EXPECT_GT(worst.min_angle, bounds[shape].min_angle) << bounds[shape].name;
    EXPECT_LT(worst.area_ratio, bounds[shape].area_ratio) << bounds[shape].name;
  }
}

TEST(MeshShapes, OutwardOriented) {
  const Vec3 c(0.3, -0.2, 0.1);
  for (std::size_t target : {20, 300, 2000}) {
    const TriangleMesh s = sphere_mesh(c, 0.05, target);
    expect_outward(s, c);
    EXPECT_GT(enclosed_volume(s, s.vertices), 0);
    const TriangleMesh k = capsule_mesh(c, Vec3(-1, 2, 0.5), 0.02, 0.1, target);
    expect_outward(k, c);
    EXPECT_GT(enclosed_volume(k, k.vertices), 0);
    const TriangleMesh p = pillow_mesh(c, Vec3(0, 0, 1), Vec3(1, 1, 0), Vec3(0.1, 0.06, 0.02), 3, target);
    expect_outward(p, c);
    EXPECT_GT(enclosed_volume(p, p.vertices), 0);
  }
}

TEST(MeshShapes, PillowFrameAndSize) {
  // Axis along z, side along x: semi-axes 0.1 along z, 0.05 along x, 0.02 along y (= z cross x).
  const Vec3 c(1, 2, 3);
  const TriangleMesh p = pillow_mesh(c, Vec3(0, 0, 2), Vec3(1, 0, 0.3), Vec3(0.2, 0.1, 0.04), 4, 2000);
  Vec3 lo = p.vertices[0], hi = p.vertices[0];
  for (const Vec3& x : p.vertices) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const Vec3 half = 0.5 * (hi - lo);
  EXPECT_NEAR(half.z(), 0.1, 0.002);
  EXPECT_NEAR(half.x(), 0.05, 0.001);
  EXPECT_NEAR(half.y(), 0.02, 0.0005);
  EXPECT_NEAR((0.5 * (hi + lo) - c).norm(), 0, 1e-3);
  // Every vertex on the surface.
  double worst = 0;
  for (const Vec3& x : p.vertices) {
    const Vec3 q = x - c;
    const double f = std::pow(std::abs(q.z() / 0.1), 4) + std::pow(std::abs(q.x() / 0.05), 4) + std::pow(std::abs(q.y() / 0.02), 4);
    worst = std::max(worst, std::abs(f - 1));
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(MeshShapes, WindingNumberInsideOutside) {
  Rng rng(7);
  const Vec3 c(0.01, 0.02, -0.03);
  const double r = 0.05;
  const TriangleMesh s = sphere_mesh(c, r, 2000);
  // Capsule along z: the points within r of the segment between the cap centres c -+ (0, 0, r).
  const TriangleMesh k = capsule_mesh(c, Vec3(0, 0, 1), r, 4 * r, 2000);
  double worst = 0;
  for (int i = 0; i < 100; ++i) {
    const Vec3 d = rng.unit();
    const Vec3 radial = Vec3(d.x(), d.y(), 0).normalized();
    const Vec3 on_axis = c + Vec3(0, 0, rng.uniform(-r, r));
    const Vec3 cap_centre = c + Vec3(0, 0, d.z() > 0 ? r : -r);
    for (double f : {0.99, 1.01}) {
      const double expected = f < 1 ? 1.0 : 0.0;
      worst = std::max(worst, std::abs(winding_number(s, s.vertices, c + f * r * d) - expected));
      worst = std::max(worst, std::abs(winding_number(k, k.vertices, on_axis + f * r * radial) - expected));
      worst = std::max(worst, std::abs(winding_number(k, k.vertices, cap_centre + f * r * d) - expected));
    }
  }
  std::printf("  worst |winding number - (1 or 0)| at 1 %% of the radius from the surface: %.2e\n", worst);
  EXPECT_LT(worst, 1e-9);
  // Exactly on a face (in its plane, inside it): one half; far away: 0.
  TriangleMesh t = tetrahedron();
  build_topology(t);
  EXPECT_NEAR(winding_number(t, t.vertices, Vec3(0.25, 0.25, 0)), 0.5, 1e-12);
  EXPECT_NEAR(winding_number(t, t.vertices, Vec3(0.1, 0.1, 0.1)), 1.0, 1e-12);
  EXPECT_NEAR(winding_number(t, t.vertices, Vec3(0.25, 0.25, -1e-9)), 0.0, 1e-12);
  EXPECT_NEAR(winding_number(t, t.vertices, Vec3(50, -30, 20)), 0.0, 1e-12);
}

TEST(MeshShapes, RectangleSheet) {
  const TriangleMesh m = rectangle_mesh(Vec3(1, 2, 3), 0.4, 0.2, 4, 3);
  EXPECT_EQ(m.size(), 24u);
  EXPECT_EQ(m.vertices.size(), 20u);
  EXPECT_FALSE(m.closed());
  EXPECT_EQ(check_topology(m), 1);
  int boundary = 0;
  for (const auto& e : m.edge_triangles) boundary += e[1] == kNoTriangle;
  EXPECT_EQ(boundary, 2 * (4 + 3));
  EXPECT_NEAR(surface_area(m, m.vertices), 0.08, 1e-15);
  for (const auto& t : m.triangles) {
    const Vec3 n = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
    EXPECT_GT(n.z(), 0);
    EXPECT_EQ(m.vertices[t[0]].z(), 3.0);
  }
  // Alternating diagonals: corner (0, 0) is on its cell's diagonal (2 triangles), corner (0, 3),
  // in a cell of the same parity, is not (1 triangle); corner (4, 0), in a cell of the other
  // parity, is again (2).
  auto fan = [&](std::size_t v) { return m.vertex_triangle_begin[v + 1] - m.vertex_triangle_begin[v]; };
  EXPECT_EQ(fan(0), 2u);
  EXPECT_EQ(fan(15), 1u);
  EXPECT_EQ(fan(4), 2u);
}

TEST(MeshShapes, RejectsBadDimensions) {
  EXPECT_THROW(sphere_mesh(Vec3(0, 0, 0), 0, 100), std::invalid_argument);
  EXPECT_THROW(capsule_mesh(Vec3(0, 0, 0), Vec3(0, 0, 1), 0.1, 0.15, 100), std::invalid_argument);
  EXPECT_THROW(capsule_mesh(Vec3(0, 0, 0), Vec3(0, 0, 0), 0.1, 0.3, 100), std::invalid_argument);
  EXPECT_THROW(pillow_mesh(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(1, 1, 1), 2, 100), std::invalid_argument);
  EXPECT_THROW(pillow_mesh(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 1), 2, 100), std::invalid_argument);
  EXPECT_THROW(pillow_mesh(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 1), 1.5, 100), std::invalid_argument);
  EXPECT_THROW(rectangle_mesh(Vec3(0, 0, 0), 1, 1, 0, 1), std::invalid_argument);
}

// ------------------------------------------------------------------------------------------------
// STL

TEST(Stl, AsciiAndBinaryCubeAgree) {
  TempDir dir;
  const Soup cube = cube_soup(10);  // 10 mm
  write_file(dir.path / "cube_ascii.stl", ascii_stl(cube));
  write_file(dir.path / "cube_binary.stl", binary_stl(cube));
  // A binary header may begin with "solid" too: the size decides.
  write_file(dir.path / "cube_solid_header.stl", binary_stl(cube, "solid but binary"));
  std::vector<TriangleMesh> ms;
  for (const char* name : {"cube_ascii.stl", "cube_binary.stl", "cube_solid_header.stl"}) {
    std::size_t dropped = 99;
    ms.push_back(read_stl((dir.path / name).string(), 0.1, &dropped));
    const TriangleMesh& m = ms.back();
    EXPECT_EQ(dropped, 0u) << name;
    EXPECT_EQ(m.vertices.size(), 8u) << name;
    EXPECT_EQ(m.size(), 12u) << name;
    EXPECT_TRUE(m.closed()) << name;
    EXPECT_EQ(check_topology(m), 2) << name;
    EXPECT_NEAR(enclosed_volume(m, m.vertices), 1.0, 1e-12) << name;
    EXPECT_NEAR(surface_area(m, m.vertices), 6.0, 1e-12) << name;
  }
  EXPECT_EQ(ms[0].triangles, ms[1].triangles);
  EXPECT_EQ(ms[1].triangles, ms[2].triangles);
  for (std::size_t v = 0; v < 8; ++v) EXPECT_LT((ms[0].vertices[v] - ms[1].vertices[v]).norm(), 1e-15);
}

TEST(Stl, KeepsTheFilesOrientation) {
  TempDir dir;
  Soup cube = cube_soup(1);
  for (std::size_t i = 0; i < cube.corners.size(); i += 3) std::swap(cube.corners[i + 1], cube.corners[i + 2]);
  write_file(dir.path / "inside_out.stl", ascii_stl(cube));
  const TriangleMesh m = read_stl((dir.path / "inside_out.stl").string(), 1.0);
  EXPECT_NEAR(enclosed_volume(m, m.vertices), -1.0, 1e-15);
}

TEST(Stl, WeldsWithinToleranceOnly) {
  TempDir dir;
  // The bounding-box diagonal is sqrt(3): tolerance 1.7e-9. A corner copy moved by 1e-10 welds;
  // moved by 1e-7 it stays a separate vertex and the surface opens there.
  Soup near = cube_soup(1), far = cube_soup(1);
  near.corners[0] += Vec3(1e-10, -1e-10, 0);
  far.corners[0] += Vec3(1e-7, 0, 0);
  write_file(dir.path / "near.stl", ascii_stl(near));
  write_file(dir.path / "far.stl", ascii_stl(far));
  const TriangleMesh a = read_stl((dir.path / "near.stl").string(), 1.0);
  EXPECT_EQ(a.vertices.size(), 8u);
  EXPECT_TRUE(a.closed());
  const TriangleMesh b = read_stl((dir.path / "far.stl").string(), 1.0);
  EXPECT_EQ(b.vertices.size(), 9u);
  EXPECT_FALSE(b.closed());
}

TEST(Stl, DropsDegenerateFacets) {
  TempDir dir;
  Soup cube = cube_soup(1);
  for (const Vec3& x : {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0)}) cube.corners.push_back(x);        // repeated corner
  for (const Vec3& x : {Vec3(0, 0, 0), Vec3(0.5, 0, 0), Vec3(1, 0, 0)}) cube.corners.push_back(x);      // collinear
  write_file(dir.path / "with_slivers.stl", binary_stl(cube));
  std::size_t dropped = 0;
  const TriangleMesh m = read_stl((dir.path / "with_slivers.stl").string(), 1.0, &dropped);
  EXPECT_EQ(dropped, 2u);
  EXPECT_EQ(m.size(), 12u);
  EXPECT_EQ(m.vertices.size(), 8u);  // the collinear facet's midpoint is no vertex of the surface
  EXPECT_TRUE(m.closed());
}

TEST(Stl, ErrorsNameTheFile) {
  TempDir dir;
  const std::string missing = (dir.path / "missing.stl").string();
  std::string msg = stl_error(missing);
  EXPECT_NE(msg.find(missing), std::string::npos) << msg;
  EXPECT_NE(msg.find("cannot open"), std::string::npos) << msg;

  std::string bytes = binary_stl(cube_soup(1));
  bytes.resize(bytes.size() - 30);
  const std::string truncated = (dir.path / "truncated.stl").string();
  write_file(truncated, bytes);
  msg = stl_error(truncated);
  EXPECT_NE(msg.find(truncated), std::string::npos) << msg;
  EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
  EXPECT_NE(msg.find("12 facets"), std::string::npos) << msg;

  const std::string garbage = (dir.path / "garbage.stl").string();
  write_file(garbage, "solid broken\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 zero\n");
  msg = stl_error(garbage);
  EXPECT_NE(msg.find(garbage + ": line 4:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'zero'"), std::string::npos) << msg;

  const std::string early_end = (dir.path / "early_end.stl").string();
  write_file(early_end, "solid broken\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n\n");
  msg = stl_error(early_end);
  EXPECT_NE(msg.find(early_end + ": line 5:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("end of the file"), std::string::npos) << msg;

  const std::string text = (dir.path / "text.stl").string();
  write_file(text, "hello");
  msg = stl_error(text);
  EXPECT_NE(msg.find(text), std::string::npos) << msg;
  EXPECT_NE(msg.find("not an STL file"), std::string::npos) << msg;

  const std::string empty = (dir.path / "empty.stl").string();
  write_file(empty, "solid nothing\nendsolid nothing\n");
  msg = stl_error(empty);
  EXPECT_NE(msg.find("no facets"), std::string::npos) << msg;
}

TEST(Stl, RefusesNonManifoldSurface) {
  TempDir dir;
  Soup cube = cube_soup(1);
  // A fin on the bottom edge (0,0,0)-(1,0,0): a third facet on that edge.
  for (const Vec3& x : {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, -1, -1)}) cube.corners.push_back(x);
  const std::string path = (dir.path / "fin.stl").string();
  write_file(path, ascii_stl(cube));
  const std::string msg = stl_error(path);
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("not a manifold surface"), std::string::npos) << msg;
  EXPECT_NE(msg.find("shared by 3 triangles"), std::string::npos) << msg;
}
