// Candidate triangles of each sphere for the sphere-triangle contacts (the bag's film, STL walls):
// every triangle closer than radius + reach + skin to the sphere's centre when the list is built.
// The list stays valid while no sphere and no vertex moved more than skin/2 since (a point of a
// triangle moves no more than its farthest vertex). Triangles go into a uniform grid by their
// bounding boxes (inflated by the largest reach), each sphere looks in its own cell, and the
// exact closest-point distance filters the cell's triangles.
#pragma once
#include <cstdint>
#include <vector>

#include "bagdem/mesh/triangle_mesh.hpp"
#include "bagdem/vec3.hpp"

namespace bagdem {

struct MeshCandidates {
  std::vector<std::uint32_t> begin;     // CSR over spheres: size spheres + 1
  std::vector<std::uint32_t> triangle;  // candidate triangles, ascending for each sphere
  std::size_t size() const { return triangle.size(); }
  // Scratch of the search, kept so that a rebuild reuses its memory: (cell, triangle) entries.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> cells;
};

// `vertices`: the mesh's vertex positions in the same frame as `centres - shift`.
// `reach`: added to each sphere's radius (the film's half thickness).
void find_mesh_candidates(const TriangleMesh& mesh, const std::vector<Vec3>& vertices,
                          const std::vector<Vec3>& centres, const std::vector<double>& radius, const Vec3& shift,
                          double reach, double skin, MeshCandidates& out);

}  // namespace bagdem
