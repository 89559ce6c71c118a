// The contact law of a body against a surface: a wall (mass at infinity), an STL wall, or a point of
// the bag's film (its effective mass already in g.m_eff). The roles in order: normal (hertz.hpp),
// tangential (mindlin.hpp), rolling (rolling.hpp). Used by every kind of surface contact, so they
// all evaluate the same law the same way.
#pragma once
#include "bagdem/contact/hertz.hpp"
#include "bagdem/contact/mindlin.hpp"
#include "bagdem/contact/rolling.hpp"

namespace bagdem {

// Returns the force on the body; adds its torque to `torque` and, when Energy, this step's (normal,
// tangential, rolling) dissipation to `diss`. Histories: `damping_prev` (normal damping force of the
// last step), `th` (when Tangential), `rh` (when Rolling).
template <bool Tangential, bool Rolling, bool Energy>
BAGDEM_INLINE Vec3 surface_contact(const ContactGeometry& g, const PairLaw& law, double dt, double& damping_prev,
                                   TangentialHistory* th, RollingHistory* rh, Vec3& torque, Vec3& diss) {
  const NormalResult nr = hertz_normal(g, law);
  Vec3 F = nr.force * g.n;
  if constexpr (Energy) diss.x() += normal_dissipation(nr, g.v_half.dot(g.n), dt, damping_prev);
  if constexpr (Tangential) {
    const TangentialResult tr = mindlin_tangential(g, law, nr, dt, *th);
    F += tr.force;
    torque -= g.arm_i * cross(g.n, tr.force);
    if constexpr (Energy) diss.y() += tr.dissipated;
  }
  if constexpr (Rolling) {
    const RollingResult rr = epsd_rolling(g, law, nr.stiffness, nr.force, dt, *rh);
    torque += rr.torque;
    if constexpr (Energy) diss.z() += rr.dissipated;
  }
  return F;
}

}  // namespace bagdem
