// Tangential role: Mindlin no-slip spring with history, viscous damping and a Coulomb cap.
//
//   S_t = 8 G* sqrt(R* delta)                                   Mindlin (1949); Johnson (1985) eq. 7.41
//   gamma_t = 2 sqrt(5/6)|beta| sqrt(S_t m*)                   Tsuji et al. (1992)
//   F_t = F_e - gamma_t v_t,  |F_t| <= mu_s F_n                Coulomb
// The history is the elastic tangential force F_e. Each step it is carried into the current tangent
// plane (carry_spring: rotated, and scaled down when S_t fell), then incremented by -S v_t dt with
// S the step's mean stiffness (second order in dt; with S at the step's end the rebound velocity
// and spin in the sticking regime are first order: 5% off at 40 steps per contact).
// The carrying never adds stored energy, so no impact, grazing ones included, can gain energy
// from the spring.
// In gross sliding F_t = mu_s F_n t (t the direction of the trial force) and F_e = F_t.
#pragma once
#include <cmath>

#include "bagdem/contact/geometry.hpp"
#include "bagdem/contact/hertz.hpp"
#include "bagdem/material.hpp"

namespace bagdem {

// History of one contact's tangential spring (zero when the contact opens); T as in hertz.hpp.
// force and stiffness stay adjacent: surface_contact_lanes moves them as one row of 4 doubles.
template <class T>
struct TangentialHistoryT {
  V3<T> force = zero3<T>();  // elastic tangential force F_e on i (unit: N)
  T stiffness = splat<T>(0);  // S_t at the previous step (unit: N/m); 0 = new contact
  V3<T> total = zero3<T>();  // F_t of the previous step, for the energy tally (unit: N)
};
using TangentialHistory = TangentialHistoryT<double>;
static_assert(sizeof(Vec3) == 3 * sizeof(double), "a row of a history is a Vec3 and one double");

template <class T>
struct TangentialResultT {
  V3<T> force;     // F_t on i (unit: N)
  T dissipated;    // energy dissipated in this step by damping and sliding (unit: J)
};
using TangentialResult = TangentialResultT<double>;

// `normal` is the normal role's result: S_t = S_n ratio^2, gamma_t = gamma_n ratio (ratio: the law's
// tangential_ratio, sqrt(4G*/E*) for Mindlin; no sqrt here). opened_mean: the mean of S_t over the
// part of the step a new contact was closed, as a fraction of its end value: 2/3 for Mindlin's
// S_t ~ sqrt(delta) (the default), 1 for a linear spring (hooke.hpp).
template <class T, class Law>
BAGDEM_INLINE TangentialResultT<T> mindlin_tangential(const ContactGeometryT<T>& g, const Law& law,
                                                      const NormalResultT<T>& normal, double dt, TangentialHistoryT<T>& h,
                                                      double opened_mean = 2.0 / 3.0) {
  const T F_n = normal.force;
  const V3<T> v_t = g.v_half - dot(g.v_half, g.n) * g.n;  // tangential displacement rate over the step
  const V3<T> v_t_end = g.v_rel - dot(g.v_rel, g.n) * g.n; // tangential velocity the dashpot sees
  const T S_t = normal.stiffness * law.tangential_ratio * law.tangential_ratio;
  const T gamma_t = normal.gamma_n * law.tangential_ratio;

  const T energy_before = select(h.stiffness > 0, dot(h.force, h.force) / (2.0 * h.stiffness), splat<T>(0.0));
  V3<T> Fe = carry_spring<T>(h.force, g.n, h.stiffness, S_t);
  // Spring increment over the step with the step's mean stiffness (second order in dt): the mean of
  // the two ends, or for a contact that opened during the step, opened_mean of the end value (2/3
  // where S_t grows as sqrt(delta) from zero) over the part of the step since first touch,
  // delta / (d delta/dt).
  // One contact takes the branch; lanes compute both and select.
  auto opened_rate = [&] {
    const T approach = -dot(g.v_half, g.n) * dt;  // overlap gained over a full step (unit: m)
    const T part = select(approach > g.overlap, g.overlap / approach, splat<T>(1.0));
    return opened_mean * S_t * part;
  };
  T rate;
  if constexpr (std::is_same_v<T, double>) rate = h.stiffness > 0 ? 0.5 * (h.stiffness + S_t) : opened_rate();
  else rate = select(h.stiffness > 0, 0.5 * (h.stiffness + S_t), opened_rate());
  Fe -= rate * dt * v_t;

  V3<T> Ft = Fe - gamma_t * v_t_end;
  const T cap = law.friction * F_n;
  const T Ft2 = dot(Ft, Ft);
  // Without branches (sliding or sticking changes unpredictably): the factor is exactly 1 when it
  // sticks (then sqrt(Ft2) <= cap; for Ft2 = 0, cap / 0 is inf or NaN and std::min keeps 1).
  const auto slides = Ft2 > cap * cap;
  Ft *= opaque(min_of(splat<T>(1.0), cap / sqrt_of(Ft2)));
  const T keep = opaque(select(slides, splat<T>(0.0), splat<T>(1.0)));
  Fe = keep * Fe + (1.0 - keep) * Ft;
  // Work of F_t on the relative motion over the step: in velocity Verlet a force's discrete work is
  // the trapezoid of the forces of two steps times the half-step displacement. What the spring did
  // not store was dissipated (by the dashpot, by sliding, or lost in the stiffness rules).
  const T energy_after = dot(Fe, Fe) / (2.0 * S_t);
  const T work = 0.5 * dot(Ft + h.total, v_t) * dt;
  h.force = Fe;
  h.stiffness = S_t;
  h.total = Ft;
  return {Ft, -work - (energy_after - energy_before)};
}

BAGDEM_INLINE double mindlin_energy(const TangentialHistory& h) {
  return h.stiffness > 0 ? h.force.squaredNorm() / (2.0 * h.stiffness) : 0.0;
}

}  // namespace bagdem
