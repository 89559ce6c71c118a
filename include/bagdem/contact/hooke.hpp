// The linear spring-dashpot law ("hooke" in LIGGGHTS and LAMMPS' gran/hooke/history): a normal
// spring k_n and dashpot gamma_n, a tangential spring k_t with history, dashpot gamma_t and a
// Coulomb cap, and the same optional rolling role as Hertz-Mindlin (rolling.hpp).
//
//   F_n = k_n delta + gamma_n d(delta)/dt, gamma_n = 2 zeta sqrt(k_n m*)     not clamped: as LAMMPS'
//         gran/hooke, the force may pull at the end of an impact, so the closed forms below hold
//   zeta = -ln(e) / sqrt(pi^2 + ln(e)^2)       the damping ratio of restitution e (e = 1: zeta = 0)
//   S_t  = k_t = k_n x stiffness_ratio (default 2/7), gamma_t = gamma_n sqrt(k_t/k_n)
//   F_t  = F_e - gamma_t v_t, |F_t| <= mu_s max(F_n, 0)           the tangential role of mindlin.hpp
//                                                                  with a constant stiffness
// A head-on impact is a damped linear oscillator (omega_0 = sqrt(k_n/m*), omega_d = omega_0
// sqrt(1 - zeta^2)); it lasts t_c = pi / omega_d and returns e = exp(-zeta pi / sqrt(1 - zeta^2))
// (e.g. Schwager & Poeschel, Computational Granular Dynamics, 2005, sec. 3.1.1).
// Elastic energy U_n = k_n delta^2 / 2.
#pragma once
#include <cmath>
#include <numbers>

#include "bagdem/contact/geometry.hpp"
#include "bagdem/contact/hertz_mindlin.hpp"
#include "bagdem/material.hpp"

namespace bagdem {

namespace hooke {

// The damping ratio that returns restitution e, and its inverse.
inline double damping_ratio(double e) {
  const double l = std::log(e);
  return l < 0 ? -l / std::sqrt(std::numbers::pi * std::numbers::pi + l * l) : 0.0;  // e = 1: +0, not -0
}
inline double restitution(double zeta) { return std::exp(-zeta * std::numbers::pi / std::sqrt(1 - zeta * zeta)); }
// Duration of a head-on impact of effective mass m_eff (unit: s).
inline double contact_time(double k, double m_eff, double zeta) {
  return std::numbers::pi / (std::sqrt(k / m_eff) * std::sqrt(1 - zeta * zeta));
}

}  // namespace hooke

// T and Law as in hertz.hpp: the same result fields, S_n = k_n at every overlap.
template <class T, class Law>
BAGDEM_INLINE NormalResultT<T> hooke_normal(const ContactGeometryT<T>& g, const Law& law) {
  const T S_n = law.stiffness + splat<T>(0.0);  // a T whether the law is one contact's or per lane (+ 0 is exact)
  const T F_el = S_n * g.overlap;
  const T gamma_n = law.damping * sqrt_of(S_n * g.m_eff);
  const T delta_dot = -dot(g.v_rel, g.n);
  return {F_el + gamma_n * delta_dot, S_n, F_el, gamma_n};
}

struct Hooke {
  static constexpr LawKind kind = LawKind::Hooke;
  using TangentialState = TangentialHistory;  // the tangential spring (mindlin.hpp, constant stiffness)
  using RollingState = RollingHistory;        // rolling.hpp, as Hertz-Mindlin's
  static constexpr double kOpenedMean = 1.0;  // mindlin_tangential: a constant S_t
  // The tangential role's Coulomb cap mu_s max(F_n, 0): a pulling normal force holds nothing.
  template <class T>
  static BAGDEM_INLINE NormalResultT<T> friction_load(NormalResultT<T> nr) {
    nr.force = max_of(splat<T>(0.0), nr.force);
    return nr;
  }
  template <class T, class Law>
  static BAGDEM_INLINE NormalResultT<T> normal(const ContactGeometryT<T>& g, const Law& law) {
    return hooke_normal(g, law);
  }
  static double stiffness(const PairLaw& law, double, double) { return law.stiffness; }
  static double tangential_stiffness(const PairLaw& law, double, double) {
    return law.stiffness * law.tangential_ratio * law.tangential_ratio;
  }
  static double energy(const PairLaw& law, double, double delta) { return 0.5 * law.stiffness * delta * delta; }
  // U = sign k delta^2 / 2, U' = sign k delta.
  static BAGDEM_INLINE EulerShare euler_share(const PairLaw& law, double, double delta, double sign) {
    return {sign * 0.5 * law.stiffness * delta * delta, sign * law.stiffness * delta};
  }
  // The stiffness is the same at every overlap: a surface contact's law sees the overlap whose
  // force is the Euler sum's along its normal, the sum of sign delta cos.
  static BAGDEM_INLINE double overlap_term(double sign, double delta, double cos) { return sign * delta * cos; }
  static BAGDEM_INLINE double overlap_of(double sum) { return sum; }
  static double damping_of(double e) { return 2 * hooke::damping_ratio(e); }
  static PairLaw make(const Material& a, const Material& b, const Interaction& in, double damping);
  // The undamped amplitude v / omega_0; the impact's duration (and the damping time m*/gamma_n
  // when it is shorter) by `steps` steps.
  static double max_overlap(const PairLaw& law, double m_eff, double R_eff, double v);
  static double contact_time(const PairLaw& law, double m_eff, double R_eff, double v);  // pi / omega_d
  static double resolved_step(const PairLaw& law, double m_eff, double R_eff, double v, double steps);
};

}  // namespace bagdem
