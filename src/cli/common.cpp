// What several subcommands share (command.hpp).
#include <omp.h>

#include <cmath>
#include <iostream>
#include <string>

#include "bagdem/study/trade.hpp"
#include "command.hpp"

namespace bagdem::cli {

CLI::Validator finite_range(double lo, double hi) {
  const std::string range = "[" + CLI::detail::to_string(lo) + " - " + CLI::detail::to_string(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        double v = 0;
        std::size_t used = 0;
        try {
          v = std::stod(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used == 0 || used != text.size()) return "'" + text + "' is not a number";
        if (!std::isfinite(v) || v < lo || v > hi) return "Value " + text + " not in range " + range;
        return "";
      },
      "FLOAT in " + range);
}

void add_fidelity(CLI::App* sub, std::string& fidelity) {
  sub->add_option("--fidelity", fidelity,
                  "A preset of the speed/accuracy trade: fast, balanced (the case as written) or reference (see bagdem trade)")
      ->check(CLI::IsMember({"fast", "balanced", "reference"}));
}

void apply_fidelity(Args& a) {
  if (a.fidelity.empty()) return;
  const auto more = study::fidelity_sets(a.case_dir, a.sets, a.fidelity);
  a.sets.insert(a.sets.end(), more.begin(), more.end());
}

void warn_threads_above_cores(const std::vector<int>& threads) {
  const int cores = omp_get_num_procs();
  for (int t : threads)
    if (t > cores)
      std::cerr << "warning: --threads " << t << " is more than the " << cores << " cores of this machine: the threads "
                << "share the cores and run slower than " << cores << " would; use --threads " << cores << " or fewer\n";
}

CLI::App* add_run_reader(CLI::App& app, Args& a, const char* name, const std::string& help, const std::string& run) {
  CLI::App* c = app.add_subcommand(name, help);
  c->add_option("case_dir", a.case_dir, "Case directory (holds case.toml)")->required();
  c->add_option("--out", a.out_dir, "Output directory of the " + run + " (default CASE_DIR/out)");
  c->add_option("--set", a.sets, "The --set overrides the " + run + " was made with (repeatable)");
  add_fidelity(c, a.fidelity);
  return c;
}

void add_budget_options(CLI::App* command, int& jobs, int& threads, int& cores, const std::string& what,
                        const std::string& cores_default) {
  command->add_option("--jobs", jobs, "Runs at once (default: cores / threads)")->check(CLI::Range(1, 4096));
  command->add_option("--threads", threads, "OpenMP threads per run (default 1)")->check(CLI::Range(1, 4096));
  command->add_option("--cores", cores, "Cores this " + what + " may use (default: " + cores_default + ")")->check(CLI::Range(1, 65536));
}

}  // namespace bagdem::cli
