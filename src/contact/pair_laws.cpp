// The per-material-pair table of the contact law (contact/pair_laws.hpp).
#include "bagdem/contact/pair_laws.hpp"

#include <map>
#include <utility>

#include "bagdem/contact/law.hpp"

namespace bagdem {

PairLawTable make_pair_laws(const std::vector<Material>& materials,
                            const std::vector<Interaction>& interactions) {
  PairLawTable t;
  t.n = static_cast<int>(materials.size());
  t.laws.resize(materials.size() * materials.size());
  std::map<std::pair<LawKind, double>, double> damping_of;  // Hertz-Mindlin's costs 25-75 ms: once per law and e
  for (int a = 0; a < t.n; ++a) {
    for (int b = 0; b < t.n; ++b) {
      const Interaction& in = interactions[static_cast<size_t>(a * t.n + b)];
      const ContactLawRow& law = contact_law(in.law);
      auto it = damping_of.find({in.law, in.restitution});
      if (it == damping_of.end()) it = damping_of.emplace(std::pair{in.law, in.restitution}, law.damping_of(in.restitution)).first;
      t.laws[static_cast<size_t>(a * t.n + b)] = law.make(materials[a], materials[b], in, it->second);
    }
  }
  return t;
}

}  // namespace bagdem
