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

struct NormalResult {
  double force;       // F_n >= 0 along n, on i (unit: N)
  double stiffness;   // S_n (unit: N/m)
  double elastic;     // F_el (unit: N)
  double gamma_n;     // normal damping coefficient (unit: N s/m); the tangential role derives gamma_t from it
};

BAGDEM_INLINE NormalResult hertz_normal(const ContactGeometry& g, const PairLaw& law) {
  const double sqrt_rd = std::sqrt(g.R_eff * g.overlap);
  const double S_n = 2.0 * law.E_star * sqrt_rd;
  const double F_el = (2.0 / 3.0) * S_n * g.overlap;  // = 4/3 E* sqrt(R*) delta^(3/2)
  const double gamma_n = law.damping * std::sqrt(S_n * g.m_eff);
  const double delta_dot = -g.v_rel.dot(g.n);
  return {std::max(0.0, F_el + gamma_n * delta_dot), S_n, F_el, gamma_n};
}

// Energy dissipated by the normal damping over a step: the trapezoid of this and the previous
// step's damping force F_d = F_n - F_el times the normal displacement v_n dt over the step (v_n from
// g.v_half; velocity Verlet's discrete work of a force). `damping_prev` is updated.
BAGDEM_INLINE double normal_dissipation(const NormalResult& r, double v_n, double dt, double& damping_prev) {
  const double Fd = r.force - r.elastic;
  const double d = -0.5 * (Fd + damping_prev) * v_n * dt;
  damping_prev = Fd;
  return d;
}

BAGDEM_INLINE double hertz_energy(const PairLaw& law, double R_eff, double overlap) {
  return (8.0 / 15.0) * law.E_star * std::sqrt(R_eff) * overlap * overlap * std::sqrt(overlap);
}

}  // namespace bagdem
