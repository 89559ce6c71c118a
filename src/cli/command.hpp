// The command line: a file per subcommand in src/cli/, each adding its options to the app
// (add_NAME) and running once parsed (run_NAME); commands() is the table main() builds the app
// from. Every subcommand's errors end in one mapping (error.hpp, exit_code_of): bad input 2, a run
// that went unstable 3, anything else (I/O, a full disk) 1.
#pragma once
#include <CLI/CLI.hpp>

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "bagdem/run/bench.hpp"
#include "bagdem/study/calibrate.hpp"
#include "bagdem/study/characterize.hpp"
#include "bagdem/study/design.hpp"
#include "bagdem/study/study.hpp"
#include "bagdem/study/trade.hpp"

namespace bagdem::cli {

// What the subcommands read from the command line.
struct Args {
  std::string case_dir, out_dir;
  std::vector<std::string> sets;
  std::string fidelity;  // --fidelity: a preset's overrides, appended to sets (study/trade.hpp)
  int threads = 0;
  bool quiet = false, resume = false;
  int seeds = 1;
  std::string form = "consistent";
  double drop_speed = 0;
  std::vector<std::string> formats = {"csv", "json", "h5"};
  std::string export_to;
  BenchOptions bench;
  study::SweepArgs sweep;
  study::TradeArgs trade;
  study::CalibrateArgs calibrate;
  study::CharacterizeArgs characterize;
  study::PredictArgs predict;
  study::DesignArgs design;
  // The output directory: --out, or CASE_DIR/out.
  std::string out() const { return out_dir.empty() ? (std::filesystem::path(case_dir) / "out").string() : out_dir; }
};

// One subcommand: how it adds itself and its options to the app, and what it runs once parsed
// (its exit code; an exception it throws is mapped by exit_code_of).
struct Command {
  CLI::App* (*add)(CLI::App& app, Args& a);
  int (*run)(Args& a);
};
// Every subcommand, in the order `bagdem --help` lists them (commands.cpp).
std::span<const Command> commands();

// Runs a parsed subcommand: its errors said on stderr and mapped to the exit code (exit_code_of).
int run_reporting(const Command& c, Args& a);

// Shared by the subcommands' files (common.cpp).
// A number in [lo, hi], refused when it is not finite (CLI::Range lets nan through).
CLI::Validator finite_range(double lo, double hi);
void add_fidelity(CLI::App* sub, std::string& fidelity);
// --fidelity's preset: its overrides appended to a.sets.
void apply_fidelity(Args& a);
// More threads than cores are taken (the results are the same for any count), but they share the
// cores and the run is slower than with one per core: said on stderr.
void warn_threads_above_cores(const std::vector<int>& threads);
// A command that reads a finished run (a sweep when `run` says so) in OUT: the case, the output
// directory and the --set the run was made with.
CLI::App* add_run_reader(CLI::App& app, Args& a, const char* name, const std::string& help, const std::string& run);
// The options --jobs, --threads and --cores of a command that runs points as child processes
// (sweep, trade, calibrate, characterize, design); `cores_default` says what --cores defaults to.
void add_budget_options(CLI::App* command, int& jobs, int& threads, int& cores, const std::string& what,
                        const std::string& cores_default);

// The subcommands, a file each.
CLI::App* add_check(CLI::App& app, Args& a);
int run_check(Args& a);
CLI::App* add_run(CLI::App& app, Args& a);
int run_run(Args& a);
CLI::App* add_reduce(CLI::App& app, Args& a);
int run_reduce(Args& a);
CLI::App* add_compare(CLI::App& app, Args& a);
int run_compare(Args& a);
CLI::App* add_peaks(CLI::App& app, Args& a);
int run_peaks(Args& a);
CLI::App* add_drop(CLI::App& app, Args& a);
int run_drop(Args& a);
CLI::App* add_modes(CLI::App& app, Args& a);
int run_modes(Args& a);
CLI::App* add_export(CLI::App& app, Args& a);
int run_export(Args& a);
CLI::App* add_bench(CLI::App& app, Args& a);
int run_bench_command(Args& a);
CLI::App* add_sweep(CLI::App& app, Args& a);
int run_sweep_command(Args& a);
CLI::App* add_trade(CLI::App& app, Args& a);
int run_trade(Args& a);
CLI::App* add_calibrate(CLI::App& app, Args& a);
int run_calibrate(Args& a);
CLI::App* add_characterize(CLI::App& app, Args& a);
int run_characterize(Args& a);
CLI::App* add_predict(CLI::App& app, Args& a);
int run_predict(Args& a);
CLI::App* add_design(CLI::App& app, Args& a);
int run_design(Args& a);

}  // namespace bagdem::cli
