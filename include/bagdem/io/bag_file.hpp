// A settled bag saved for reuse (bag.h5): the starting state of other cases without refilling and
// resettling (case key bag.from). Written by `bagdem run` when the settle phase ends; positions in
// the cavity frame (the cavity at rest at the origin of its motion).
//   /film/rest       [V x 3] m    the film's stress-free shape
//   /film/position   [V x 3] m    its settled nodes
//   /film/triangles  [T x 3] int  vertex indices (outward)
//   /balls/position  [N x 3] m
//   /balls/radius    [N]     m
//   attributes: shape, axis, side, size (m), fill_fraction, film_thickness (m), program_version
#pragma once
#include <string>
#include <vector>

#include "bagdem/mesh/triangle_mesh.hpp"

namespace bagdem {

struct SavedBag {
  TriangleMesh rest;                  // vertices = rest shape; topology not built
  std::vector<Vec3> film_position;
  std::vector<Vec3> ball_position;
  std::vector<double> ball_radius;
  std::string shape;
  Vec3 axis = Vec3::UnitX(), side = Vec3::UnitY(), size = Vec3::Zero();
  double fill_fraction = 0, film_thickness = 0;
};

// Writes atomically (a temporary name, then renamed). Throws std::runtime_error on I/O failure.
void save_bag(const std::string& path, const SavedBag& bag);
// Throws InputError naming the file when it is missing or not a saved bag.
SavedBag load_bag(const std::string& path);

}  // namespace bagdem
