// `bagdem peaks`: a finished sweep's peak reductions recomputed (command.hpp).
#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/output_lock.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "bagdem/run/stepped_sine.hpp"
#include "command.hpp"

namespace bagdem::cli {

CLI::App* add_peaks(CLI::App& app, Args& a) {
  return add_run_reader(app, a, "peaks", "Recompute each mode's peak reduction of a finished sweep from its recorded points "
                                         "(OUT/sweep.csv) and the case's bare structure: rewrites OUT/peaks.csv and the peaks of "
                                         "OUT/summary.json, and prints them. For a sweep run with an older bagdem, whose peak "
                                         "refinement differed (docs/outputs.md); refuses a case whose bare peaks are not the run's.",
                        "sweep");
}

int run_peaks(Args& a) {
  apply_fidelity(a);
  const Scene s = load_case(a.case_dir, a.sets);
  if (!s.primary || !s.primary->stepped_sine)
    throw InputError(s.case_file, "excitation.kind", "", "peaks needs a coupled stepped-sine sweep (a primary structure with excitation.kind = \"stepped-sine\")");
  const OutputLock lock(a.out());
  require_case_of_run(std::filesystem::path(a.out()) / "results.h5", s, "is missing: run the sweep first (bagdem run)");
  for (const ModePeak& m : recompute_stepped_sine_peaks(*s.primary, a.out())) std::printf("%s\n", describe_peak(m).c_str());
  return 0;
}

}  // namespace bagdem::cli
