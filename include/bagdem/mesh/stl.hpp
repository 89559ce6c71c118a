// STL files (ASCII or binary): rigid cavity surfaces a user has a mesh of.
#pragma once
#include <string>

#include "bagdem/mesh/triangle_mesh.hpp"

namespace bagdem {

// Reads an STL file, scales coordinates by `scale` (file units to metres), welds vertices closer
// than 1e-9 x the bounding-box diagonal, drops degenerate triangles (reported in `dropped`), and
// builds the topology. The orientation of the file is kept (STL normals point out of the solid the
// file describes). Throws InputError naming the file (and line, for ASCII) when the file is missing,
// truncated, not STL, or not a manifold surface.
TriangleMesh read_stl(const std::string& path, double scale, std::size_t* dropped = nullptr);

}  // namespace bagdem
