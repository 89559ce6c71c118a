// Internal to src/run: what a stepped sine carries across an interruption (checkpoint.bin of
// kind "sweep", checkpoint_file.hpp). A stepped sine is checkpointed when settling ends and after each
// point written (and during settling on SIGINT/SIGTERM); --resume continues from there: the points
// written are restored, each chain (stepped_sine_chains.hpp) continues from its state after its last point
// written, and a point not written is run again from its start.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "bagdem/io/results_file.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "bagdem/run/stepped_sine.hpp"
#include "bagdem/step/dampers.hpp"

namespace bagdem {

// Why a stepped sine stops before its end: SIGINT/SIGTERM (`signal`), or 0 for the testing aid
// RunOptions::stop_after_steps (as if killed: nothing more is written).
struct SteppedSineHalt {
  int signal;
};

// What `bagdem run` prints when `signal` stopped a stepped sine at time t (s) after `points` points.
std::string interrupted_message(int signal, double t, std::size_t points, const std::filesystem::path& out);

struct SteppedSineState {
  bool settled = false;               // settling is over: the points below follow it
  double clearance = 0;               // the contents' free travel when settling ended (ReductionContext)
  SeriesLengths lengths;              // rows of results.h5.part's series (frames) at the checkpoint
  std::vector<SteppedSinePoint> points;     // the points done, in order
  std::vector<ReducedRow> reduced;    // their reduction
  std::vector<double> frame_times;    // times of the frames written (results.xmf)
  std::vector<std::vector<char>> images;  // per chain, its simulation's state after its last point
                                          // written (Dampers::image); one, the settled state,
                                          // before the chains start
  // Several dampers: per damper but the case's own, its clearance and its reduced rows.
  std::vector<double> more_clearance;
  std::vector<std::vector<ReducedRow>> more_reduced;
};

// Readies `out` for a stepped sine: with `resume`, the state from out/checkpoint.bin and the first chain's
// simulation state in `sim` (InputError when it or results.h5.part is missing or unusable);
// otherwise a fresh state and no checkpoint. Either way the earlier run's tables go
// (output_files.hpp).
void start_stepped_sine_state(const std::filesystem::path& out, bool resume, Dampers& sim, SteppedSineState& state);

// Writes out the state, its images included.
void save_stepped_sine_checkpoint(const std::filesystem::path& path, const Scene& scene, const SteppedSineState& state);

// Reads a stepped sine's checkpoint (InputError when it is missing, corrupt, of a run, or of another
// case) into `state`.
void load_stepped_sine_checkpoint(const std::filesystem::path& path, const Scene& scene, SteppedSineState& state);

}  // namespace bagdem
