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

// History of one contact's tangential spring (zero when the contact opens).
struct TangentialHistory {
  Vec3 force = Vec3::Zero();  // elastic tangential force F_e on i (unit: N)
  double stiffness = 0;       // S_t at the previous step (unit: N/m); 0 = new contact
  Vec3 total = Vec3::Zero();  // F_t of the previous step, for the energy tally (unit: N)
};

struct TangentialResult {
  Vec3 force;          // F_t on i (unit: N)
  double dissipated;   // energy dissipated in this step by damping and sliding (unit: J)
};

// `normal` is the normal role's result: S_t = S_n 4G*/E*, gamma_t = gamma_n sqrt(4G*/E*) (no sqrt here).
BAGDEM_INLINE TangentialResult mindlin_tangential(const ContactGeometry& g, const PairLaw& law,
                                           const NormalResult& normal, double dt, TangentialHistory& h) {
  const double F_n = normal.force;
  const Vec3 v_t = g.v_half - g.v_half.dot(g.n) * g.n;  // tangential displacement rate over the step
  const Vec3 v_t_end = g.v_rel - g.v_rel.dot(g.n) * g.n; // tangential velocity the dashpot sees
  const double S_t = normal.stiffness * law.tangential_ratio * law.tangential_ratio;
  const double gamma_t = normal.gamma_n * law.tangential_ratio;

  const double energy_before = h.stiffness > 0 ? h.force.squaredNorm() / (2.0 * h.stiffness) : 0.0;
  Vec3 Fe = carry_spring(h.force, g.n, h.stiffness, S_t);
  // Spring increment over the step with the step's mean stiffness (second order in dt): the mean of
  // the two ends, or for a contact that opened during the step, 2/3 of the end value (S_t grows as
  // sqrt(delta) from zero) over the part of the step since first touch, delta / (d delta/dt).
  if (h.stiffness > 0) {
    Fe -= 0.5 * (h.stiffness + S_t) * dt * v_t;
  } else {
    const double approach = -g.v_half.dot(g.n) * dt;  // overlap gained over a full step (unit: m)
    const double part = approach > g.overlap ? g.overlap / approach : 1.0;
    Fe -= (2.0 / 3.0) * S_t * part * dt * v_t;
  }

  Vec3 Ft = Fe - gamma_t * v_t_end;
  const double cap = law.friction * F_n;
  const double Ft2 = Ft.squaredNorm();
  // Without branches (sliding or sticking changes unpredictably): the factor is exactly 1 when it
  // sticks (then sqrt(Ft2) <= cap; for Ft2 = 0, cap / 0 is inf or NaN and std::min keeps 1).
  const bool slides = Ft2 > cap * cap;
  Ft *= opaque(std::min(1.0, cap / std::sqrt(Ft2)));
  const double keep = opaque(slides ? 0.0 : 1.0);
  Fe = keep * Fe + (1.0 - keep) * Ft;
  // Work of F_t on the relative motion over the step: in velocity Verlet a force's discrete work is
  // the trapezoid of the forces of two steps times the half-step displacement. What the spring did
  // not store was dissipated (by the dashpot, by sliding, or lost in the stiffness rules).
  const double energy_after = Fe.squaredNorm() / (2.0 * S_t);
  const double work = 0.5 * (Ft + h.total).dot(v_t) * dt;
  h.force = Fe;
  h.stiffness = S_t;
  h.total = Ft;
  return {Ft, -work - (energy_after - energy_before)};
}

BAGDEM_INLINE double mindlin_energy(const TangentialHistory& h) {
  return h.stiffness > 0 ? h.force.squaredNorm() / (2.0 * h.stiffness) : 0.0;
}

}  // namespace bagdem
