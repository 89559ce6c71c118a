// Effective moduli per docs/reference-study.md, section 4 (Johnson, Contact Mechanics, 1985, ch. 4 and 7).
#include "bagdem/material.hpp"

#include <cmath>

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

}  // namespace bagdem
