// Walls are geometry: each kind is one function returning the signed distance of a point from the
// surface and the inward normal (walls/plane.hpp, walls/cylinder.hpp), and the effective radius of a
// sphere's contact with it. The contact law is the one of particle pairs with the wall's mass at
// infinity (src/step/walls.cpp, wall_contacts). Cavities (box, capped cylinder, planes) are built from
// these primitives (src/case/cavity_kinds.cpp).
#pragma once
#include <cstdint>

#include "bagdem/vec3.hpp"
#include "bagdem/walls/cylinder.hpp"
#include "bagdem/walls/plane.hpp"

namespace bagdem {

enum class WallKind : std::uint8_t { Plane, Cylinder };

// A rigid wall fixed in the cavity frame (it moves with the cavity's translation).
struct Wall {
  WallKind kind = WallKind::Plane;
  Vec3 point = Vec3::Zero();     // plane: a point on it; cylinder: a point on the axis (unit: m)
  Vec3 direction = Vec3::UnitZ();// plane: unit inward normal; cylinder: unit axis
  double radius = 0;             // cylinder radius (unit: m)
  int material = 0;              // index into the scene's materials
};

// Effective radius R* of a sphere of radius r touching the wall. A plane: r. Inside a bore of
// radius Rc the surfaces are conformal in one direction (1/R' = 1/r - 1/Rc) and not in the other
// (R'' = r); Hertz's equivalent radius of the elliptical contact is sqrt(R' R'') (Johnson 1985,
// sec. 4.2), R* = r sqrt(Rc / (Rc - r)).
BAGDEM_INLINE double wall_effective_radius(const Wall& w, double r) {
  if (w.kind == WallKind::Cylinder) return r * std::sqrt(w.radius / (w.radius - r));
  return r;
}

// Signed distance of a point x given in the cavity frame; n = inward unit normal.
BAGDEM_INLINE double wall_distance(const Wall& w, const Vec3& x, Vec3& n) {
  switch (w.kind) {
    case WallKind::Plane: return plane_distance(w.point, w.direction, x, n);
    case WallKind::Cylinder: return cylinder_inner_distance(w.point, w.direction, w.radius, x, n);
  }
  n = w.direction;  // unreachable: every kind is handled above
  return 0;
}

}  // namespace bagdem
