// See include/bagdem/contact/sphere_triangle.hpp for the rule and why it has the agreement condition.
#include "bagdem/contact/sphere_triangle.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace bagdem {

namespace {

// Kind bits 3 (no feature has it) mark a hit to remove; the rule reads only triangle, feature and
// local of other hits, so marking as we go does not change later decisions.
constexpr std::uint32_t kDropped = 0xC0000000u;

// The hit of triangle t, or nullptr (hits ascending by triangle: a binary search; a sphere rarely
// has more than a few tens of hits).
const MeshHit* hit_of(const std::vector<MeshHit>& hits, std::uint32_t t) {
  const auto it =
      std::lower_bound(hits.begin(), hits.end(), t, [](const MeshHit& h, std::uint32_t tri) { return h.triangle < tri; });
  return it != hits.end() && it->triangle == t ? &*it : nullptr;
}

// Edge hit of triangle t on mesh edge e: kept when the edge's other triangle has no hit, reports
// the same edge from a higher triangle index (once per edge: the lowest triangle's hit is kept), or
// reports an end of the edge (rounding at the edge's ends). A face hit there (the documented rule),
// another edge or its third vertex (the agreement condition) drop it.
bool keep_edge(const TriangleMesh& mesh, const std::vector<MeshHit>& hits, std::uint32_t t, std::uint32_t e) {
  const auto& et = mesh.edge_triangles[e];
  const std::uint32_t other = et[0] == t ? et[1] : et[0];
  if (other == kNoTriangle) return true;
  const MeshHit* h = hit_of(hits, other);
  if (h == nullptr) return true;
  switch (h->hit.feature) {
    case Feature::Face:
      return false;
    case Feature::Edge:
      return mesh.triangle_edges[other][h->hit.local] == e && t < other;
    case Feature::Vertex: {
      const std::uint32_t u = mesh.triangles[other][h->hit.local];
      return u == mesh.edge_vertices[e][0] || u == mesh.edge_vertices[e][1];
    }
  }
  return false;
}

// Vertex hit of triangle t on mesh vertex v: kept when every triangle around v that has a hit
// reports v itself (a face hit or an edge hit on one of v's edges is the documented rule; any
// other feature, the agreement condition), and t is the lowest of them (once per vertex).
bool keep_vertex(const TriangleMesh& mesh, const std::vector<MeshHit>& hits, std::uint32_t t, std::uint32_t v) {
  for (std::uint32_t i = mesh.vertex_triangle_begin[v]; i < mesh.vertex_triangle_begin[v + 1]; ++i) {
    const std::uint32_t s = mesh.vertex_triangles[i];
    const MeshHit* h = hit_of(hits, s);
    if (h == nullptr) continue;
    if (h->hit.feature != Feature::Vertex || mesh.triangles[s][h->hit.local] != v) return false;
    if (s < t) return false;  // an earlier triangle reports v: keep that one
  }
  return true;
}

}  // namespace

void select_mesh_contacts(const TriangleMesh& mesh, std::vector<MeshHit>& hits) {
  assert(std::is_sorted(hits.begin(), hits.end(), [](const MeshHit& a, const MeshHit& b) { return a.triangle < b.triangle; }));
  for (MeshHit& h : hits) {
    switch (h.hit.feature) {
      case Feature::Face:
        h.key = feature_key(Feature::Face, h.triangle);
        break;
      case Feature::Edge: {
        const std::uint32_t e = mesh.triangle_edges[h.triangle][h.hit.local];
        h.key = keep_edge(mesh, hits, h.triangle, e) ? feature_key(Feature::Edge, e) : kDropped;
        break;
      }
      case Feature::Vertex: {
        const std::uint32_t v = mesh.triangles[h.triangle][h.hit.local];
        h.key = keep_vertex(mesh, hits, h.triangle, v) ? feature_key(Feature::Vertex, v) : kDropped;
        break;
      }
    }
  }
  // In-place compaction (no allocation: this runs per ball per step).
  std::size_t w = 0;
  for (std::size_t i = 0; i < hits.size(); ++i)
    if (hits[i].key != kDropped) {
      if (w != i) hits[w] = hits[i];
      ++w;
    }
  hits.resize(w);
}

void patch_labels(const Vec3* normals, std::size_t count, std::size_t* label) {
  constexpr double kPatchCos = 0.8660254037844387;  // cos 30 degrees
  for (std::size_t i = 0; i < count; ++i) label[i] = i;
  // Connected components of "normals within 30 degrees" (labels: the smallest index reached).
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t i = 0; i < count; ++i)
      for (std::size_t j = i + 1; j < count; ++j)
        if (label[i] != label[j] && normals[i].dot(normals[j]) >= kPatchCos) {
          label[i] = label[j] = std::min(label[i], label[j]);
          changed = true;
        }
  }
}

std::size_t join_patches(const Vec3* normals, const double* overlaps, std::size_t count, PatchContact* out) {
  count = std::min(count, kMaxPatchHits);
  std::size_t label[kMaxPatchHits], size[kMaxPatchHits], member[kMaxPatchHits][kPatchMembers];
  std::fill(size, size + count, std::size_t{0});
  patch_labels(normals, count, label);
  // Each patch's members, deepest first (the first of equals first).
  for (std::size_t i = 0; i < count; ++i) {
    std::size_t* m = member[label[i]];
    std::size_t& k = size[label[i]];
    std::size_t at = k;
    while (at > 0 && overlaps[i] > overlaps[m[at - 1]]) --at;
    if (at == kPatchMembers) continue;
    for (std::size_t j = std::min(k, kPatchMembers - 1); j > at; --j) m[j] = m[j - 1];
    m[at] = i;
    k = std::min(k + 1, kPatchMembers);
  }
  std::size_t n = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t* m = member[label[i]];
    if (m[0] != i) continue;
    PatchContact& c = out[n++];
    c.count = size[label[i]];
    std::copy(m, m + c.count, c.member);
    if (c.count > 1) {
      Vec3 nn[kPatchMembers];
      double d[kPatchMembers];
      for (std::size_t j = 0; j < c.count; ++j) nn[j] = normals[m[j]], d[j] = overlaps[m[j]];
      c.blend = blend_patch(nn, d, c.count);
    }
  }
  return n;
}

PatchBlend blend_patch(const Vec3* normals, const double* overlaps, std::size_t count) {
  static_assert(kPatchNorm == 8, "the powers below are written for p = 8");
  assert(count >= 2 && count <= kPatchMembers);
  // With r_i = delta_i / delta_0 <= 1 (the deepest first): delta = delta_0 S^(1/8), S = sum r_i^8.
  double r[kPatchMembers], S = 0;
  for (std::size_t i = 0; i < count; ++i) {
    r[i] = overlaps[i] / overlaps[0];
    const double r2 = r[i] * r[i], r4 = r2 * r2;
    S += r4 * r4;
  }
  const double root = std::sqrt(std::sqrt(std::sqrt(S)));  // S^(1/8)
  PatchBlend b{};
  b.overlap = overlaps[0] * root;
  Vec3 N(0, 0, 0);
  double sum_c = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const double q = r[i] / root, q2 = q * q, q4 = q2 * q2;  // delta_i / delta
    b.c[i] = q4 * q2 * q;                                     // q^7
    sum_c += b.c[i];
    N += b.c[i] * normals[i];
  }
  b.scale = N.norm();
  b.n = N / b.scale;  // the hits' normals are within 30 degrees of a chain: N is far from zero
  for (std::size_t i = 0; i < count; ++i) b.share[i] = b.c[i] / sum_c;
  return b;
}

}  // namespace bagdem
