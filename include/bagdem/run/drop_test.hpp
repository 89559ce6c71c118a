// The bag's restitution from a drop test (docs/reference-study.md, section 5, method ii): the case's contents,
// settled as in the case, are launched at speed V against a wall of the resting cavity (the one
// across the larger gap along the excitation direction e), and e_drop = -v_after / v_before of
// their centre of mass along e (the study's Eq. (9)). The impact is the force on the wall ahead, every wave
// of it, foot to foot (reduce/impacts.hpp, merged): v_before is the velocity before its first foot,
// v_after the fastest rebound from the pulse's centroid on (a bag's contents leave in waves; once
// free, only friction slows them; a single ball's rebound speed is constant after its contact). The pulse is found above a quarter of its peak (sliding friction on
// the floor pulls on the cavity along e too; the test fails when the peak is not at least twice the
// largest friction force mu M g), and its feet reach down to where it rises out of the sliding.
// The run stops when that force has stayed below the threshold for a settling span (100 steps and
// 1% of the flight time) with the contents no longer approaching, or as soon as, on the way back,
// another wall pushes the contents, so that the rebound is measured before any other wall acts on
// it. The contact time is the pulse's span foot to foot (no force threshold, so it does not shrink
// with the step). e_drop lies in [0, 1] (a rebound faster than the approach by less than the
// integration's tolerance is an elastic impact, e_drop = 1), or the test fails saying why. Gravity stays as in the
// case; the cavity is held fixed and a primary structure is not simulated.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "bagdem/scene.hpp"

namespace bagdem {

// The drop's record: the wall force along the launch and the contents' approach velocity at each
// step (drop.csv).
struct DropSeries {
  std::vector<double> time, wall_force, approach_velocity;  // s, N, m/s
};

struct DropResult {
  double speed = 0;          // launch speed V (m/s)
  double v_before = 0;       // centre-of-mass speed along the impact normal just before contact (m/s)
  double v_after = 0;        // rebound speed after it (m/s, positive away from the wall)
  double restitution = 0;    // e_drop = v_after / v_before
  double peak_force = 0;     // largest wall force during the impact (N)
  double duration = 0;       // the impact's span, foot to foot (s)
  double gap = 0;            // gap crossed before the impact (m)
  double tolerance = 0;      // how far above 1 an elastic impact's e_drop may come out: (dt / duration)^2,
                             // velocity Verlet's energy error over the contact's steps; within it e_drop is 1
  std::string note;          // how the launch speed was found, when the case's own gave no figure
  DropSeries series;
};

// Runs the drop; speed <= 0 takes the case's expected impact speed (the cavity's speed amplitude
// of its motion, or of the primary's bare response), and where the impact at that speed does not
// stand out of the sliding friction (or the contents do not reach the wall in time) launches again
// twice as fast, up to 16 times that speed, saying so in `note`. Throws InputError when the scene
// has no contents or no excitation direction, RunError if the run goes unstable or no launch gave
// a figure. Writes out_dir/drop.csv (write_drop_series) and returns the figures.
DropResult run_drop_test(const Scene& scene, double speed, const std::filesystem::path& out_dir, bool quiet);
void write_drop_series(const std::filesystem::path& path, const DropSeries& series);
// drop_result.csv: the figures above, one row (read by `bagdem reduce`).
void write_drop_result(const std::filesystem::path& path, const DropResult& result, const Scene& scene);

}  // namespace bagdem
