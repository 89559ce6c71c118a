// Materials, pairwise interaction parameters, and the per-material-pair table
// the contact kernel reads (effective moduli per docs/reference-study.md, section 4).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace bagdem {

// The contact laws (contact/law.hpp holds their table): which one a pair of materials follows.
enum class LawKind : std::uint8_t { HertzMindlin, Hooke };

// The normal coefficient of restitution a user may ask of any law: e in (0, 1] (1: elastic). The
// reduction's formulas have their own domains ((0, 1) for the two-impact motion, [0, 1) for the
// continuum model's), checked where they are used: a fitted e is not an input.
inline constexpr const char* kRestitutionRange = "(0, 1]";
constexpr bool restitution_in_range(double e) { return e > 0 && e <= 1; }

struct Material {
  std::string name;
  double density = 0;        // (unit: kg/m^3)
  double youngs_modulus = 0; // (unit: Pa)
  double poisson_ratio = 0;  // (dimensionless, in (-1, 0.5))
};

// What a user states for a pair of materials.
struct Interaction {
  double restitution = 0.5;       // normal coefficient of restitution e, in kRestitutionRange
  double friction = 0.0;          // Coulomb sliding friction coefficient mu_s >= 0
  double rolling_friction = 0.0;  // rolling resistance coefficient mu_r >= 0 (0 = off)
  LawKind law = LawKind::HertzMindlin;  // interactions.NAME.law
  double stiffness = 0.0;         // Hooke: normal spring k_n (unit: N/m)
  double stiffness_ratio = 2.0 / 7.0;  // Hooke: tangential spring k_t / k_n (LAMMPS' default)
};

// Everything the kernel needs for one pair of materials, computed once at set-up.
struct PairLaw {
  LawKind kind = LawKind::HertzMindlin;  // which law's roles the kernels run (contact/law.hpp)
  double E_star = 0;        // effective Young's modulus 1/E* = sum (1-nu^2)/E (unit: Pa)
  double G_star = 0;        // effective shear modulus 1/G* = sum 2(2-nu)(1+nu)/E (unit: Pa)
  double damping = 0;       // damping factor (dimensionless): gamma = damping x sqrt(S_n m*); 2 zeta for Hooke,
                            // 2 sqrt(5/6)|beta| for Hertz-Mindlin
  double tangential_ratio = 0;  // sqrt(S_t / S_n) (sqrt(4 G*/E*), sqrt(k_t/k_n)): gamma_t = gamma_n * this
  double stiffness = 0;     // Hooke: normal spring k_n (unit: N/m); 0 for Hertz-Mindlin
  double friction = 0;      // Coulomb sliding friction mu_s (dimensionless)
  double rolling = 0;       // rolling resistance mu_r (dimensionless)
  double restitution = 1;   // the requested e (dimensionless; for reports, not read by the kernel)
};

// Square table of PairLaw indexed by material index (particles and walls share the index space).
struct PairLawTable {
  int n = 0;
  std::vector<PairLaw> laws;  // n*n, symmetric
  const PairLaw& operator()(int a, int b) const { return laws[static_cast<size_t>(a * n + b)]; }
};

// E* and G* of two materials (docs/reference-study.md, section 4; Johnson, Contact Mechanics, 1985).
double effective_youngs(const Material& a, const Material& b);
double effective_shear(const Material& a, const Material& b);

}  // namespace bagdem
