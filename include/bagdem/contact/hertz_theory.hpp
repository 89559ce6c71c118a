// Closed-form results of Hertz theory, used to choose the time step and as test references.
//   t_c       = 2.87 (m*^2 / (R* E*^2 v))^(1/5)                 contact duration (Johnson 1985, 11.24)
//   delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5)             maximum overlap (Johnson 1985, 11.23)
//   dt_R      = pi R sqrt(rho/G) / (0.1631 nu + 0.8766)          Rayleigh time (Li et al. 2005)
//   delta_static = (3 m g / (4 E* sqrt(R*)))^(2/3)              sphere resting under gravity
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>

namespace bagdem::hertz {

inline double contact_time(double m_eff, double R_eff, double E_star, double v) {
  return 2.87 * std::pow(m_eff * m_eff / (R_eff * E_star * E_star * v), 0.2);
}
inline double max_overlap(double m_eff, double R_eff, double E_star, double v) {
  return std::pow(15.0 * m_eff * v * v / (16.0 * E_star * std::sqrt(R_eff)), 0.4);
}
inline double rayleigh_time(double R, double density, double E, double nu) {
  const double G = E / (2 * (1 + nu));
  return std::numbers::pi * R * std::sqrt(density / G) / (0.1631 * nu + 0.8766);
}
inline double static_overlap(double weight, double R_eff, double E_star) {
  return std::pow(3.0 * weight / (4.0 * E_star * std::sqrt(R_eff)), 2.0 / 3.0);
}
// Dimensionless damping a = sqrt(5)|beta| of the impact ODE (restitution.hpp) from PairLaw::damping
// = 2 sqrt(5/6)|beta|.
inline double damping_parameter(double law_damping) { return law_damping * std::sqrt(6.0) / 2.0; }
// Step that resolves a contact: its duration t_c by `steps` steps, and, when damping dominates
// (a > 2/3, i.e. e < ~0.45), its viscous time t_c / (1.5 a) likewise. Measured (tests/impact.hpp
// sweep, steel): recovered e within 1% for e = 0.01..0.99 with steps = 40.
inline double resolved_step(double t_c, double a, double steps) {
  return t_c / (steps * std::max(1.0, 1.5 * a));
}

// Critical step of bagdem's integrator for a damped oscillator of frequency w and damping ratio z.
// Velocity Verlet with the dashpot on the half-step velocity is stable up to 2/w (sqrt(1+z^2) - z);
// bagdem's dashpot sees the velocity predicted to the step's end, v + dt/2 a, which acts as twice
// the damping: the limit is 2/w (sqrt(1+4z^2) - 2z) (linear stability analysis; matches measured
// divergence within 1% at e = 0.5, tests/test_stability_limit.cpp).
inline double critical_step(double w, double z) { return 2.0 / w * (std::sqrt(1 + 4 * z * z) - 2 * z); }

}  // namespace bagdem::hertz
