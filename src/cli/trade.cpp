// `bagdem trade`: the speed/accuracy trade of a case (command.hpp).
#include "bagdem/study/trade.hpp"
#include "command.hpp"

namespace bagdem::cli {

CLI::App* add_trade(CLI::App& app, Args& args) {
  auto& a = args.trade;
  std::string names;
  for (const study::Knob& k : study::knobs()) {
    std::string factors;
    for (double x : k.factors) factors += (factors.empty() ? "" : ", ") + study::short_text(x);
    names += "\n  " + k.name + ": " + k.what + " (reference " + study::short_text(k.factors.front()) + "; factors " + factors + ")";
  }
  CLI::App* t = app.add_subcommand(
      "trade",
      "The speed/accuracy trade of a case: runs it at its reference fidelity, then with one shortcut at a time "
      "(knobs below) and at the presets balanced (the case as written) and fast, each a `bagdem run` in OUT/point-NNN "
      "(in parallel within the cores; resumable), and prints per run its wall time, speed-up, time step, contact "
      "duration and the error of the peak reduction (dB), C_b/(M_b w), M_eff/M_bag, e, energy per cycle and loss factor "
      "against the reference; OUT/trade.csv (tools/plot draws trade.png). Knobs:" + names);
  t->add_option("dir", a.dir, "CASE_DIR (holds case.toml)")->required();
  t->add_option("--knobs", a.only, "Only these knobs; `none`: only the reference, its seed+1 twin and the presets (default: every knob the case uses)");
  t->add_option("--set", a.sets, "Override a key of case.toml in every run (repeatable)")->allow_extra_args(false);
  add_budget_options(t, a.jobs, a.threads, a.cores, "trade", "this machine's");
  t->add_option("--out", a.out, "Output directory (default CASE_DIR/trade)");
  return t;
}

int run_trade(Args& a) {
  return study::holding_interrupts("bagdem trade", [&] { return study::trade_command(a.trade); });
}

}  // namespace bagdem::cli
