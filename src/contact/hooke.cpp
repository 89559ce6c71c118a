// Set-up and time step of the linear spring-dashpot law (contact/hooke.hpp).
#include "bagdem/contact/hooke.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace bagdem {

PairLaw Hooke::make(const Material& a, const Material& b, const Interaction& in, double damping) {
  PairLaw law;
  law.kind = kind;
  law.E_star = effective_youngs(a, b);  // for reports: the law reads k_n and k_t
  law.G_star = effective_shear(a, b);
  law.stiffness = in.stiffness;
  law.damping = damping;
  law.tangential_ratio = std::sqrt(in.stiffness_ratio);
  law.friction = in.friction;
  law.rolling = in.rolling_friction;
  law.restitution = in.restitution;
  return law;
}

double Hooke::max_overlap(const PairLaw& law, double m_eff, double, double v) { return v / std::sqrt(law.stiffness / m_eff); }

double Hooke::contact_time(const PairLaw& law, double m_eff, double, double) {
  return hooke::contact_time(law.stiffness, m_eff, 0.5 * law.damping);
}

double Hooke::resolved_step(const PairLaw& law, double m_eff, double R_eff, double v, double steps) {
  const double zeta = 0.5 * law.damping, w0 = std::sqrt(law.stiffness / m_eff);
  const double t_c = contact_time(law, m_eff, R_eff, v);
  const double damping_time = zeta > 0 ? std::numbers::pi / (2 * zeta * w0) : t_c;  // pi m*/gamma_n
  return std::min(t_c, damping_time) / steps;
}

}  // namespace bagdem
