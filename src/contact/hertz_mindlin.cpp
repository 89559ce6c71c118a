// Set-up and time step of the Hertz-Mindlin law (contact/hertz_mindlin.hpp).
#include "bagdem/contact/hertz_mindlin.hpp"

#include <cmath>

#include "bagdem/contact/hertz_theory.hpp"
#include "bagdem/contact/restitution.hpp"

namespace bagdem {

double HertzMindlin::damping_of(double e) { return 2.0 * std::sqrt(5.0 / 6.0) * clamped_beta(e); }

PairLaw HertzMindlin::make(const Material& a, const Material& b, const Interaction& in, double damping) {
  PairLaw law;
  law.kind = kind;
  law.E_star = effective_youngs(a, b);
  law.G_star = effective_shear(a, b);
  law.damping = damping;
  law.tangential_ratio = std::sqrt(4.0 * law.G_star / law.E_star);
  law.friction = in.friction;
  law.rolling = in.rolling_friction;
  law.restitution = in.restitution;
  return law;
}

double HertzMindlin::max_overlap(const PairLaw& law, double m_eff, double R_eff, double v) {
  return hertz::max_overlap(m_eff, R_eff, law.E_star, v);
}

double HertzMindlin::contact_time(const PairLaw& law, double m_eff, double R_eff, double v) {
  return hertz::contact_time(m_eff, R_eff, law.E_star, v);
}

double HertzMindlin::resolved_step(const PairLaw& law, double m_eff, double R_eff, double v, double steps) {
  return hertz::resolved_step(contact_time(law, m_eff, R_eff, v), hertz::damping_parameter(law.damping), steps);
}

}  // namespace bagdem
