// Internal to src/mesh: isotropic remeshing of a closed surface given by a projection onto it.
#pragma once
#include <functional>

#include "bagdem/mesh/triangle_mesh.hpp"

namespace bagdem::detail {

// Remeshes a closed, outward-oriented, manifold triangulation towards edge length L (unit: m) by
// Botsch & Kobbelt's loop ("A remeshing approach to multiresolution modeling", SGP 2004): split
// edges longer than 4/3 L, collapse edges shorter than 4/5 L, flip edges to bring valences towards
// 6, relax vertices along the surface; `project` maps a point near the surface to the nearest
// surface point. Ends with Delaunay flips (the larger smallest angle of each pair) and relaxation.
// Deterministic (every pass walks vertices and triangles in index order). Returns the mesh with
// its topology built.
TriangleMesh remesh(const TriangleMesh& mesh, double L, const std::function<Vec3(const Vec3&)>& project,
                    int iterations);

}  // namespace bagdem::detail
