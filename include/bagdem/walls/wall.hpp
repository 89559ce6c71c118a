// Walls are geometry: each kind is one function returning the signed distance of a point from the
// surface and the inward normal (walls/plane.hpp, walls/cylinder.hpp). The contact law is the same
// as for particle pairs with the wall's radius and mass at infinity (contact/law.hpp).
// Cavities (box, capped cylinder, planes) are built from these primitives (case/cavity_kinds.cpp).
#pragma once
#include <cstdint>
#include <string>

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
  std::string name;              // for messages ("box -x", "bore")
};

// Signed distance of a point x given in the cavity frame; n = inward unit normal.
BAGDEM_INLINE double wall_distance(const Wall& w, const Vec3& x, Vec3& n) {
  switch (w.kind) {
    case WallKind::Plane: return plane_distance(w.point, w.direction, x, n);
    case WallKind::Cylinder: return cylinder_inner_distance(w.point, w.direction, w.radius, x, n);
  }
  return 0;
}

}  // namespace bagdem
