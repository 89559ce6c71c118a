// `bagdem reduce`: a finished run reduced to the effective parameters (command.hpp).
#include "bagdem/case/load_case.hpp"
#include "bagdem/io/output_lock.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "command.hpp"

namespace bagdem::cli {

CLI::App* add_reduce(CLI::App& app, Args& a) {
  return add_run_reader(app, a, "reduce", "Reduce a finished run to the bag's effective parameters (also done at the end of run): per driven frequency "
                                          "M_eff and C_eff by first-harmonic projection over whole steady cycles, energy per cycle, "
                                          "loss factor, M_eff/M_bag, C_b/(M_b w), Gamma, d/X, the impacts (phase, peak force, duration) and the "
                                          "restitution e (per impact between free flights, else Eq. 19a, else the drop test; e_method says which), "
                                          "each with its standard error and 95% interval over the correlated cycles, and steady = 0 for a window "
                                          "whose energy balance is off by more than 1%. Writes OUT/reduced.csv (columns: docs/outputs.md).",
                        "run");
}

int run_reduce(Args& a) {
  apply_fidelity(a);
  const Scene s = load_case(a.case_dir, a.sets);
  refuse_several_dampers(s, "bagdem reduce", "reduces the case's own damper's results.h5 (the others' are in OUT/dampers)");
  const std::optional<OutputLock> lock = lock_existing(a.out());  // not while a run writes there
  // A drop test of another case is refused before reduced.csv is written (a harmonic run's is rewritten).
  const bool drop = check_drop_result(a.out(), s);
  std::vector<ReducedRow> rows = reduce_run(s, a.out());
  if (drop) attach_drop_result(rows, a.out());
  std::printf("%s%s", describe_reduced(rows).c_str(), describe_restitution(rows).c_str());
  return 0;
}

}  // namespace bagdem::cli
