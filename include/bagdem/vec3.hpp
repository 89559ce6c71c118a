// Vec3: the one 3-vector type of bagdem (Eigen's fixed-size double vector; not
// a "vectorizable" fixed size, so it needs no special alignment in containers).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross(), unitOrthogonal()

namespace bagdem {
using Vec3 = Eigen::Vector3d;
}  // namespace bagdem

// For the small functions of the contact kernel: GCC otherwise declines to inline them into the
// large OpenMP-outlined loops, which costs ~15% of a step.
#define BAGDEM_INLINE inline __attribute__((always_inline))
