// The speed/accuracy trade: `bagdem trade CASE_DIR` and the fidelity presets (`--fidelity`).
//
// A knob is one shortcut users take for speed, expressed as overrides of the case (`--set`):
//   timestep     simulation.timestep_safety x factor and simulation.steps_per_contact / factor (at
//                least 10), the two limits of the automatic step a user sets (an explicit
//                simulation.timestep x factor)
//   stiffness    the Young's modulus of every ball material, and the spring k_n of every Hooke
//                interaction, x factor (the standard DEM softening; its effect on the contact
//                duration is reported: Hertz t_c ~ E*^(-2/5), Hooke t_c ~ k_n^(-1/2))
//   film         bag.triangles x factor (the film's resolution)
//   tangential   friction = 0 in every [interactions.*] (the tangential model off)
//   rolling      rolling_friction = 0 in every [interactions.*] (rolling resistance off)
//   output       output.cavity_interval x factor (the rate the reduction samples the cavity at)
//   steady       excitation.steady_tolerance x factor (when a sweep calls a frequency steady)
// Each knob has a reference setting (its most accurate on the ladder) and cheaper ones; a knob the
// case does not use (no bag, no friction, no sweep) is left out. The trade runs the reference (every
// knob at its reference), the reference with simulation.seed + 1 (the noise floor: how far a
// chaotic bed's results move with no shortcut at all), and, for each knob and each cheaper setting,
// the reference with that one knob changed; then the presets `balanced` and `fast`.
// Errors against the reference: the peak reduction as a difference in dB; C_b/(M_b w) and
// M_eff/M_bag relative to the magnitude of the reference's complex effective mass ratio
// |M_eff/M_bag - i C_b/(M_b w)| (either part may be near zero); the others relative to their own
// reference value. Each rung is a point of a study (its own
// `bagdem run` child in OUT/point-NNN, resumable, in parallel within the cores), and the table
// compares each rung's wall time and results with the reference's.
//
// Presets (--fidelity of run, check, sweep and trade; overrides appended after the user's --set):
//   reference   every knob at its reference setting (the trade's reference run)
//   balanced    the case as written
//   fast        timestep x2 (safety at most 1), film x0.5, steady tolerance x2
// Their measured speed and error on the shipped cases are in docs/trade.md.
#pragma once
#include <string>
#include <vector>

namespace bagdem::study {

struct Knob {
  std::string name;                // "timestep", ...
  std::string what;                // for the help and the table's notes
  std::vector<double> factors;     // the reference first, then the cheaper settings (on/off knobs: 1, 0)
};

// The knobs, a plain table (the order of the ladder).
const std::vector<Knob>& knobs();

// The overrides of a preset ("reference", "balanced", "fast") for the case; throws InputError for
// another name.
std::vector<std::string> fidelity_sets(const std::string& case_dir, const std::vector<std::string>& sets,
                                       const std::string& preset);

// One run of the trade.
struct Rung {
  std::string name;                // "reference", "reference, seed+1", "timestep x2", "tangential off", "preset fast"
  std::string knob;                // "" for the reference and the presets, "seed" for the noise floor
  std::vector<std::string> sets;   // every override of the run (the user's, then the rung's)
};

// The ladder of a case: the reference, one rung per knob and cheaper setting, the presets.
// `only` restricts the knobs (empty: all that apply).
std::vector<Rung> trade_ladder(const std::string& case_dir, const std::vector<std::string>& sets,
                               const std::vector<std::string>& only);

struct TradeArgs {
  std::string dir;                       // CASE_DIR
  std::vector<std::string> sets;         // --set, applied to every rung
  std::vector<std::string> only;         // --knobs
  int jobs = 0, threads = 0, cores = 0;
  std::string out;                       // default CASE_DIR/trade
  std::string executable = "/proc/self/exe";
};

// Plans the ladder, runs it (resumable), writes OUT/trade.csv and prints the table. Exit codes as
// sweep: 0, 2 bad input (nothing run), 3 a rung failed (its row says so).
int trade_command(const TradeArgs& args);

}  // namespace bagdem::study
