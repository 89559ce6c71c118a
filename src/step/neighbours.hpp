// The neighbours component: what renews the candidate pair list (PairContacts) and decides when:
// the broad phase, the balls' places at the last build, the spare buffers of the last list, and
// the balls' travel since the build. Its stage: neighbours (pair_list.cpp).
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "bagdem/neighbour/broad_phase.hpp"
#include "bagdem/vec3.hpp"
#include "history.hpp"

namespace bagdem {

struct Neighbours {
  std::unique_ptr<BroadPhase> broad;
  std::vector<Vec3> x_at_build;  // the balls' positions at the last neighbour build
  // Buffers of the previous pair list, reused by the next rebuild (no allocation once grown).
  struct Spare {
    CandidatePairs pairs;
    ContactHistories hist;
  } spare;
  std::uint64_t builds = 0;  // neighbour builds so far
  // Since the pair list was installed (derive_pair_buffers): the sum over the steps of the largest
  // distance any ball moved in the step, rounded up, so no ball moved farther (PairState::wake) (unit: m).
  double travel = 0;
  double far_check_at = -1.0;  // travel up to which no ball can be near the skin's edge (near_skin_edge) (unit: m)
  // The pair list is renewed before this step's pairs: a ball was near the skin's edge at the last
  // step (end_drift), or the cavity moved more than skin/2 (move_cavity).
  bool needs_rebuild = false;
  bool near_edge = false;     // a ball is more than skin/2 - kSkinStep x skin from its place at the build
  double largest_step = 0;    // the largest distance a ball moved in the last step (unit: m)
  // Its checkpoint fields (step/checkpoint.cpp): one list for writing and reading, so the two
  // cannot disagree. IO: pod(x) and vec(v).
  // The rest is derived again from the stored list (Stepper::load_state).
  template <class IO>
  void checkpoint(IO& io) {
    io.pod(builds), io.vec(x_at_build);
  }
};

}  // namespace bagdem
