// Internal to src/run: the energy and the first harmonics of a stepped sine point's window, its last 2K
// cycles (run/stepped_sine.hpp).
#pragma once
#include <complex>
#include <deque>

#include "bagdem/reduce/reduce.hpp"
#include "bagdem/run/stepped_sine.hpp"
#include "bagdem/step/dampers.hpp"
#include "bagdem/step/simulation.hpp"
#include "bagdem/structure/response.hpp"

namespace bagdem {

// Energy the run has seen so far, for per-cycle differences.
struct Ledger {
  double work_external = 0, dissipated_structure = 0, dissipated_contents = 0, stored = 0;
};
Ledger ledger(const Simulation& sim);
// Several dampers (one: the same as its simulation's): the structure once, every damper's contents.
Ledger ledger(const Dampers& dampers);

// The last `window` cycles of a point: the ledger at the start of each, the first harmonics of the
// response, the cavity's displacement and the contents' force, and the samples.
struct PointWindow {
  std::deque<Ledger> starts;
  std::deque<Ledger> own;  // several dampers, the case's own damper's window: its own ledger (starts: every damper's)
  std::deque<std::complex<double>> ys, cav, load;
  std::deque<CavitySeries> recent;
};

// The energy balance over the window as it stands: (W - D_s - D_c - dE) / |W| per cycle, and the
// contents' dissipation per cycle (sweep.csv's energy_balance and dissipated_contents_per_cycle).
struct WindowBalance {
  double balance = 0, dissipated_contents = 0, work_external = 0, dissipated_structure = 0;
};
// now: the ledger at the window's end (of what its starts hold).
WindowBalance window_balance(const PointWindow& win, const Ledger& now);

// As judge_steady (reduce/reduce.hpp) will judge the window.
bool balances(const WindowBalance& b);

// The point's response, first harmonics and energy over its window (sweep.csv's columns).
void measure_window(const Ledger& now, const Primary& P, const PointWindow& win, const SteadyStateDetector& steady, double w,
                    SteppedSinePoint& pt);

// The damper's effective parameters over the same cycles (one step = one sample); sets pt.steady.
ReducedRow reduce_window(const PointWindow& win, const Scene& scene, const ReductionContext& context, SteppedSinePoint& pt);

}  // namespace bagdem
