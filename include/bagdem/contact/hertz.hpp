// Normal role: Hertz elastic force with restitution damping, clamped at zero (no tensile force).
//
//   F_el = (4/3) E* sqrt(R*) delta^(3/2)                       Hertz (1882); Johnson (1985) eq. 4.23
//   S_n  = dF_el/d(delta) = 2 E* sqrt(R* delta)
//   F_d  = gamma_n d(delta)/dt, gamma_n = 2 sqrt(5/6)|beta| sqrt(S_n m*)   Tsuji et al. (1992)
//   F_n  = max(0, F_el + F_d)                                  |beta| from clamped_beta(e)
// Elastic energy U_n = (2/5)(4/3) E* sqrt(R*) delta^(5/2).
#pragma once
#include <algorithm>
#include <cmath>

#include "bagdem/contact/geometry.hpp"
#include "bagdem/material.hpp"

namespace bagdem {

// T: double for one contact, Lanes for several (lanes.hpp); Law: PairLaw, or PairLawLanes.
template <class T>
struct NormalResultT {
  T force;       // F_n >= 0 along n, on i (unit: N)
  T stiffness;   // S_n (unit: N/m)
  T elastic;     // F_el (unit: N)
  T gamma_n;     // normal damping coefficient (unit: N s/m); the tangential role derives gamma_t from it
};
using NormalResult = NormalResultT<double>;

template <class T, class Law>
BAGDEM_INLINE NormalResultT<T> hertz_normal(const ContactGeometryT<T>& g, const Law& law) {
  const T sqrt_rd = sqrt_of(g.R_eff * g.overlap);
  const T S_n = 2.0 * law.E_star * sqrt_rd;
  const T F_el = (2.0 / 3.0) * S_n * g.overlap;  // = 4/3 E* sqrt(R*) delta^(3/2)
  const T gamma_n = law.damping * sqrt_of(S_n * g.m_eff);
  const T delta_dot = -dot(g.v_rel, g.n);
  return {max_of(splat<T>(0.0), F_el + gamma_n * delta_dot), S_n, F_el, gamma_n};
}

// Energy dissipated by the normal damping over a step: the trapezoid of this and the previous
// step's damping force F_d = F_n - F_el times the normal displacement v_n dt over the step (v_n from
// g.v_half; velocity Verlet's discrete work of a force). `damping_prev` is updated.
template <class T>
BAGDEM_INLINE T normal_dissipation(const NormalResultT<T>& r, T v_n, double dt, T& damping_prev) {
  const T Fd = r.force - r.elastic;
  const T d = -0.5 * (Fd + damping_prev) * v_n * dt;
  damping_prev = Fd;
  return d;
}

BAGDEM_INLINE double hertz_constant(const PairLaw& law, double R_eff) { return (8.0 / 15.0) * law.E_star * std::sqrt(R_eff); }
BAGDEM_INLINE double hertz_energy(const PairLaw& law, double R_eff, double overlap) {
  return hertz_constant(law, R_eff) * overlap * overlap * std::sqrt(overlap);
}

}  // namespace bagdem
