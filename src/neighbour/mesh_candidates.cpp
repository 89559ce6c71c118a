// Sphere -> triangle candidate lists (neighbour/mesh_candidates.hpp).
#include "bagdem/neighbour/mesh_candidates.hpp"

#include <algorithm>
#include <cmath>

#include "bagdem/contact/sphere_triangle.hpp"
#include "bagdem/parallel.hpp"

namespace bagdem {
namespace {

std::uint64_t cell_key(long x, long y, long z) {
  // 21 bits per axis, offset so negative cells pack too.
  const auto u = [](long c) { return static_cast<std::uint64_t>(c + (1L << 20)) & 0x1fffffu; };
  return (u(x) << 42) | (u(y) << 21) | u(z);
}

}  // namespace

void find_mesh_candidates(const TriangleMesh& mesh, const std::vector<Vec3>& vertices,
                          const std::vector<Vec3>& centres, const std::vector<double>& radius, const Vec3& shift,
                          double reach, double skin, MeshCandidates& out) {
  const std::size_t ns = centres.size(), nt = mesh.triangles.size();
  out.begin.assign(ns + 1, 0);
  out.triangle.clear();
  if (ns == 0 || nt == 0) return;
  double rmax = 0;
  for (double r : radius) rmax = std::max(rmax, r);
  const double cut = rmax + reach + skin;  // largest distance at which a triangle is a candidate
  const double h = 2 * cut;                 // cell size
  auto cell = [h](double c) { return static_cast<long>(std::floor(c / h)); };

  // (cell, triangle) entries for every cell the inflated bounding box of a triangle overlaps.
  auto& entries = out.cells;
  entries.clear();
  for (std::uint32_t t = 0; t < nt; ++t) {
    const auto& tri = mesh.triangles[t];
    Vec3 lo = vertices[tri[0]], hi = lo;
    for (int k = 1; k < 3; ++k) {
      lo = lo.cwiseMin(vertices[tri[k]]);
      hi = hi.cwiseMax(vertices[tri[k]]);
    }
    for (long x = cell(lo.x() - cut); x <= cell(hi.x() + cut); ++x)
      for (long y = cell(lo.y() - cut); y <= cell(hi.y() + cut); ++y)
        for (long z = cell(lo.z() - cut); z <= cell(hi.z() + cut); ++z) entries.emplace_back(cell_key(x, y, z), t);
  }
  std::sort(entries.begin(), entries.end());

  // Each sphere: the triangles of its cell, kept when truly within reach + skin (ascending, since
  // entries of one cell are sorted by triangle). Two passes, count then fill, into the CSR.
  auto visit = [&](std::size_t i, auto&& keep) {
    const Vec3 c = centres[i] - shift;
    const std::uint64_t key = cell_key(cell(c.x()), cell(c.y()), cell(c.z()));
    auto it = std::lower_bound(entries.begin(), entries.end(), std::make_pair(key, std::uint32_t{0}));
    const double reach_i = radius[i] + reach + skin;
    for (; it != entries.end() && it->first == key; ++it) {
      const auto& tri = mesh.triangles[it->second];
      const TriangleHit hit = closest_point_on_triangle(c, vertices[tri[0]], vertices[tri[1]], vertices[tri[2]]);
      if (hit.distance2 < reach_i * reach_i) keep(it->second);
    }
  };
  parallel_for(ns, [&](std::size_t i) {
    std::uint32_t n = 0;
    visit(i, [&n](std::uint32_t) { ++n; });
    out.begin[i + 1] = n;
  });
  for (std::size_t i = 0; i < ns; ++i) out.begin[i + 1] += out.begin[i];
  out.triangle.resize(out.begin[ns]);
  parallel_for(ns, [&](std::size_t i) {
    std::uint32_t at = out.begin[i];
    visit(i, [&](std::uint32_t t) { out.triangle[at++] = t; });
  });
}

}  // namespace bagdem
