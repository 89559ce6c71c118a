// Contact geometry: what the neighbour search and the wall functions hand to the contact law.
// Layer 2 of 3 (neighbour search -> contact geometry -> contact law).
#pragma once
#include <algorithm>
#include <cmath>

#include "bagdem/vec3.hpp"

namespace bagdem {

// One contact between body i (a particle) and body j (a particle or a wall), seen from i.
struct ContactGeometry {
  Vec3 n;           // unit normal pointing from j towards i
  double overlap;   // delta > 0 (unit: m)
  double R_eff;     // R* with 1/R* = 1/R_i + 1/R_j, R_j = inf for a wall (unit: m)
  double m_eff;     // m* with 1/m* = 1/m_i + 1/m_j, m_j = inf for a wall (unit: kg)
  double arm_i;     // distance from i's centre to the contact point (unit: m)
  double arm_j;     // same for j (0 for a wall) (unit: m)
  // Relative motion at the contact point, i's material point relative to j's, two ways:
  Vec3 v_rel;       // at the end of the step (predicted): what dashpots see (unit: m/s)
  Vec3 v_half;      // at the half step: (displacement over the step)/dt, for springs and energy tallies (unit: m/s)
  Vec3 w_half;      // relative angular velocity at the half step, for rolling (unit: rad/s)
};

// Whether two spheres with centres xi, xj and radii summing to rsum do not overlap: the one test
// of contact (sphere_sphere, and the pair stage's scan, which must skip exactly the same pairs).
BAGDEM_INLINE bool spheres_apart(const Vec3& xi, const Vec3& xj, double rsum) {
  return (xi - xj).squaredNorm() >= rsum * rsum;
}

// Sphere-sphere geometry: false when apart, else g's geometry (x centres, r radii).
BAGDEM_INLINE bool sphere_sphere(const Vec3& xi, const Vec3& xj, double ri, double rj, ContactGeometry& g) {
  const Vec3 d = xi - xj;
  const double rsum = ri + rj;
  if (spheres_apart(xi, xj, rsum)) return false;
  const double dist2 = d.squaredNorm();
  const double dist = std::sqrt(dist2);
  g.n = d / dist;
  g.overlap = rsum - dist;
  g.R_eff = ri * rj / rsum;
  g.arm_i = ri - 0.5 * g.overlap;
  g.arm_j = rj - 0.5 * g.overlap;
  return true;
}

// Velocity of i's material point at the contact c relative to j's (c - x_i = -arm_i n,
// c - x_j = +arm_j n).
BAGDEM_INLINE Vec3 contact_velocity(const Vec3& vi, const Vec3& vj, const Vec3& wi, const Vec3& wj,
                             const ContactGeometry& g) {
  return vi - vj - (g.arm_i * wi + g.arm_j * wj).cross(g.n);
}

// Carries a contact's stored spring vector (tangential force, rolling torque) into the current
// tangent plane, normal n: rotated with its magnitude kept (as LIGGGHTS does), then scaled by
// k_new/k_old when the spring's stiffness fell (unloading), kept when it rose (Thornton, Cummins &
// Cleary 2013, sec. 2.2). Both rules leave the stored energy |v|^2/(2k) non-increasing.
BAGDEM_INLINE Vec3 carry_spring(Vec3 v, const Vec3& n, double k_old, double k_new) {
  // Written without branches (whether the spring unloads is a coin toss from step to step, and a
  // mispredicted branch stalls the contact loop). Each factor is exactly 1 where it does not apply:
  // k_new / k_old >= 1 when the stiffness rose (inf or NaN for a new contact, whose v is zero, and
  // std::min keeps its first argument then); rot2 = 0 only when v is zero.
  const double mag2 = v.squaredNorm();
  v -= v.dot(n) * n;
  const double rot2 = v.squaredNorm();
  v *= std::sqrt(mag2 / (rot2 > 0 ? rot2 : 1.0));
  v *= opaque(std::min(1.0, k_new / k_old));
  return v;
}
}  // namespace bagdem
