// The wall contacts component: the balls' contacts with the cavity's analytic walls (planes,
// cylinders), their histories and which walls each ball may touch. Its stage: walls (walls.cpp).
#pragma once
#include <cstdint>
#include <vector>

#include "bagdem/vec3.hpp"
#include "history.hpp"

namespace bagdem {

struct Balls;
struct CavityFrame;
struct Scene;
struct StepContext;

struct WallContacts {
  // Histories per wall then per ball (slot): the balls on one wall of a bed (its floor) come in
  // runs in the stepper's order (spatial_order), so their histories on that wall lie side by side
  // (slot).
  ContactHistories hist;
  std::vector<std::uint32_t> touch;  // per ball: bit w set = touched wall w at the last step
  // Per ball: bit w set = wall w was within skin of the ball's surface at the last neighbour build.
  // The list holds while no ball and not the cavity moved more than skin/2 since (kick_drift,
  // move_cavity), so the walls not in it cannot be touched: the wall stage skips them.
  std::vector<std::uint32_t> near;
  // The balls, ascending, that may touch a wall or leave the cavity's bounds before the next build:
  // a wall near or the centre within skin of the bounds at the build. The others are skipped by the
  // wall stage when it has nothing else to do for them (advance).
  std::vector<std::uint32_t> near_balls;
  // The slot of ball p on wall w, of `balls` balls.
  std::size_t slot(std::size_t p, std::size_t w, std::size_t balls) const { return w * balls + p; }
  std::vector<std::uint8_t> near_scratch;  // find_near_walls: per ball, 1 if in near_balls (kept: no allocation in a step)
  // Its checkpoint fields (step/checkpoint.cpp): one list for writing and reading, so the two
  // cannot disagree. IO: pod(x) and vec(v).
  template <class IO>
  void checkpoint(IO& io) {
    hist.fields(io);
    io.vec(touch);
  }
};

// What the walls stage works on: the step, the scene, the cavity's frame, the balls, the wall
// contacts, the balls' load moments on the structure (StructureCoupling::cavity_load), and whether
// it does the balls' kick while their forces are at hand (no later stage adds to them).
struct WallStage {
  const StepContext& ctx;
  const Scene& scene;
  const CavityFrame& frame;
  Balls& balls;
  WallContacts& walls;
  std::vector<Vec3>& cavity_load;
  bool kick;
};

}  // namespace bagdem
