// Sphere against a triangulated surface: the closest point of a triangle and which feature of it
// (face, edge or vertex) that point lies on, and the rule that makes one contact per feature of a
// mesh (no double counting where triangles share an edge or a vertex).
// Layer 2 of 3 (neighbour search -> contact geometry -> contact law); used by the film of a bag and
// by rigid STL cavities alike.
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

#include "bagdem/contact/lanes.hpp"
#include "bagdem/mesh/triangle_mesh.hpp"
#include "bagdem/vec3.hpp"

namespace bagdem {

enum class Feature : std::uint8_t { Face = 0, Edge = 1, Vertex = 2 };

// Closest point of a triangle to a point.
struct TriangleHit {
  Vec3 point;          // closest point of the triangle (unit: m)
  Vec3 weights;        // its barycentric weights on the triangle's vertices (sum 1, each in [0, 1])
  double distance2;    // squared distance from the query point (unit: m^2)
  Feature feature;     // where the closest point lies: inside the face, on an edge, at a vertex
  std::uint8_t local;  // Edge: k (vertices k and (k+1)%3); Vertex: k; Face: 0
};

// Closest point of triangle (a, b, c) to p by Voronoi regions (Ericson, Real-Time Collision
// Detection, 2005, sec. 5.1.5). A closest point on an edge has exactly zero weight on the opposite
// vertex; at a vertex, weight 1 on it. Inline: it runs for every ball near every film triangle,
// every step.
//
// The region tests are Ericson's, in his order (vertex a, vertex b, edge ab, vertex c, edge ca,
// edge bc, face), with d1..d6 the projections of p - a, p - b, p - c on ab and ac and
// va, vb, vc the face's barycentric numerators (signed areas times |n|^2). Each edge case divides
// by |edge|^2 (d1 - d3 = |ab|^2 etc.), which is > 0 for any non-degenerate triangle; the face
// weights are clamped at 0 so that rounding at a region boundary cannot give a negative weight.
// A degenerate (zero-area) triangle never reaches the face case in exact arithmetic; should it
// by rounding, the nearest-vertex fallback keeps the result finite.
BAGDEM_INLINE TriangleHit closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  TriangleHit h;
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  auto vertex = [&](const Vec3& q, std::uint8_t k) {
    h.point = q;
    h.weights = Vec3::Zero();
    h.weights[k] = 1.0;
    h.feature = Feature::Vertex;
    h.local = k;
    h.distance2 = (p - q).squaredNorm();
    return h;
  };
  auto edge = [&](const Vec3& q0, const Vec3& e, double t, std::uint8_t k) {
    // Edge k from vertex k to vertex (k + 1) % 3, closest point q0 + t e.
    h.point = q0 + t * e;
    h.weights = Vec3::Zero();
    h.weights[k] = 1.0 - t;
    h.weights[(k + 1) % 3] = t;
    h.feature = Feature::Edge;
    h.local = k;
    h.distance2 = (p - h.point).squaredNorm();
    return h;
  };
  if (d1 <= 0 && d2 <= 0) return vertex(a, 0);
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return vertex(b, 1);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return edge(a, ab, d1 / (d1 - d3), 0);
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return vertex(c, 2);
  const double vb = d5 * d2 - d1 * d6;
  // Edge ca is edge 2 (from c to a): t runs from c, 1 - t from a.
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return edge(c, a - c, d6 / (d6 - d2), 2);
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return edge(b, c - b, (d4 - d3) / ((d4 - d3) + (d5 - d6)), 1);
  const double wa = std::max(va, 0.0), wb = std::max(vb, 0.0), wc = std::max(vc, 0.0);
  const double sum = wa + wb + wc;
  if (!(sum > 0)) [[unlikely]] {
    const double da = ap.squaredNorm(), db = bp.squaredNorm(), dc = cp.squaredNorm();
    return da <= db && da <= dc ? vertex(a, 0) : db <= dc ? vertex(b, 1) : vertex(c, 2);
  }
  const double inv = 1.0 / sum;
  const double v = wb * inv, w = wc * inv;
  h.weights = Vec3(wa * inv, v, w);  // each >= 0 exactly; the sum is 1 to rounding
  h.point = a + v * ab + w * ac;
  h.feature = Feature::Face;
  h.local = 0;
  h.distance2 = (p - h.point).squaredNorm();
  return h;
}

// Squared distance from p to each of kLanes triangles (a, b, c), without branches: the face's
// plane where p projects inside the triangle, else the nearest of the three edges (each a segment,
// its parameter clamped to [0, 1]). The same distance as closest_point_on_triangle to within a few
// ulps of the coordinates' scale, so it serves to pass over triangles far beyond a contact's reach
// before the exact test (surface_features.hpp). A degenerate triangle gives NaN.
BAGDEM_INLINE Lanes triangle_distance2(const Lanes3& p, const Lanes3& a, const Lanes3& b, const Lanes3& c) {
  const Lanes3 ab = b - a, bc = c - b, ca = a - c, ap = p - a, bp = p - b, cp = p - c;
  auto segment2 = [](const Lanes3& qp, const Lanes3& e) {
    const Lanes t = min_of(max_of(dot(qp, e) / dot(e, e), splat<Lanes>(0)), splat<Lanes>(1));
    const Lanes3 r = qp - t * e;
    return dot(r, r);
  };
  const Lanes edge2 = min_of(min_of(segment2(ap, ab), segment2(bp, bc)), segment2(cp, ca));
  const Lanes3 n = cross(ab, bc);
  const Lanes s = dot(n, ap);
  const Lanes plane2 = s * s / dot(n, n);
  // Inside: p's projection is on the inner side of every edge.
  const LanesMask inside = (dot(cross(ab, ap), n) >= 0) & (dot(cross(bc, bp), n) >= 0) & (dot(cross(ca, cp), n) >= 0);
  return select(inside, plane2, edge2);
}

