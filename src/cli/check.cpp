// `bagdem check`: a case validated and its resolved scene printed (command.hpp).
#include <iostream>

#include "bagdem/case/load_case.hpp"
#include "command.hpp"

namespace bagdem::cli {

CLI::App* add_check(CLI::App& app, Args& a) {
  CLI::App* check = app.add_subcommand("check", "Validate a case and print the resolved scene: what is modelled, N, dt and how it was chosen, steps, memory; for a bag its size, fill, film resolution and strings.");
  check->add_option("case_dir", a.case_dir, "Case directory (holds case.toml)")->required();
  check->add_option("--set", a.sets, "Override a key of case.toml: --set simulation.duration=\"0.5 s\" (repeatable)");
  add_fidelity(check, a.fidelity);
  return check;
}

int run_check(Args& a) {
  apply_fidelity(a);
  const Scene s = load_case(a.case_dir, a.sets);
  std::cout << describe_scene(s);
  for (const auto& w : s.warnings) std::cout << "warning: " << w << "\n";
  return 0;
}

}  // namespace bagdem::cli
