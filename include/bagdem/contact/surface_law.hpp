// The contact law of a pair of balls or of a body against a surface: a wall (mass at infinity), an
// STL wall, or a point of the bag's film (its effective mass already in g.m_eff). The roles in
// order: normal, tangential, rolling, those of the contact's law (contact/law.hpp: Hertz-Mindlin,
// Hooke). Used by every kind of contact, so they all evaluate the same law the same way.
#pragma once
#include "bagdem/contact/lanes.hpp"
#include "bagdem/contact/law.hpp"

namespace bagdem {

// Returns the force on the body; adds its torque to `torque` and, when Energy, this step's (normal,
// tangential, rolling) dissipation to `diss`. Histories: `damping_prev` (normal damping force of the
// last step), `th` (when Tangential), `rh` (when Rolling). `elastic` (when not null): the elastic
// part of the normal force along g.n. L: the law's type (law.kind's).
template <class L, bool Tangential, bool Rolling, bool Energy>
BAGDEM_INLINE Vec3 surface_contact_as(const ContactGeometry& g, const PairLaw& law, double dt, double& damping_prev,
                                      TangentialHistory* th, RollingHistory* rh, Vec3& torque, Vec3& diss, double* elastic) {
  const NormalResult nr = L::normal(g, law);
  if (elastic) *elastic = nr.elastic;
  Vec3 F = nr.force * g.n;
  if constexpr (Energy) diss.x() += normal_dissipation(nr, g.v_half.dot(g.n), dt, damping_prev);
  if constexpr (Tangential) {
    const TangentialResult tr = mindlin_tangential(g, law, L::friction_load(nr), dt, *th, L::kOpenedMean);
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
template <bool Tangential, bool Rolling, bool Energy>
BAGDEM_INLINE Vec3 surface_contact(const ContactGeometry& g, const PairLaw& law, double dt, double& damping_prev,
                                   TangentialHistory* th, RollingHistory* rh, Vec3& torque, Vec3& diss,
                                   double* elastic = nullptr) {
  return visit_law(law.kind, [&](auto L) BAGDEM_INLINE_LAMBDA {
    return surface_contact_as<decltype(L), Tangential, Rolling, Energy>(g, law, dt, damping_prev, th, rh, torque, diss, elastic);
  });
}

// The constants of the laws per lane, for contacts of different materials side by side.
struct PairLawLanes {
  Lanes E_star, damping, tangential_ratio, friction, rolling, stiffness;
};
BAGDEM_INLINE PairLawLanes law_lanes(const PairLaw* const* e) {
  auto field = [e](double PairLaw::*m) BAGDEM_INLINE_LAMBDA { return Lanes{e[0]->*m, e[1]->*m, e[2]->*m, e[3]->*m}; };
  return {field(&PairLaw::E_star), field(&PairLaw::damping), field(&PairLaw::tangential_ratio),
          field(&PairLaw::friction), field(&PairLaw::rolling), field(&PairLaw::stiffness)};
}

// The same law on kLanes contacts side by side (lanes.hpp), lane l's histories at damping_prev[l],
// th[l], rh[l] (the pointers of the roles in use). Lanes beyond the contacts in hand repeat the last
// one: they write its histories again, with the same values. F: the force on the body; its torque
// from the tangential force is -arm x nxFt; roll: the rolling torque; diss: this step's (normal,
// tangential, rolling) dissipation when Energy.
struct SurfaceLanes {
  Lanes3 F, nxFt, roll, diss;
};
template <class L, bool Tangential, bool Rolling, bool Energy, class Law>
BAGDEM_INLINE SurfaceLanes surface_contact_lanes_as(const ContactGeometryT<Lanes>& g, const Law& law, double dt,
                                                    double* const* damping_prev, TangentialHistory* const* th,
                                                    RollingHistory* const* rh) {
  const NormalResultT<Lanes> nr = L::normal(g, law);
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
    const TangentialResultT<Lanes> tr = mindlin_tangential(g, law, L::friction_load(nr), dt, h, L::kOpenedMean);
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

// One law on every lane (all contacts of one pair of materials).
template <bool Tangential, bool Rolling, bool Energy>
BAGDEM_INLINE SurfaceLanes surface_contact_lanes(const ContactGeometryT<Lanes>& g, const PairLaw& law, double dt,
                                                 double* const* damping_prev, TangentialHistory* const* th,
                                                 RollingHistory* const* rh) {
  return visit_law(law.kind, [&](auto L) BAGDEM_INLINE_LAMBDA {
    return surface_contact_lanes_as<decltype(L), Tangential, Rolling, Energy>(g, law, dt, damping_prev, th, rh);
  });
}

// Lanes of several laws: each law present on all lanes, the lanes of the other laws on copies of
// their histories; each lane keeps its own law's results and histories.
template <bool Tangential, bool Rolling, bool Energy>
SurfaceLanes mixed_law_lanes(const ContactGeometryT<Lanes>& g, const PairLaw* const* e, const PairLawLanes& law, double dt,
                             double* const* damping_prev, TangentialHistory* const* th, RollingHistory* const* rh) {
  SurfaceLanes out{};
  double d0[kLanes] = {};
  TangentialHistory t0[kLanes];
  RollingHistory r0[kLanes];
  for (int l = 0; l < kLanes; ++l) {
    if constexpr (Energy) d0[l] = *damping_prev[l];
    if constexpr (Tangential) t0[l] = *th[l];
    if constexpr (Rolling) r0[l] = *rh[l];
  }
  for_each_law([&](auto L) {
    double d[kLanes];
    TangentialHistory t[kLanes];
    RollingHistory r[kLanes];
    double* dp[kLanes];
    TangentialHistory* tp[kLanes];
    RollingHistory* rp[kLanes];
    LanesMask mine{};
    for (int l = 0; l < kLanes; ++l) {
      d[l] = d0[l], t[l] = t0[l], r[l] = r0[l];
      dp[l] = &d[l], tp[l] = &t[l], rp[l] = &r[l];
      mine[l] = e[l]->kind == decltype(L)::kind ? -1 : 0;
    }
    if (!(mine[0] | mine[1] | mine[2] | mine[3])) return;
    const SurfaceLanes o = surface_contact_lanes_as<decltype(L), Tangential, Rolling, Energy>(g, law, dt, dp, tp, rp);
    auto keep = [&mine](Lanes3& to, const Lanes3& from) {
      to = {select(mine, from.x, to.x), select(mine, from.y, to.y), select(mine, from.z, to.z)};
    };
    keep(out.F, o.F), keep(out.nxFt, o.nxFt), keep(out.roll, o.roll), keep(out.diss, o.diss);
    for (int l = 0; l < kLanes; ++l) {
      if (!mine[l]) continue;
      if constexpr (Energy) *damping_prev[l] = d[l];
      if constexpr (Tangential) *th[l] = t[l];
      if constexpr (Rolling) *rh[l] = r[l];
    }
  });
  return out;
}

// Lane l's law is *e[l]. Lanes of one law run it once; lanes of several laws run each law on all
// lanes, the lanes of the others on copies of their histories, and keep each lane's own law's
// results (a lane's bits are its law's either way).
template <bool Tangential, bool Rolling, bool Energy>
BAGDEM_INLINE SurfaceLanes surface_contact_lanes(const ContactGeometryT<Lanes>& g, const PairLaw* const* e, double dt,
                                                 double* const* damping_prev, TangentialHistory* const* th,
                                                 RollingHistory* const* rh) {
  const PairLawLanes law = law_lanes(e);
  const LawKind k0 = e[0]->kind;
  if (e[1]->kind == k0 && e[2]->kind == k0 && e[3]->kind == k0) [[likely]]
    return visit_law(k0, [&](auto L) BAGDEM_INLINE_LAMBDA {
      return surface_contact_lanes_as<decltype(L), Tangential, Rolling, Energy>(g, law, dt, damping_prev, th, rh);
    });
  return mixed_law_lanes<Tangential, Rolling, Energy>(g, e, law, dt, damping_prev, th, rh);
}

}  // namespace bagdem
