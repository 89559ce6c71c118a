// Closed (and flat) triangulated surfaces generated from dimensions: the shapes a bag's film can
// take at rest, and flat sheets for tests. Every closed shape is outward oriented, has its topology
// built, and has triangles of nearly uniform size: `triangles` is a target; the result is within a
// factor 1.5 of it (at least the coarsest mesh of the shape).
#pragma once
#include <cstddef>

#include "bagdem/mesh/triangle_mesh.hpp"

namespace bagdem {

// Capsule: a cylinder of radius r with hemispherical caps, overall length L >= 2r (tip to tip),
// axis along the unit vector `axis`, centred at `centre`. Rings of nodes around the axis, spaced
// by arc length along the profile, with the pole of each cap a single node.
TriangleMesh capsule_mesh(const Vec3& centre, const Vec3& axis, double radius, double length,
                          std::size_t triangles);

// Pillow: a rounded box, the superellipsoid |x/a|^p + |y/b|^p + |z/c|^p = 1 with semi-axes
// (a, b, c) = size/2 and exponent p (2 = ellipsoid; larger is boxier), axes along the frame's x
// (`axis`), and y = a unit vector orthogonal to it (`side`), z = x cross y. Built by projecting a
// subdivided cube radially onto the surface.
TriangleMesh pillow_mesh(const Vec3& centre, const Vec3& axis, const Vec3& side, const Vec3& size, double exponent,
                         std::size_t triangles);

// Sphere of radius r (a subdivided icosahedron projected on the sphere; triangles is rounded to
// 20 * 4^k).
TriangleMesh sphere_mesh(const Vec3& centre, double radius, std::size_t triangles);

// Open flat rectangle lx by ly centred at `centre` in the plane z = centre.z, nx by ny cells, each
// cell split into two triangles along alternating diagonals; normals along +z.
TriangleMesh rectangle_mesh(const Vec3& centre, double lx, double ly, std::size_t nx, std::size_t ny);

}  // namespace bagdem
