// Running a resolved scene to completion: the step loop with its recorders (results.h5 as it
// goes), checkpoints, progress, and the files of a finished run.
//
// Files in the output directory (default CASE_DIR/out):
//   results.h5      written as results.h5.part and renamed when the run is complete; a run that
//                   fails renames it results.failed.h5 instead (root attribute "status" says why).
//                   An earlier run's results.h5 stays until a complete run replaces it; the earlier
//                   run's tables (summary.json, reduced.csv, compare.csv, the drop test's, ...:
//                   output_files.hpp) are removed when the run starts
//   results.xmf     XDMF index of the particle frames for ParaView
//   summary.json    written last and atomically: its presence marks a complete run
//   reduced.csv     harmonic cavity motion: the contents' effective parameters (reduce/reduce.hpp)
//   checkpoint.bin  the latest checkpoint (output.checkpoint_interval > 0, and on SIGINT/SIGTERM),
//                   checksummed; --resume continues it
//   dampers/NAME/   several dampers on the structure (case key [[dampers]]): each damper but the
//                   case's own, its results.h5 (without /structure), summary.json and checkpoint.bin
// SIGINT or SIGTERM stops the run after the step in progress: a checkpoint is written, results.h5.part
// gets status "interrupted" and is closed, and the report's `signal` is set (`bagdem run` exits with
// 128 + the signal).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "bagdem/reduce/reduce.hpp"
#include "bagdem/scene.hpp"

namespace bagdem {

struct RunOptions {
  std::string out_dir;   // where outputs go
  int threads = 0;       // OpenMP threads (0 = default)
  bool quiet = false;    // no progress line
  bool resume = false;   // continue from out_dir/checkpoint.bin
  long long stop_after_steps = -1;  // testing aid: stop (as if killed) after this many steps
};

struct RunReport {
  bool complete = false;
  std::string message;                 // failure message, if any
  int signal = 0;                      // SIGINT or SIGTERM stopped the run (a checkpoint was left)
  double wall_seconds = 0;
  double ns_per_particle_step = 0;
  double energy_balance_error = 0;     // relative, see summary.json
  double dissipated_per_cycle = 0;     // J, harmonic motion only (measured part)
  double cycles = 0;
  bool bag = false;                    // the scene has a bag: the figures below are set
  double bag_packing = 0;              // its packing fraction when settling ended
  Vec3 bag_outer = Vec3::Zero();       // its outer length, width, height then (m)
  std::uint64_t film_self_steps = 0;   // steps at which the film met itself (summary.json's film_self_steps)
  std::uint64_t film_wall_stops = 0;   // steps at which the walls' stop held a film node (film_wall_stops)
  std::uint64_t film_self_pairs_max = 0;  // the most node pairs touching at one step
  bool structure = false;              // the scene has a primary structure: the figures below are set
  double response_rms = 0;             // RMS displacement at x_a after release (m)
  double band_response_rms = 0;        // random force: its part in the force's band after excitation.skip (m)
  double acceleration_rms = 0;         // RMS acceleration at x_a (m/s^2)
  double decay_time = 0;               // decay and impulse excitations: time to fall by 20 dB (s)
  double decay_zeta = 0;               // their fitted damping ratio
  std::vector<ReducedRow> reduced;     // harmonic cavity motion: the effective parameters (reduced.csv)
  std::string reduce_message;          // why the reduction was not possible, or (with rows) why e has no estimate
  // Several dampers ([[dampers]]): the others' names and output directories (OUT/dampers/NAME, each
  // with its results.h5 and summary.json; the structure's table is the case's own damper's, in OUT).
  struct DamperOutput {
    std::string name, dir;
  };
  std::vector<DamperOutput> dampers;
};

// Runs the scene; throws InputError for unusable options, returns the report otherwise (a run that
// went unstable returns complete = false with the message; its record results.failed.h5 is readable).
RunReport run_scene(const Scene& scene, const RunOptions& options);

}  // namespace bagdem
