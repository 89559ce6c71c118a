// The state of pipelined steps (pipelined.cpp): per range of balls, how far it is and what the
// other ranges read of it; the cavity's path over the pipelined steps; the counts of fused and
// pipelined steps.
#pragma once
#include <atomic>
#include <cstdint>
#include <vector>

#include "bagdem/motion/motion.hpp"
#include "stage.hpp"

namespace bagdem {

struct Pipeline {
  static constexpr std::uint64_t kNever = ~std::uint64_t{0};
  // Per range: its own thread writes it; the others read it once `done` says it is there.
  struct alignas(64) RangeProgress {
    std::atomic<std::uint64_t> done{0};  // steps of the region it finished: its balls are at step `done`
    double travel[4] = {};    // its balls' travel at step s, slot s % 4 (no range gets more than 2 steps ahead of another)
    bool near[4] = {};        // one of its balls near the skin's edge at step s (kSkinStep), slot s % 4
    double far = 0;           // the travel up to which none of its balls can be near the edge (near_skin_edge)
    double cross = 0;         // the travel scale of the cross pairs into it at its last step (cross_travel)
    double step = 0;          // the largest distance one of its balls moved in its last step (unit: m)
    StageFold fold;           // its folds of the step in progress, then of its last step
    std::uint64_t failed = kNever;  // the step at which its guards failed
  };
  std::vector<RangeProgress> progress;
  std::atomic<std::uint64_t> stop_before{0};  // no range starts this pipelined step or a later one
  double region_travel = 0;                   // the pairs' travel when the pipelined steps began (cross_travel)
  std::vector<CavityState> cavity_path;       // the cavity at each pipelined step (0: at the start)
  std::vector<WallMotion> wall_path;          // the walls' motion over each pipelined step
  std::uint64_t region_steps = 0;             // the region planned (plan_pipelined): at most this many steps
  std::uint64_t region_done = 0;              // the steps it did (pipelined_region)
  std::uint64_t pipelined_steps = 0;
  std::uint64_t fused_steps = 0;
};

}  // namespace bagdem
