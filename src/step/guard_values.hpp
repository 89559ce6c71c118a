// The guards' values of the last step (guards.cpp reads them, the stages write them): kept free of
// divisions (the ratios go into messages only).
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>

namespace bagdem {

struct Balls;
struct CavityFrame;
struct Film;
struct Scene;
struct SurfaceContacts;

struct GuardValues {
  bool all_finite = true;        // every velocity finite (kick)
  bool balls_finite = true;      // every ball's velocity finite after the kick of the wall stage
  bool finished_finite = true;   // every ball's velocity finite after kick_drift finished a pending kick
  double overlap_excess = 0;     // max over contacts of overlap - max_overlap x smaller radius (unit: m)
  double min_boundary_distance = 0;  // min over balls of the centre's distance inside the cavity (unit: m)
  std::size_t crossed = static_cast<std::size_t>(-1);  // a ball found across the film this step
  double crossed_depth = 0;      // how far beyond the film's mid-surface (unit: m)
  std::size_t crossed_surface = 0;  // which surface it crossed
  std::size_t mesh_overflow = static_cast<std::size_t>(-1);  // a ball touching more than kMaxMeshContacts features
};

// The guards' test of what the ball stages fold (StageFold), the one test of a whole step
// (Stepper::guards) and of a pipelined range's step (end_range_step): a velocity not finite, an
// overlap beyond the limit, a ball outside the cavity, a ball that moved more than `step_limit` in
// the step (unit: m).
inline bool balls_fail(bool finite, double overlap_excess, double min_boundary_distance, double largest_step, double step_limit) {
  return !finite || overlap_excess > 0.0 || min_boundary_distance < 0.0 || largest_step > step_limit;
}

// What the guards stage reads: the scene, the cavity's frame, the balls, the film, the surfaces,
// the guards' values of the step, the largest step of a ball, the skin's share a step may use
// (Stepper::kSkinStep), the time and step count (for the message), and the largest overlap ratio
// of the pairs and walls (asked for the message only).
struct GuardStage {
  const Scene& scene;
  const CavityFrame& frame;
  const Balls& balls;
  const Film& film;
  const SurfaceContacts& surfaces;
  const GuardValues& guard;
  double largest_step;  // (unit: m)
  double skin_step;
  double time;          // (unit: s)
  std::uint64_t step;
  std::function<double()> largest_overlap_ratio;
};
// The guards stage (guards.cpp): NaN, an overlap beyond the limit, a ball outside the cavity or
// across the film, a film node pressed into a wall, a ball too fast for the skin: RunError saying
// what happened and what to change.
void check_guards(const GuardStage& s);

}  // namespace bagdem