// A feature of a mesh as one key: triangle, edge or vertex index with the kind in the top 2 bits.
BAGDEM_INLINE std::uint32_t feature_key(Feature f, std::uint32_t index) {
  return (static_cast<std::uint32_t>(f) << 30) | index;
}

struct MeshHit {
  std::uint32_t triangle;  // triangle the hit was found on
  std::uint32_t key;       // feature_key of the feature (global edge or vertex index for Edge/Vertex)
  TriangleHit hit;
};

// The one-contact-per-feature rule for one sphere against one mesh. `hits` holds the closest points
// of every triangle within contact reach (at most one per triangle), in ascending triangle order;
// on return it holds the contacts to apply, in the same order:
//   - every face hit;
//   - an edge hit once per edge, and only if no triangle of that edge has a face hit;
//   - a vertex hit once per vertex, and only if no triangle around it has a face hit and none of
//     its edges has an edge hit;
//   - and (agreement) an edge or vertex hit only if every other triangle holding that edge or
//     vertex, where it has a hit, reports the same feature (for an edge, one of its two ends also
//     agrees: the two triangles may round the same point to the end).
// Why the agreement condition: the first three rules alone do not give one contact on a flat
// triangulation. A triangle that does not hold the sphere's foot point still has its own closest
// point, on an edge or vertex away from the foot, and nothing in those rules removes it unless a
// triangle of that feature has the face hit. E.g. rectangle_mesh(Vec3(0, 0, 0), 1, 1, 10, 10),
// sphere radius 0.1, centre (0.2468, -0.0895, 0.0117): a face hit at 0.0117 and four edge hits at 0.047 to 0.097
// survive; for centres drawn uniformly over the middle of that sheet at heights 0.01 to 0.09, 94 %
// keep more than one contact.
// A feature is the sphere's closest feature (its centre lies in the feature's Voronoi region
// relative to the surrounding triangles) exactly when every triangle holding it finds its closest
// point there; a triangle that disagrees has a point strictly nearer, so the dropped hit is never
// the nearest contact, and the nearest hit in the list always survives (in exact arithmetic).
// On a flat triangulation a sphere thus always has exactly one contact, the same as with the plane;
// in a concave corner each face touched keeps its face contact.
// Fills each kept hit's key from the mesh topology (build_topology must have run). Allocation-free:
// decides in place (lookups of other triangles' hits by binary search), then compacts.
void select_mesh_contacts(const TriangleMesh& mesh, std::vector<MeshHit>& hits);

// One contact of the law per patch (its damping and friction; the elastic force of a sphere against
// a triangulated surface is the Euler sum over the features, step/surface_features.hpp,
// euler_terms, which counts no contacts). Hits of a sphere on one surface whose contact normals are
// within 30 degrees of each other, directly or through a chain of such hits, form a patch
// (patch_labels: label[i] is the smallest index of hit i's patch). A triangulation of a smooth
// surface meets a ball in one patch: its shallow folds (a capsule's ring chords, a film's gentle
// wrinkles) would otherwise give the ball two dampers and two friction springs where the surface
// has one contact. Faces meeting at a real corner (a box's walls, a film wrapped tightly round a
// ball) keep a contact each.
void patch_labels(const Vec3* normals, std::size_t count, std::size_t* label);

// A patch's hits joined into one contact: the p-norm of their overlaps,
//   delta = (sum_i delta_i^p)^(1/p),  p = kPatchNorm,
// the hit's own overlap when the patch has one and at most 2^(1/p) (9%) above the deepest; its
// normal, the direction of sum_i c_i n_i with c_i = d delta / d delta_i = (delta_i/delta)^(p-1);
// and each hit's share c_i / sum c of the law's force, of the contact point's velocity and of its
// mobility. A hit half as deep as the deepest gets 1/128. (Why its U(delta) is not the elastic
// energy: it jumps where two hits' normals cross the 30 degrees and where a hit is born at positive
// overlap; docs/bag.md, Model.) The joined contact takes the patch's kPatchMembers deepest hits.
inline constexpr int kPatchNorm = 8;
inline constexpr std::size_t kPatchMembers = 3;
struct PatchBlend {
  double overlap;    // the joined overlap (unit: m)
  Vec3 n;            // unit direction of sum_i c_i n_i: the joined contact's normal
  double scale;      // |sum_i c_i n_i|: the normal force along n is U'(delta) scale
  double c[kPatchMembers];      // d delta / d delta_i
  double share[kPatchMembers];  // c_i / sum c: where the tangential force and the velocities are taken
};
// `count` (2..kPatchMembers) hits, deepest first (overlaps > 0).
PatchBlend blend_patch(const Vec3* normals, const double* overlaps, std::size_t count);

// The contacts of `count` hits (at most kMaxPatchHits are read): one per patch, in the order of
// each patch's deepest hit (the first of equals), its members the patch's kPatchMembers deepest
// (indices into the hits, deepest first) and, for more than one, their join.
inline constexpr std::size_t kMaxPatchHits = 64;
struct PatchContact {
  std::size_t count;
  std::size_t member[kPatchMembers];
  PatchBlend blend;  // when count > 1
};
std::size_t join_patches(const Vec3* normals, const double* overlaps, std::size_t count, PatchContact* out);

}  // namespace bagdem
