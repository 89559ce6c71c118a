// Cylindrical wall seen from inside (a bore): axis through `point` along unit `axis`, radius R.
#pragma once
#include <cmath>

#include "bagdem/vec3.hpp"

namespace bagdem {

// Signed distance of x from the cylinder surface (positive inside); n = inward normal at the
// nearest surface point (towards the axis). On the axis itself any radial direction is chosen.
BAGDEM_INLINE double cylinder_inner_distance(const Vec3& point, const Vec3& axis, double R, const Vec3& x,
                                      Vec3& n) {
  const Vec3 d = x - point;
  const Vec3 radial = d - d.dot(axis) * axis;
  const double s = radial.norm();
  if (s > 0) {
    n = -radial / s;
  } else {
    n = axis.unitOrthogonal();
  }
  return R - s;
}

}  // namespace bagdem
