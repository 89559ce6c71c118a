// The table of broad-phase kinds (the only place that lists them).
#include "bagdem/neighbour/broad_phase.hpp"

#include <stdexcept>

namespace bagdem {

const std::vector<BroadPhaseKind>& broad_phase_kinds() {
  static const std::vector<BroadPhaseKind> kinds = {
      {"hash", "spatial hashing of cell coordinates (default; best for dense beds)", make_spatial_hash},
      {"kdtree", "nanoflann k-d tree (robust to very wide size distributions)", make_kdtree},
      {"brute", "O(N^2) all pairs (reference for tests; tiny scenes only)", make_brute_force},
  };
  return kinds;
}

std::unique_ptr<BroadPhase> make_broad_phase(const std::string& name) {
  for (const auto& k : broad_phase_kinds())
    if (name == k.name) return k.create();
  throw std::invalid_argument("unknown broad phase '" + name + "'");
}

}  // namespace bagdem
