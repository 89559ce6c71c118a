// A rigid triangulated wall fixed in the cavity frame, read from an STL file (src/mesh/stl.cpp):
// any shape of cavity a user has a mesh of. Balls touch it through the sphere-triangle contact of
// contact/sphere_triangle.hpp with the pair law of the ball's and the wall's materials (the wall's
// mass at infinity), exactly as they touch the bag's film.
#pragma once
#include <string>

#include "bagdem/mesh/triangle_mesh.hpp"

namespace bagdem {

struct MeshWall {
  std::string name;   // for messages ("cavity.file = box.stl")
  TriangleMesh mesh;  // in the cavity frame; normals point away from the balls (out of the cavity)
  int material = 0;
};

}  // namespace bagdem
