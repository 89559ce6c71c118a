// The contact law of a body against a surface: a wall (mass at infinity), an STL wall, or a point of
// the bag's film (its effective mass already in g.m_eff). The roles in order: normal (hertz.hpp),
// tangential (mindlin.hpp), rolling (rolling.hpp). Used by every kind of surface contact, so they
// all evaluate the same law the same way.
#pragma once
#include "bagdem/contact/hertz.hpp"
#include "bagdem/contact/lanes.hpp"
#include "bagdem/contact/mindlin.hpp"
#include "bagdem/contact/rolling.hpp"

namespace bagdem {

// Returns the force on the body; adds its torque to `torque` and, when Energy, this step's (normal,
// tangential, rolling) dissipation to `diss`. Histories: `damping_prev` (normal damping force of the
// last step), `th` (when Tangential), `rh` (when Rolling). `elastic` (when not null): the Hertz
// elastic part of the normal force along g.n.
template <bool Tangential, bool Rolling, bool Energy>
BAGDEM_INLINE Vec3 surface_contact(const ContactGeometry& g, const PairLaw& law, double dt, double& damping_prev,
                                   TangentialHistory* th, RollingHistory* rh, Vec3& torque, Vec3& diss,
                                   double* elastic = nullptr) {
  const NormalResult nr = hertz_normal(g, law);
  if (elastic) *elastic = nr.elastic;
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

// The constants of the law per lane, for contacts of different materials side by side.
struct PairLawLanes {
  Lanes E_star, damping, tangential_ratio, friction, rolling;
};
BAGDEM_INLINE PairLawLanes law_lanes(const PairLaw* const* e) {
  auto field = [e](double PairLaw::*m) BAGDEM_INLINE_LAMBDA { return Lanes{e[0]->*m, e[1]->*m, e[2]->*m, e[3]->*m}; };
  return {field(&PairLaw::E_star), field(&PairLaw::damping), field(&PairLaw::tangential_ratio),
          field(&PairLaw::friction), field(&PairLaw::rolling)};
}

// The same law on kLanes contacts side by side (lanes.hpp), lane l's histories at damping_prev[l],
// th[l], rh[l] (the pointers of the roles in use). Lanes beyond the contacts in hand repeat the last
// one: they write its histories again, with the same values. F: the force on the body; its torque
// from the tangential force is -arm x nxFt; roll: the rolling torque; diss: this step's (normal,
// tangential, rolling) dissipation when Energy.
struct SurfaceLanes {
  Lanes3 F, nxFt, roll, diss;
};
template <bool Tangential, bool Rolling, bool Energy, class Law>
BAGDEM_INLINE SurfaceLanes surface_contact_lanes(const ContactGeometryT<Lanes>& g, const Law& law, double dt,
                                                 double* const* damping_prev, TangentialHistory* const* th,
                                                 RollingHistory* const* rh) {
  const NormalResultT<Lanes> nr = hertz_normal(g, law);
  SurfaceLanes out{nr.force * g.n, zero3<Lanes>(), zero3<Lanes>(), zero3<Lanes>()};
  if constexpr (Energy) {
    Lanes prev{*damping_prev[0], *damping_prev[1], *damping_prev[2], *damping_prev[3]};
    out.diss.x = normal_dissipation(nr, dot(g.v_half, g.n), dt, prev);
    for (int l = 0; l < kLanes; ++l) *damping_prev[l] = prev[l];
  }
  if constexpr (Tangential) {
    // The history's force and stiffness are 4 consecutive doubles: one row, loaded and stored.
    TangentialHistoryT<Lanes> h;
    double* row[kLanes];
    for (int l = 0; l < kLanes; ++l) row[l] = th[l]->force.data();
    gather4(row, h.force, h.stiffness);
    if constexpr (Energy) {
      const double* total[kLanes] = {th[0]->total.data(), th[1]->total.data(), th[2]->total.data(), th[3]->total.data()};
      h.total = gather3(total);
    }
    const TangentialResultT<Lanes> tr = mindlin_tangential(g, law, nr, dt, h);
    to_rows(h.force, h.stiffness, row);
    if constexpr (Energy)
      for (int l = 0; l < kLanes; ++l) th[l]->total = lane(h.total, l);
    out.F += tr.force;
    out.nxFt = cross(g.n, tr.force);
    if constexpr (Energy) out.diss.y = tr.dissipated;
  }
  if constexpr (Rolling) {
    RollingHistoryT<Lanes> h;
    double* row[kLanes];
    for (int l = 0; l < kLanes; ++l) row[l] = rh[l]->torque.data();
    gather4(row, h.torque, h.stiffness);
    const RollingResultT<Lanes> rr = epsd_rolling(g, law, nr.stiffness, nr.force, dt, h);
    to_rows(h.torque, h.stiffness, row);
    out.roll = rr.torque;
    if constexpr (Energy) out.diss.z = rr.dissipated;
  }
  return out;
}

}  // namespace bagdem
