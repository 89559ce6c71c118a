// The neighbours component: what renews the candidate pair list (PairContacts) and decides when:
// the broad phase, the balls' places at the last build, the spare buffers of the last list, and
// the balls' travel since the build. Its stage: neighbours (neighbours.cpp), which renews the
// other candidate lists too (the walls near each ball, the triangulated surfaces').
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "bagdem/neighbour/broad_phase.hpp"
#include "bagdem/step/simulation.hpp"
#include "bagdem/vec3.hpp"
#include "history.hpp"

namespace bagdem {

struct Balls;
struct CavityFrame;
struct CavityTrack;
struct Film;
struct PairContacts;
struct Scene;
struct StructureCoupling;
struct SurfaceContacts;
struct WallContacts;

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
  // The list is renewed one step ahead: before the pairs at a step's positions when, at the step
  // before, a ball was more than skin/2 - kSkinStep x skin from its place at the build
  // (Stepper::kSkinStep).
  static constexpr double kSkinStep = Simulation::kSkinStep;
  // After a drift whose largest step was sqrt(step2), to positions x: the travel, whether the list
  // is renewed before this step's pairs, and whether a ball is near the skin's edge now.
  void end_drift(double step2, const std::vector<Vec3>& x, double skin);
  // Whether a ball of x is near the skin's edge now (if not, far_check_at moves on).
  bool near_skin_edge(const std::vector<Vec3>& x, double skin);
  // Whether balls at most sqrt(d2) from their place at the build are near the skin's edge; if
  // not, far: the travel (now `travel`) up to which they cannot be.
  static bool near_edge_of(double d2, double travel, double& far, double skin);
  // Its checkpoint fields (step/checkpoint.cpp): one list for writing and reading, so the two
  // cannot disagree. IO: pod(x) and vec(v).
  // The rest is derived again from the stored list (Stepper::load_state).
  template <class IO>
  void checkpoint(IO& io) {
    io.pod(builds), io.vec(x_at_build);
  }
};

// What the neighbours stage works on: the scene, the cavity's frame, the balls (read), the lists
// it renews (the pairs', the walls near each ball, the surfaces' candidates, the walls near each
// film node), the cavity's place at the build, and the balls' load moments on the structure (a
// ball with no wall near loads nothing).
struct NeighbourStage {
  const Scene& scene;
  const CavityFrame& frame;
  const Balls& balls;
  Neighbours& nb;
  PairContacts& pairs;
  WallContacts& walls;
  SurfaceContacts& surfaces;
  Film& film;
  CavityTrack& cavity;
  StructureCoupling& structure;
};
// The neighbours stage (stage.hpp): renews the lists when they may not hold (or always: force).
void neighbours_stage(const NeighbourStage& s, bool force_rebuild);
// After a checkpoint is loaded: what follows from the stored list and build positions, without a
// new broad-phase search (the same lists as the run that saved it).
void neighbours_restored(const NeighbourStage& s);

}  // namespace bagdem
