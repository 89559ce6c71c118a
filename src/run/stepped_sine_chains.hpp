// Internal to src/run: how a stepped sine shares its points among its chains
// (excitation.chains, run/stepped_sine.hpp).
//
// A chain is a simulation of its own, started from the settled contents; it runs its points in
// order, each from the state its previous point left, and its first point from the start the
// stepped sine's first point has (the bare structure's steady state with excitation.start = "steady").
// The chains run side by side on the threads given, but which chain runs which point is set by the
// case alone, so the results are the same for any thread count:
//  - the planned frequencies are cut into `chains` contiguous blocks, in order, the first blocks a
//    point longer when the count does not divide; chain k runs block k in the list's order, as
//    the serial stepped sine would. A bag's state off resonance depends on its history: run down from
//    above the peak, a chain met its first point (the pipe's 94 Hz, Gamma below 1) with a freshly
//    settled bag that barely moved, where the serial stepped sine arrives with one shaken loose at the
//    peak; C_b and M_eff there fell outside the serial stepped sine's interval over 5 seeds;
//  - the peak refinement runs in rounds of up to `chains` points per mode (refine_round). The
//    round's points, mode after mode, go to the chains in turn: point j to chain j mod chains.
// With one chain this is the serial stepped sine: every point from the state of the one before.
#pragma once
#include <complex>
#include <cstddef>
#include <vector>

#include "stepped_sine_peaks.hpp"

namespace bagdem {

// A point of the stepped sine and the chain that runs it. `index` is the point's place in the stepped sine's
// tables (the planned points, then the refinement's in the order of its rounds).
struct ChainTask {
  static constexpr std::size_t none = static_cast<std::size_t>(-1);
  std::size_t index = 0;
  double frequency = 0;  // requested (unit: Hz)
  std::size_t chain = 0;
  // The point whose contents model the start (excitation.predict): the chain's previous point, or
  // for the refinement the written point nearest in frequency; none for a chain's first point.
  std::size_t model = none;
};

// The chains a stepped sine of `planned` frequencies runs: `chains`, at most one per frequency.
std::size_t chain_count(std::size_t chains, std::size_t planned);

// The planned frequencies as tasks, block k to chain k, each chain's in the order it runs them.
std::vector<ChainTask> planned_tasks(const std::vector<double>& frequencies, std::size_t chains);

// The refinement's rounds: ceil(refine / chains); round r places min(chains, refine - r chains)
// points per mode.
std::size_t refinement_rounds(std::size_t refine, std::size_t chains);
std::size_t round_points(std::size_t refine, std::size_t chains, std::size_t round);

// A round's tasks from the points done so far (numbered from `first_index`): per mode
// (group_by_mode), `per_mode` frequencies dividing the gap between the largest |H| and its larger
// neighbour into equal parts (refinement_frequencies), mode after mode; each modelled on the done
// point nearest in frequency.
std::vector<ChainTask> refinement_tasks(const Primary& P, const std::vector<SteppedSinePoint>& done, std::size_t per_mode,
                                        std::size_t chains, double dt, std::size_t first_index);

// The contents' dynamic stiffness at the cavity, Z = -L / U (the first harmonics of their force on
// it and of its displacement) measured at point p, taken as a mass and a dashpot
// (Z = -w^2 M_e + i w C_e) and carried to circular frequency w: how a point's start predicts the
// contents (excitation.predict, Primary::steady_amplitudes). NaN when the cavity did not move.
std::complex<double> contents_stiffness(const SteppedSinePoint& p, double w);

}  // namespace bagdem
