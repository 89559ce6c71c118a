// The wall contacts component: the balls' contacts with the cavity's analytic walls (planes,
// cylinders), their histories and which walls each ball may touch. Its stage: walls (walls.cpp).
#pragma once
#include <cstdint>
#include <vector>

#include "history.hpp"

namespace bagdem {

struct WallContacts {
  // Histories per wall then per ball (slot): the balls on one wall of a bed (its floor) come in
  // runs in the stepper's order (spatial_order), so their histories on that wall lie side by side
  // (Stepper::wall_slot).
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
  std::vector<std::uint8_t> near_scratch;  // find_near_walls: per ball, 1 if in near_balls (kept: no allocation in a step)
  // Its checkpoint fields (step/checkpoint.cpp): one list for writing and reading, so the two
  // cannot disagree. IO: pod(x) and vec(v).
  template <class IO>
  void checkpoint(IO& io) {
    hist.fields(io);
    io.vec(touch);
  }
};

}  // namespace bagdem
