// bagdem: the command line. Each subcommand is a file of src/cli/ (command.hpp's table); this builds
// the app from the table, parses, and runs the subcommand parsed. `bagdem <cmd> --help` explains each.
#include <CLI/CLI.hpp>

#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "bagdem/error.hpp"
#include "command.hpp"

using namespace bagdem;

namespace {

// A first word that names no subcommand: said so, with the subcommands (CLI11 would say "A
// subcommand is required"); false when it names one.
bool refuse_unknown_subcommand(CLI::App& app, const std::string& word) {
  std::string names;
  bool known = false;
  for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
    names += (names.empty() ? "" : ", ") + sub->get_name();
    known = known || sub->get_name() == word;
  }
  if (!known) std::cerr << "unknown subcommand '" << word << "': the subcommands are " << names << " (bagdem --help)\n";
  return !known;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bagdem " BAGDEM_VERSION
               ": discrete-element simulation of granular and bean-bag impact dampers.\n"
               "A case is a directory with case.toml (schema: docs/case-schema.md).\n"
               "Exit codes: 0 success, 1 system error (I/O, a full disk), 2 bad input (case or command line), 3 the run "
               "went unstable, 130/143 stopped by SIGINT/SIGTERM (a run writes a checkpoint: continue with --resume; a study keeps its points done: the same command goes on)."};
  app.require_subcommand(1);
  app.set_version_flag("--version", BAGDEM_VERSION);

  cli::Args a;
  std::vector<std::pair<CLI::App*, const cli::Command*>> subcommands;
  for (const cli::Command& c : cli::commands()) subcommands.emplace_back(c.add(app, a), &c);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (argc > 1 && argv[1][0] != '-' && refuse_unknown_subcommand(app, argv[1])) return kExitInputError;
    // CLI11 prints its message (or the help and version, which succeed); a command-line error is
    // bad input like any other: exit code 2, not CLI11's own codes.
    return app.exit(e) == 0 ? 0 : kExitInputError;
  }
  for (const auto& [sub, command] : subcommands)
    if (sub->parsed()) return cli::run_reporting(*command, a);
  return 0;
}
