// The Hertz-Mindlin law, bagdem's default: Hertz's normal force with restitution damping, clamped
// at zero (hertz.hpp), Mindlin's tangential spring with a Coulomb cap (mindlin.hpp) and the
// optional EPSD2 rolling resistance (rolling.hpp). What the kernels, the set-up, the time step,
// the energy budget and the film ask of it; registered in contact/law.hpp.
#pragma once
#include <cmath>

#include "bagdem/contact/hertz.hpp"
#include "bagdem/contact/mindlin.hpp"
#include "bagdem/contact/rolling.hpp"
#include "bagdem/material.hpp"

namespace bagdem {

// A law's share of an Euler term of a surface contact (step/surface_features.hpp): the energy
// sign U(delta) and the force's magnitude sign U'(delta) along the term's normal.
struct EulerShare {
  double energy, force;
};

struct HertzMindlin {
  static constexpr LawKind kind = LawKind::HertzMindlin;
  // Its roles' histories: the tangential spring and the rolling torque (the normal role has none;
  // the energy tally keeps the damping force of the last step for every law).
  using TangentialState = TangentialHistory;
  using RollingState = RollingHistory;
  static constexpr double kOpenedMean = 2.0 / 3.0;  // mindlin_tangential: S_t grows as sqrt(delta)
  // The normal force the tangential role's Coulomb cap reads: F_n itself, never negative here.
  template <class T>
  static BAGDEM_INLINE const NormalResultT<T>& friction_load(const NormalResultT<T>& nr) { return nr; }
  template <class T, class Law>
  static BAGDEM_INLINE NormalResultT<T> normal(const ContactGeometryT<T>& g, const Law& law) {
    return hertz_normal(g, law);
  }
  // Normal and tangential stiffness at overlap delta (unit: N/m); elastic energy (unit: J).
  static double stiffness(const PairLaw& law, double R_eff, double delta) { return 2 * law.E_star * std::sqrt(R_eff * delta); }
  static double tangential_stiffness(const PairLaw& law, double R_eff, double delta) {
    return 8 * law.G_star * std::sqrt(R_eff * delta);
  }
  static double energy(const PairLaw& law, double R_eff, double delta) { return hertz_energy(law, R_eff, delta); }
  // U = sign c delta^(5/2), U' = sign (5/2) c delta^(3/2), c = hertz_constant.
  static BAGDEM_INLINE EulerShare euler_share(const PairLaw& law, double R_eff, double delta, double sign) {
    const double c = hertz_constant(law, R_eff), root = std::sqrt(delta);
    return {sign * c * delta * delta * root, sign * 2.5 * c * delta * root};
  }
  // A surface contact's law sees the overlap whose stiffness is the Euler sum's along its normal:
  // sum of sign S(delta) cos^2, S ~ sqrt(delta), so the overlap is the square of the sum of
  // sign sqrt(delta) cos^2 (step/surface_features.hpp, law_overlaps).
  static BAGDEM_INLINE double overlap_term(double sign, double delta, double cos) { return sign * std::sqrt(delta) * cos * cos; }
  static BAGDEM_INLINE double overlap_of(double sum) { return sum * sum; }
  // Set-up and time step (src/contact/hertz_mindlin.cpp).
  static double damping_of(double e);  // 2 sqrt(5/6)|beta| with |beta| = clamped_beta(e)
  static PairLaw make(const Material& a, const Material& b, const Interaction& in, double damping);
  static double max_overlap(const PairLaw& law, double m_eff, double R_eff, double v);
  static double contact_time(const PairLaw& law, double m_eff, double R_eff, double v);
  static double resolved_step(const PairLaw& law, double m_eff, double R_eff, double v, double steps);
};

}  // namespace bagdem
