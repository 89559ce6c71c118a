// The stages of one time step, in order, and what they share. Every way of running a step goes
// through the one table of stages (stepper.cpp, kStages): one after the other (staged), each on the
// clock (profiling), or with pairs, walls and the next step's drift in one parallel region (fused;
// many fused steps on several threads: pipelined.cpp).
//
//   kick_drift    v += dt/2 F/m, x += dt v, w += dt/2 T/I         velocity Verlet, first half
//                 (balls and film nodes; balls.cpp)
//   move_cavity   cavity position and velocity at t + dt (prescribed, or from the structure)
//   neighbours    renew the Verlet pair list, the walls near each ball and the sphere-triangle
//                 candidate lists when a ball came near the skin's edge at the last step (kSkinStep),
//                 or a film node or the cavity moved more than skin/2 (pair_list.cpp)
//   pairs         each candidate pair that may touch (PairState::wake): geometry -> contact law ->
//                 per-pair force and torque (pair_kernel.cpp, on the threads' ranges)
//   walls         each ball: its wall contacts (walls.cpp)
//   triangles     each ball: its contacts with triangulated surfaces, the bag's film and STL walls
//                 (surfaces.cpp)
//   film          the bag's film: membrane, strings, film-wall contacts, the balls' loads on its
//                 nodes (film.cpp)
//   structure     the primary structure carrying the cavity: the contents' load on it, its external
//                 force, its acceleration (structure.cpp)
//   kick          v += dt/2 F/m, w += dt/2 T/I                     velocity Verlet, second half
//                 (the balls' kick is done in the wall stage when no triangulated surface follows,
//                 and between the steps of one advance() in the next step's kick_drift)
//   guards        NaN, excessive overlap, a ball outside the cavity or across the film, a ball too
//                 fast for the skin (kSkinStep) -> RunError (guards.cpp)
//
// Velocity Verlet is symplectic and second order (Swope et al., J. Chem. Phys. 76, 1982). Springs
// advance with the half-step motion; dashpots see the velocity predicted to the end of the step,
// v(n+1/2) + dt/2 F(n)/m (LAMMPS and LIGGGHTS use the half-step velocity, a first-order error in the
// restitution when damping dominates).
// Determinism: every per-particle sum runs in a fixed order (pairs by partner index, then walls in
// wall order), and totals are summed over particles in index order, so results are bitwise equal
// for any thread count. The index order is the stepper's own: set-up sorts the balls spatially
// (neighbour/spatial_order.hpp), so that each thread's contiguous range of balls is a compact piece
// of the bed (PairState); outputs are written in the scene's order.
#pragma once
#include <cstdint>

#include "bagdem/vec3.hpp"

namespace bagdem {

enum class Stage : std::uint8_t { kick_drift, move_cavity, neighbours, pairs, walls, triangles, film, structure, kick, guards };

// The mode of a force evaluation: at rest (set-up, and the structure's release, when the forces are
// evaluated without time passing: dt = 0, so contacts add no history and nothing is tallied), or
// a time step.
enum class StepMode : std::uint8_t { set_up, step };

// Where the balls' velocity Verlet stands between the stages (advance() defers a step's second
// half-kick of the balls to the next step's kick_drift, which applies the same force twice in the
// same order; fused, the pair stage does the next kick_drift itself):
//   due       this step's kick_drift is to be done, the last step's kick is complete
//   pending   this step's kick_drift is to be done and finishes the last step's kick first
//   drifted   this step's kick_drift is done (fused_contacts, pair_schedule.cpp)
enum class BallKick : std::uint8_t { due, pending, drifted };

// What the stages of the step in progress share; Stepper::begin_step sets it.
struct StepContext {
  StepMode mode = StepMode::set_up;
  double dt = 0;  // the step (unit: s); 0 in set-up: no time passes
  bool stepping() const { return mode == StepMode::step; }
  // Enters mode m: a step of `step` seconds, or set-up (dt = 0).
  void enter(StepMode m, double step) {
    mode = m;
    dt = m == StepMode::step ? step : 0.0;
  }
  // This step's kick of the balls is left to the next step's kick_drift (advance, between two of
  // its steps; only when the wall stage would do it: no triangulated surface). Set per step.
  bool defer_kick = false;
  BallKick balls = BallKick::due;
  // The step in progress (Stepper::steps_done() before it ends): its forces are at the positions
  // of step `step + 1` (in set-up, at step 0's). Set per step.
  std::uint64_t step = 0;
};

// The cavity's motion at a lab point: its displacement, the velocity at the end of the step, the
// mean velocity over the step and the step's displacement (Stepper::motion_at).
struct WallMotion {
  Vec3 pos, vel, half, step;
};

// What the ball stages fold over the balls (max, min, and, or: the same for any order and team):
// the guards' values and the largest step.
struct StageFold {
  double excess = -1e300;         // pairs and walls: max of overlap - max_overlap x smaller radius (unit: m)
  double min_dist = 1e300;        // walls: min of the centres' distances inside the cavity (unit: m)
  bool kicked_finite = true;      // walls: every velocity finite after the kick done there
  double step2 = 0;               // drift: the largest |x(n+1) - x(n)|^2 of a ball (unit: m^2)
  bool finished_finite = true;    // drift: every velocity finite after the pending kick (Finish)
  void merge(const StageFold& o);
};

}  // namespace bagdem
