// Effective moduli per docs/reference-study.md, section 4 (Johnson, Contact Mechanics, 1985, ch. 4 and 7).
#include "bagdem/material.hpp"

#include "bagdem/contact/restitution.hpp"

#include <cmath>
#include <map>

namespace bagdem {

double effective_youngs(const Material& a, const Material& b) {
  return 1.0 / ((1 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus +
                (1 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus);
}

double effective_shear(const Material& a, const Material& b) {
  auto term = [](const Material& m) {
    return 2.0 * (2.0 - m.poisson_ratio) * (1.0 + m.poisson_ratio) / m.youngs_modulus;
  };
  return 1.0 / (term(a) + term(b));
}

PairLawTable make_pair_laws(const std::vector<Material>& materials,
                            const std::vector<Interaction>& interactions) {
  PairLawTable t;
  t.n = static_cast<int>(materials.size());
  t.laws.resize(materials.size() * materials.size());
  std::map<double, double> beta_of;  // clamped_beta(e) costs 25-75 ms: once per distinct e
  for (int a = 0; a < t.n; ++a) {
    for (int b = 0; b < t.n; ++b) {
      const Interaction& in = interactions[static_cast<size_t>(a * t.n + b)];
      PairLaw& law = t.laws[static_cast<size_t>(a * t.n + b)];
      law.E_star = effective_youngs(materials[a], materials[b]);
      law.G_star = effective_shear(materials[a], materials[b]);
      auto it = beta_of.find(in.restitution);
      if (it == beta_of.end()) it = beta_of.emplace(in.restitution, clamped_beta(in.restitution)).first;
      law.damping = 2.0 * std::sqrt(5.0 / 6.0) * it->second;
      law.tangential_ratio = std::sqrt(4.0 * law.G_star / law.E_star);
      law.friction = in.friction;
      law.rolling = in.rolling_friction;
      law.restitution = in.restitution;
    }
  }
  return t;
}

}  // namespace bagdem
