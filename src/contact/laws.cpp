// The table of contact laws (contact/law.hpp).
#include "bagdem/contact/law.hpp"

#include <stdexcept>
#include <string>

namespace bagdem {
namespace {

template <class L>
constexpr ContactLawRow row(std::string_view name, std::string_view summary, std::string_view keys, bool from_moduli, bool pulls) {
  return {name, L::kind, summary, keys, from_moduli, pulls, &L::damping_of, &L::make, &L::stiffness, &L::tangential_stiffness,
          &L::energy, &L::max_overlap, &L::contact_time, &L::resolved_step};
}

const ContactLawRow kLaws[] = {
    row<HertzMindlin>("hertz-mindlin",
                      "Hertz normal force with restitution damping, clamped at zero; Mindlin tangential spring, Coulomb cap",
                      "", true, false),
    row<Hooke>("hooke", "linear spring-dashpot (k_n, gamma_n from e, not clamped); tangential spring k_t, Coulomb cap",
               "stiffness, stiffness_ratio", false, true),
};

}  // namespace

std::span<const ContactLawRow> contact_laws() { return kLaws; }

const ContactLawRow& contact_law(LawKind kind) {
  for (const ContactLawRow& r : kLaws)
    if (r.kind == kind) return r;
  throw std::logic_error("contact_law: a LawKind without a row in src/contact/laws.cpp");
}

const ContactLawRow* find_contact_law(std::string_view name) {
  for (const ContactLawRow& r : kLaws)
    if (r.name == name) return &r;
  return nullptr;
}

std::string contact_law_names() {
  std::string s;
  for (const ContactLawRow& r : kLaws) s += (s.empty() ? "\"" : ", \"") + std::string(r.name) + "\"";
  return s;
}

}  // namespace bagdem
