// A sweep point's window (sweep_window.hpp).
#include "sweep_window.hpp"

#include <cmath>

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

WindowBalance window_balance(const PointWindow& win, const Simulation& sim) {
  const Ledger end = ledger(sim), &from = win.starts.front();
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

}  // namespace bagdem
