// Closed (and flat) triangulated surfaces generated from dimensions: the shapes a bag's film can
// take at rest, and flat sheets for tests. Every closed shape is outward oriented, has its topology
// built, and has triangles of nearly uniform size and shape (they are membrane elements):
// `triangles` is a target; the result is within a factor 1.5 of it (at least the coarsest mesh of
// the shape), except for the sphere between 31 and 53 (20 or 80 triangles).
// Measured for targets 200 to 8000: smallest angle of any triangle sphere 54 degrees, capsule 40,
// pillow 33 (flat, long and boxy ones included); largest / smallest triangle area sphere 1.9,
// capsule 1.6, pillow 2.3; triangle count within 10 % of the target (capsule, pillow) or the
// nearest 20 n^2 (sphere). (tests/test_mesh.cpp checks pillows up to 2000: 35 degrees, 2.1.)
// Below ~50 triangles shapes keep their coarsest form (a flat pillow's 12-triangle box has
// 8-degree angles).
// Errors: std::invalid_argument for non-positive or non-finite dimensions and bad directions.
#pragma once
#include <cstddef>

#include "bagdem/mesh/triangle_mesh.hpp"

namespace bagdem {

// Capsule: a cylinder of radius r with hemispherical caps, overall length L >= 2r (tip to tip),
// axis along the unit vector `axis`, centred at `centre`. Rings of nodes around the axis, spaced
// by arc length along the profile, with the pole of each cap a single node. Ring spacing and node
// counts make triangles near equilateral: ring spacing ds = P / m (P = pi r + L - 2r the profile
// length, m chosen for the target), ring k with round(2 pi rho_k / (2 ds / sqrt 3)) >= 3 nodes, or
// on the caps the nearest multiple of 6 where that is within 15 % (hexagonal rings 6, 12, 18
// around a pole of valence 6); a ring with as many nodes as the previous one turned by half a node
// spacing; neighbouring rings joined along their shorter diagonals.
TriangleMesh capsule_mesh(const Vec3& centre, const Vec3& axis, double radius, double length,
                          std::size_t triangles);

// Pillow: a rounded box, the superellipsoid |x/a|^p + |y/b|^p + |z/c|^p = 1 with semi-axes
// (a, b, c) = size/2 and exponent p >= 2 (2 = ellipsoid; larger is boxier), axes along the frame's
// x (`axis`), and y = a unit vector orthogonal to it (`side`, its part orthogonal to `axis`),
// z = x cross y. Built by projecting a subdivided box (cells in proportion to the semi-axes,
// equiangular spacing at p = 2) radially onto the surface, then remeshed isotropically on the
// surface (Botsch & Kobbelt 2004: split, collapse, flip, tangential relaxation) to near equilateral
// triangles of uniform size: a flat pillow's rim otherwise gets cells 3-10 times longer than wide.
// Every vertex lies on the surface; diagonals are chosen by angle, not convexity, so some edges
// fold slightly inwards (105 of 744 on a 500-triangle rounded cube, p = 4): the polyhedron is not
// exactly convex.
TriangleMesh pillow_mesh(const Vec3& centre, const Vec3& axis, const Vec3& side, const Vec3& size, double exponent,
                         std::size_t triangles);

// Sphere of radius r: an icosahedron with each face cut into n^2 triangles (geodesic class I,
// frequency n), projected radially on the sphere: 20 n^2 triangles, n chosen nearest the target by
// ratio (n = 2^k gives the classic 20 * 4^k subdivisions).
TriangleMesh sphere_mesh(const Vec3& centre, double radius, std::size_t triangles);

// Open flat rectangle lx by ly centred at `centre` in the plane z = centre.z, nx by ny cells, each
// cell split into two triangles along alternating diagonals; normals along +z.
TriangleMesh rectangle_mesh(const Vec3& centre, double lx, double ly, std::size_t nx, std::size_t ny);

}  // namespace bagdem
