// Vec3: the one 3-vector type of bagdem (Eigen's fixed-size double vector; not
// a "vectorizable" fixed size, so it needs no special alignment in containers).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross(), unitOrthogonal()

namespace bagdem {
using Vec3 = Eigen::Vector3d;
}  // namespace bagdem
