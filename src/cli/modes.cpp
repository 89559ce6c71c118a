// `bagdem modes`: the modal table of a case's structure (command.hpp).
#include "bagdem/io/atomic_file.hpp"
#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/structure/modal_table.hpp"
#include "command.hpp"

namespace bagdem::cli {

CLI::App* add_modes(CLI::App& app, Args& a) {
  CLI::App* modes = app.add_subcommand("modes", "Write the modal table of the case's primary structure, the input of primary.kind = \"modal\" "
                                          "(columns: docs/case-schema.md): per mode its natural frequency, damping ratio and modal mass, "
                                          "the shapes at the cavity's attachment, the force and the response points, the slope and the "
                                          "curvature at the attachment, and whether it is a rigid-body mode; mass-normalised, to every "
                                          "digit, without primary.cavity_mass. Read back, it gives the same structure.");
  modes->add_option("case_dir", a.case_dir, "Case directory (holds case.toml)")->required();
  modes->add_option("--to", a.export_to, "Where to write the table (default CASE_DIR/out/modes.csv)");
  modes->add_option("--set", a.sets, "Override a key of case.toml (repeatable)");
  return modes;
}

int run_modes(Args& a) {

  const Scene s = load_case(a.case_dir, a.sets);
  refuse_several_dampers(s, "bagdem modes", "writes the structure's table without its one cavity's mass");
  if (!s.primary) throw InputError(s.case_file, "primary.kind", "", "modes needs a primary structure (sdof, beam, fe-beam or modal)");
  const std::filesystem::path to = a.export_to.empty() ? std::filesystem::path(a.out()) / "modes.csv" : std::filesystem::path(a.export_to);
  check_output_target(
      to, "--to", [](const std::filesystem::path&, const std::string& head) { return head.rfind("frequency [Hz],damping_ratio [1],modal_mass [kg],", 0) == 0; },
      "a table of modes bagdem wrote");
  if (to.has_parent_path()) std::filesystem::create_directories(to.parent_path());
  write_modal_table(to, *s.primary);
  std::printf("wrote %s: %zu modes of %s\n", to.string().c_str(), s.primary->size(), s.primary->description.c_str());
  return 0;
}

}  // namespace bagdem::cli
