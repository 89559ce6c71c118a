// A stepped sine point's window (stepped_sine_window.hpp).
#include "stepped_sine_window.hpp"

#include <cmath>
#include <vector>

#include "bagdem/reduce/interval.hpp"
#include "bagdem/structure/response.hpp"

namespace bagdem {

Ledger ledger(const Simulation& sim) {
  Ledger l;
  const auto& S = sim.structure().scalars;
  l.work_external = S.work_external;
  l.dissipated_structure = S.dissipated;
  if (sim.scene().models.energy) {
    const EnergySample e = sim.energy();
    l.dissipated_contents = e.dissipated();
    // Contents: kinetic + elastic + gravity's potential (-work of gravity).
    l.stored = e.kinetic + e.elastic - e.work_gravity;
  }
  l.stored += sim.structure_energy();
  return l;
}

Ledger ledger(const Dampers& dampers) {
  Ledger l;
  const auto& S = dampers[0].structure().scalars;
  l.work_external = S.work_external;
  l.dissipated_structure = S.dissipated;
  for (std::size_t k = 0; k < dampers.size(); ++k) {
    if (!dampers.scene(k).models.energy) continue;
    const EnergySample e = dampers[k].energy();
    l.dissipated_contents += e.dissipated();
    l.stored += e.kinetic + e.elastic - e.work_gravity;
  }
  l.stored += dampers[0].structure_energy();
  return l;
}

WindowBalance window_balance(const PointWindow& win, const Ledger& end) {
  const Ledger& from = win.starts.front();
  const double cycles = static_cast<double>(win.ys.size());
  WindowBalance b;
  b.work_external = (end.work_external - from.work_external) / cycles;
  b.dissipated_structure = (end.dissipated_structure - from.dissipated_structure) / cycles;
  b.dissipated_contents = (end.dissipated_contents - from.dissipated_contents) / cycles;
  const double residual = b.work_external - b.dissipated_structure - b.dissipated_contents - (end.stored - from.stored) / cycles;
  b.balance = b.work_external != 0 ? residual / std::abs(b.work_external) : 0.0;
  return b;
}

bool balances(const WindowBalance& b) {
  return !(std::abs(b.balance) > kSteadyBalanceTolerance) && !(b.dissipated_contents < 0);
}

// Response, energy and first harmonics over the window.
void measure_window(const Ledger& now, const Primary& P, const PointWindow& win, const SteadyStateDetector& steady, double w,
                    SteppedSinePoint& pt) {
  const double F = P.amplitude;
  const double cycles = static_cast<double>(win.ys.size());
  std::vector<double> magnitude;
  pt.response = pt.cavity = pt.contents_force = std::complex<double>(0, 0);
  for (std::size_t c = 0; c < win.ys.size(); ++c) {
    pt.response += win.ys[c] / cycles, pt.cavity += win.cav[c] / cycles, pt.contents_force += win.load[c] / cycles;
    magnitude.push_back(std::abs(win.ys[c]) / F);
  }
  pt.receptance_ci95 = batch_means_interval(magnitude).ci95;
  const WindowBalance b = window_balance(win, now);
  pt.work_external = b.work_external, pt.dissipated_structure = b.dissipated_structure;
  pt.dissipated_contents = b.dissipated_contents, pt.balance = b.balance;
  pt.receptance = pt.response / std::complex<double>(0, -F);
  pt.bare = P.bare_receptance(w);
  pt.spread = steady.spread();
}

// The damper's effective parameters over the same cycles (one step = one sample); sets pt.steady.
ReducedRow reduce_window(const PointWindow& win, const Scene& scene, const ReductionContext& context, SteppedSinePoint& pt) {
  CavitySeries last;
  for (const CavitySeries& c : win.recent) {
    last.t.insert(last.t.end(), c.t.begin(), c.t.end()), last.x.insert(last.x.end(), c.x.begin(), c.x.end());
    last.force.insert(last.force.end(), c.force.begin(), c.force.end());
    last.v_rel.insert(last.v_rel.end(), c.v_rel.begin(), c.v_rel.end());
  }
  ReducedRow reduced = reduce_series(last, pt.frequency, last.t.front() - 0.5 * scene.dt, context);
  reduced.response_amplitude = std::abs(pt.response);
  // Without the contents' energy tallies (output.energy = false) the balance cannot close: unknown.
  if (scene.models.energy) reduced.dissipated_per_cycle = pt.dissipated_contents, reduced.energy_balance = pt.balance;
  if (!pt.settled) reduced.steady = 0;
  judge_steady(reduced);
  pt.steady = reduced.steady == 1;
  return reduced;
}

}  // namespace bagdem
