// Sphere against a triangulated surface: the closest point of a triangle and which feature of it
// (face, edge or vertex) that point lies on, and the rule that makes one contact per feature of a
// mesh (no double counting where triangles share an edge or a vertex).
// Layer 2 of 3 (neighbour search -> contact geometry -> contact law); used by the film of a bag and
// by rigid STL cavities alike.
#pragma once
#include <cstdint>
#include <vector>

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
// vertex; at a vertex, weight 1 on it.
TriangleHit closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

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
// of every triangle within contact reach, in ascending triangle order; on return it holds the
// contacts to apply, in the same order:
//   - every face hit;
//   - an edge hit once per edge, and only if no triangle of that edge has a face hit;
//   - a vertex hit once per vertex, and only if no triangle around it has a face hit and none of
//     its edges has an edge hit.
// On a flat triangulation a sphere thus always has exactly one contact, the same as with the plane.
// Fills each hit's key from the mesh topology (build_topology must have run).
void select_mesh_contacts(const TriangleMesh& mesh, std::vector<MeshHit>& hits);

}  // namespace bagdem
