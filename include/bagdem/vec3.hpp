// Vec3: the one 3-vector type of bagdem (Eigen's fixed-size double vector; not
// a "vectorizable" fixed size, so it needs no special alignment in containers).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross(), unitOrthogonal()

namespace bagdem {
using Vec3 = Eigen::Vector3d;

// Three draws of `draw` as a vector, drawn z first, then y, then x. Not Vec3(draw(), draw(), draw()):
// C++ leaves the order of a call's arguments unspecified (GCC evaluates them last first, clang first
// first), so a seeded fill would depend on the compiler. z, y, x is the order GCC gave, which every
// fill and result so far was made with.
template <class Draw>
Vec3 draw_vec3(Draw&& draw) {
  const double z = draw(), y = draw(), x = draw();
  return {x, y, z};
}
}  // namespace bagdem

// For the small functions of the contact kernel: GCC otherwise declines to inline them into the
// large OpenMP-outlined loops, which costs ~15% of a step.
#define BAGDEM_INLINE inline __attribute__((always_inline))
#define BAGDEM_INLINE_LAMBDA __attribute__((always_inline))

namespace bagdem {
// a x b, always inlined (Eigen's cross of an expression is an out-of-line call in the contact
// kernel: 4% of a step).
BAGDEM_INLINE Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y() * b.z() - a.z() * b.y(), a.z() * b.x() - a.x() * b.z(), a.x() * b.y() - a.y() * b.x()};
}

// v, with its value hidden from the optimizer. For factors that are exactly 1 in one case of a
// data-dependent choice (std::min(1.0, r)): GCC otherwise turns x * factor into a branch around the
// multiplication, and a branch that goes either way at random stalls the contact loop.
BAGDEM_INLINE double opaque(double v) {
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__aarch64__))
#if defined(__x86_64__)
  asm("" : "+v"(v));
#else
  asm("" : "+w"(v));
#endif
#endif
  return v;
}
}  // namespace bagdem
