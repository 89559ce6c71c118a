// Plane wall: a half-space boundary given by a point and a unit normal pointing into the cavity.
#pragma once
#include "bagdem/vec3.hpp"

namespace bagdem {

// Signed distance of x from the plane (positive on the cavity side); n = inward normal.
BAGDEM_INLINE double plane_distance(const Vec3& point, const Vec3& normal, const Vec3& x, Vec3& n) {
  n = normal;
  return (x - point).dot(normal);
}

}  // namespace bagdem
