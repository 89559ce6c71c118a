// The table of subcommands (command.hpp) and the one mapping of their errors to exit codes.
#include <cstdio>

#include "bagdem/error.hpp"
#include "command.hpp"

namespace bagdem::cli {

std::span<const Command> commands() {
  static const Command kCommands[] = {
      {add_check, run_check},       {add_run, run_run},
      {add_reduce, run_reduce},     {add_compare, run_compare},
      {add_peaks, run_peaks},       {add_drop, run_drop},
      {add_modes, run_modes},       {add_export, run_export},
      {add_bench, run_bench_command}, {add_sweep, run_sweep_command},
      {add_trade, run_trade},       {add_calibrate, run_calibrate},
      {add_characterize, run_characterize}, {add_predict, run_predict},
      {add_design, run_design},
  };
  return kCommands;
}

int run_reporting(const Command& c, Args& a) {
  try {
    return c.run(a);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", error_label(e), e.what());
    return exit_code_of(e);
  }
}

}  // namespace bagdem::cli
