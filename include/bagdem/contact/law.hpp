// The contact laws, one table: a law is registered by the name a case gives it
// (interactions.NAME.law) and is its normal, tangential and rolling roles (a type such as
// HertzMindlin or Hooke, each in its own header) plus what the set-up, the time step, the energy
// budget and the film ask of it. The kernels run a contact's roles by its PairLaw::kind
// (visit_law); everything else asks the table row.
//
// Adding a law: its header (the roles and the functions of Hooke's, hooke.hpp), a .cpp for its
// set-up, a row in src/contact/laws.cpp, a LawKind and a case in visit_law below. docs/design.md.
#pragma once
#include <span>
#include <string>
#include <string_view>
#include <type_traits>

#include "bagdem/contact/hertz_mindlin.hpp"
#include "bagdem/contact/hooke.hpp"
#include "bagdem/material.hpp"

namespace bagdem {

// Calls fn(L{}) with L the law type of kind k; the kernels' one switch over the laws.
template <class Fn>
BAGDEM_INLINE decltype(auto) visit_law(LawKind k, Fn&& fn) {
  switch (k) {
    case LawKind::Hooke:
      return fn(Hooke{});
    case LawKind::HertzMindlin:
      break;
  }
  return fn(HertzMindlin{});
}

// Calls fn(L{}) for every law type L: the lanes of mixed laws run each (surface_law.hpp).
template <class Fn>
void for_each_law(Fn&& fn) {
  fn(HertzMindlin{});
  fn(Hooke{});
}

// Every law's histories are those the stepper stores per contact (step/history.hpp).
template <class L>
inline constexpr bool kStoredHistories = std::is_same_v<typename L::TangentialState, TangentialHistory> &&
                                         std::is_same_v<typename L::RollingState, RollingHistory>;
static_assert(kStoredHistories<HertzMindlin> && kStoredHistories<Hooke>,
              "a law with other histories needs their storage in step/history.hpp");

// The elastic energy of the normal spring of `law` at overlap delta (unit: J), for the energy budget.
inline double law_energy(const PairLaw& law, double R_eff, double delta) {
  return visit_law(law.kind, [&](auto L) { return decltype(L)::energy(law, R_eff, delta); });
}

struct ContactLawRow {
  std::string_view name;     // interactions.NAME.law
  LawKind kind;
  std::string_view summary;  // one line, for docs and `bagdem check`
  std::string_view keys;     // the interaction keys it reads besides restitution and the frictions
  bool from_moduli;          // its stiffness follows the materials' moduli (the Rayleigh time limits the step)
  bool pulls;                // its normal force may pull at the end of an impact (not clamped at zero)
  double (*damping_of)(double e);  // PairLaw::damping for restitution e
  PairLaw (*make)(const Material& a, const Material& b, const Interaction& in, double damping);
  double (*stiffness)(const PairLaw& law, double R_eff, double delta);             // S_n (unit: N/m)
  double (*tangential_stiffness)(const PairLaw& law, double R_eff, double delta);  // S_t (unit: N/m)
  double (*energy)(const PairLaw& law, double R_eff, double delta);                // U_n (unit: J)
  // A head-on impact at speed v: its largest overlap (unit: m), its duration (unit: s) and the step
  // that resolves it.
  double (*max_overlap)(const PairLaw& law, double m_eff, double R_eff, double v);
  double (*contact_time)(const PairLaw& law, double m_eff, double R_eff, double v);
  double (*resolved_step)(const PairLaw& law, double m_eff, double R_eff, double v, double steps);
};

std::span<const ContactLawRow> contact_laws();
const ContactLawRow& contact_law(LawKind kind);
const ContactLawRow* find_contact_law(std::string_view name);  // null: no such law
std::string contact_law_names();                               // "\"a\", \"b\"" for messages

}  // namespace bagdem
