// Contact geometry: what the neighbour search and the wall functions hand to the contact law.
// Layer 2 of 3 (neighbour search -> contact geometry -> contact law).
#pragma once
#include <algorithm>
#include <cmath>

#include "bagdem/contact/lanes.hpp"
#include "bagdem/vec3.hpp"

namespace bagdem {

// One contact between body i (a particle) and body j (a particle or a wall), seen from i (T =
// double), or kLanes of them (T = Lanes; lanes.hpp).
template <class T>
struct ContactGeometryT {
  V3<T> n;          // unit normal pointing from j towards i
  T overlap;        // delta > 0 (unit: m)
  T R_eff;          // R* with 1/R* = 1/R_i + 1/R_j, R_j = inf for a wall (unit: m)
  T m_eff;          // m* with 1/m* = 1/m_i + 1/m_j, m_j = inf for a wall (unit: kg)
  T arm_i;          // distance from i's centre to the contact point (unit: m)
  T arm_j;          // same for j (0 for a wall) (unit: m)
  // Relative motion at the contact point, i's material point relative to j's, two ways:
  V3<T> v_rel;      // at the end of the step (predicted): what dashpots see (unit: m/s)
  V3<T> v_half;     // at the half step: (displacement over the step)/dt, for springs and energy tallies (unit: m/s)
  V3<T> w_half;     // relative angular velocity at the half step, for rolling (unit: rad/s)
};
using ContactGeometry = ContactGeometryT<double>;

// Whether two spheres with centres xi, xj and radii summing to rsum do not overlap: the one test
// of contact (sphere_sphere, and the pair stage's scan, which must skip exactly the same pairs).
// |d|^2 is summed as sphere_sphere_geometry sums it (dot), so a pair that passes has a distance
// of at most rsum there: its overlap is never negative.
BAGDEM_INLINE bool spheres_apart(const Vec3& xi, const Vec3& xj, double rsum) {
  const Vec3 d = xi - xj;
  return dot(d, d) >= rsum * rsum;
}

// Sphere-sphere geometry of two spheres known to overlap: centres x, radii r.
template <class T>
BAGDEM_INLINE void sphere_sphere_geometry(const V3<T>& xi, const V3<T>& xj, T ri, T rj, ContactGeometryT<T>& g) {
  const V3<T> d = xi - xj;
  const T rsum = ri + rj;
  const T dist = sqrt_of(dot(d, d));
  g.n = d / dist;
  g.overlap = rsum - dist;
  g.R_eff = ri * rj / rsum;
  g.arm_i = ri - 0.5 * g.overlap;
  g.arm_j = rj - 0.5 * g.overlap;
}

// The same, false when they do not overlap.
BAGDEM_INLINE bool sphere_sphere(const Vec3& xi, const Vec3& xj, double ri, double rj, ContactGeometry& g) {
  if (spheres_apart(xi, xj, ri + rj)) return false;
  sphere_sphere_geometry<double>(xi, xj, ri, rj, g);
  return true;
}

// Velocity of i's material point at the contact c relative to j's (c - x_i = -arm_i n,
// c - x_j = +arm_j n).
template <class T>
BAGDEM_INLINE V3<T> contact_velocity(const V3<T>& vi, const V3<T>& vj, const V3<T>& wi, const V3<T>& wj,
                                     const ContactGeometryT<T>& g) {
  return vi - vj - cross(V3<T>(g.arm_i * wi + g.arm_j * wj), g.n);
}

// Carries a contact's stored spring vector (tangential force, rolling torque) into the current
// tangent plane, normal n: rotated with its magnitude kept (as LIGGGHTS does), then scaled by
// k_new/k_old when the spring's stiffness fell (unloading), kept when it rose (Thornton, Cummins &
// Cleary 2013, sec. 2.2). Both rules leave the stored energy |v|^2/(2k) non-increasing.
template <class T>
BAGDEM_INLINE V3<T> carry_spring(V3<T> v, const V3<T>& n, T k_old, T k_new) {
  // Written without branches (whether the spring unloads is a coin toss from step to step, and a
  // mispredicted branch stalls the contact loop). Each factor is exactly 1 where it does not apply:
  // k_new / k_old >= 1 when the stiffness rose (inf or NaN for a new contact, whose v is zero, and
  // std::min keeps its first argument then); rot2 = 0 only when v is zero.
  const T mag2 = dot(v, v);
  v -= dot(v, n) * n;
  const T rot2 = dot(v, v);
  v *= sqrt_of(mag2 / select(rot2 > 0, rot2, splat<T>(1.0)));
  v *= opaque(min_of(splat<T>(1.0), k_new / k_old));
  return v;
}
}  // namespace bagdem
