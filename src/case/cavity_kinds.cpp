// Cavity kinds: each builds its walls from [cavity] keys. The table below is the only list.
//   box       min, max                   six inward planes
//   cylinder  center, axis, radius, length   a bore (inner cylinder) capped by two planes
//   planes    [[cavity.planes]] point, normal (into the cavity); bounds = box the particles stay in
//   stl       file, scale                a triangulated surface (closed; normals out of the cavity)
#include <cmath>
#include <filesystem>

#include "bagdem/case/load_case.hpp"
#include "bagdem/mesh/stl.hpp"

namespace bagdem {
namespace {

void box(const CaseReader& in, Scene& s, int material) {
  const Vec3 lo = in.vector("cavity.min", dim::length), hi = in.vector("cavity.max", dim::length);
  for (int k = 0; k < 3; ++k)
    if (!(hi[k] > lo[k])) in.fail("cavity.max", "every component must exceed cavity.min's");
  const char* axes = "xyz";
  for (int k = 0; k < 3; ++k) {
    Wall a, b;
    a.kind = b.kind = WallKind::Plane;
    a.material = b.material = material;
    a.point = lo;
    a.direction = Vec3::Unit(k);
    b.point = hi;
    b.direction = -Vec3::Unit(k);
    s.walls.push_back(a);
    s.walls.push_back(b);
    s.wall_names.push_back(std::string("box -") + axes[k]);
    s.wall_names.push_back(std::string("box +") + axes[k]);
  }
  s.cavity_lo = lo;
  s.cavity_hi = hi;
}

Vec3 axis_of(const CaseReader& in, const std::string& key) {
  const std::string a = in.has(key) && in.root().at_path(key).is_string() ? in.string(key) : "";
  if (a == "x") return Vec3::UnitX();
  if (a == "y") return Vec3::UnitY();
  if (a == "z") return Vec3::UnitZ();
  if (!a.empty()) in.fail(key, "must be \"x\", \"y\", \"z\" or a vector [ax, ay, az]");
  const Vec3 v = in.vector(key, dim::none, Vec3::UnitX());
  if (v.norm() == 0) in.fail(key, "must not be the zero vector");
  return v.normalized();
}

void cylinder(const CaseReader& in, Scene& s, int material) {
  const Vec3 c = in.vector("cavity.center", dim::length, Vec3::Zero());
  const Vec3 u = axis_of(in, "cavity.axis");
  const double R = in.quantity("cavity.radius", dim::length);
  const double L = in.quantity("cavity.length", dim::length);
  if (!(R > 0)) in.fail("cavity.radius", "must be > 0");
  if (!(L > 0)) in.fail("cavity.length", "must be > 0");
  s.walls = {{WallKind::Cylinder, c, u, R, material},
             {WallKind::Plane, c - 0.5 * L * u, u, 0, material},
             {WallKind::Plane, c + 0.5 * L * u, -u, 0, material}};
  s.wall_names = {"bore", "cap -axis", "cap +axis"};
  // Bounding box of a capped cylinder: extent along each world axis k is
  // L/2 |u_k| + R sqrt(1 - u_k^2).
  for (int k = 0; k < 3; ++k) {
    const double e = 0.5 * L * std::abs(u[k]) + R * std::sqrt(std::max(0.0, 1 - u[k] * u[k]));
    s.cavity_lo[k] = c[k] - e;
    s.cavity_hi[k] = c[k] + e;
  }
}

void planes(const CaseReader& in, Scene& s, int material) {
  const std::size_t n = in.array_size("cavity.planes");
  if (n == 0) in.fail("cavity.planes", "needs at least one [[cavity.planes]] with point and normal");
  if (n > 32) in.fail("cavity.planes", "has " + std::to_string(n) + " planes; at most 32 are allowed");
  for (std::size_t k = 0; k < n; ++k) {
    const std::string key = "cavity.planes." + std::to_string(k);
    Wall w;
    w.kind = WallKind::Plane;
    w.material = material;
    w.point = in.vector(key + ".point", dim::length);
    w.direction = in.vector(key + ".normal", dim::none);
    if (w.direction.norm() == 0) in.fail(key + ".normal", "must not be the zero vector");
    w.direction.normalize();
    s.walls.push_back(w);
    s.wall_names.push_back("plane " + std::to_string(k));
  }
  // Planes need not enclose anything: the bounds the particles must stay in are given.
  s.cavity_lo = in.vector("cavity.min", dim::length);
  s.cavity_hi = in.vector("cavity.max", dim::length);
}

// A rigid cavity of any shape from an STL file (normals pointing out of the cavity, away from the
// balls): balls touch its triangles (walls/mesh_wall.hpp). Bounds: the mesh's bounding box.
void stl(const CaseReader& in, Scene& s, int material) {
  const std::string path = in.file_path("cavity.file", s.case_dir);
  const double scale = in.quantity("cavity.scale", dim::length, 1.0);
  if (!(scale > 0)) in.fail("cavity.scale", "must be > 0: the length of one file unit (\"1 mm\" for a file in mm)");
  MeshWall w;
  w.name = "cavity.file = " + in.string("cavity.file");
  w.mesh = read_stl(path, scale);
  w.material = material;
  if (!w.mesh.closed())
    in.fail("cavity.file", "is an open surface; a cavity must be closed (every edge shared by two triangles)");
  if (!(enclosed_volume(w.mesh, w.mesh.vertices) > 0))
    in.fail("cavity.file", "has its normals pointing into the cavity (negative enclosed volume); they must point "
                           "out of it, away from the balls: flip the facets' orientation in the file");
  s.cavity_lo = s.cavity_hi = w.mesh.vertices[0];
  for (const Vec3& v : w.mesh.vertices) s.cavity_lo = s.cavity_lo.cwiseMin(v), s.cavity_hi = s.cavity_hi.cwiseMax(v);
  s.mesh_walls.push_back(std::move(w));
}

struct CavityKind {
  const char* name;
  void (*build)(const CaseReader&, Scene&, int);
};

const CavityKind kCavityKinds[] = {{"box", box}, {"cylinder", cylinder}, {"planes", planes}, {"stl", stl}};

}  // namespace

void resolve_cavity(const CaseReader& in, Scene& s, int material) {
  std::vector<std::string> names;
  for (const auto& k : kCavityKinds) names.emplace_back(k.name);
  s.cavity_kind = in.choice("cavity.kind", names, "box");
  for (const auto& k : kCavityKinds)
    if (s.cavity_kind == k.name) k.build(in, s, material);
  s.cavity_reference = in.vector("cavity.reference", dim::length, 0.5 * (s.cavity_lo + s.cavity_hi));
}

}  // namespace bagdem
