// `bagdem export`: a reduced table for FE and continuum codes (command.hpp).
#include "bagdem/io/output_lock.hpp"
#include "bagdem/reduce/export.hpp"
#include "command.hpp"

namespace bagdem::cli {

CLI::App* add_export(CLI::App& app, Args& a) {
  CLI::App* exporter = app.add_subcommand("export", "Export the reduced-parameter table of a run or a study (C_b, M_b, e, loss factor against "
                                               "frequency, amplitude and Gamma, with the swept design parameters) as CSV, JSON and HDF5 with "
                                               "units, for FE and continuum codes (columns: docs/outputs.md).");
  exporter->add_option("dir", a.out_dir, "A run's output directory or a study's (holds reduced.csv)")->required();
  exporter->add_option("--formats", a.formats, "Any of csv json h5 (default all)")->check(CLI::IsMember({"csv", "json", "h5"}));
  exporter->add_option("--to", a.export_to, "Path of the exported files without extension (default DIR/export)");
  return exporter;
}

int run_export(Args& a) {
  const std::optional<OutputLock> lock = lock_existing(a.out_dir);  // not while a run or a study writes there
  for (const std::string& p : export_reduced(a.out_dir, a.export_to, a.formats)) std::printf("wrote %s\n", p.c_str());
  return 0;
}

}  // namespace bagdem::cli
