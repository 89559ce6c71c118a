// Reduction of a run to the damper's effective parameters (docs/reference-study.md, section 5): the rows of
// reduced.csv, one per driven frequency.
//
// Input: the cavity's displacement x along the excitation direction e, the force F the contents
// exert on the cavity along e (both means over sample intervals), and the contents' centre-of-mass
// velocity relative to the cavity along e (point samples at the intervals' ends), over whole steady
// cycles of the drive frequency f. Output per frequency:
//   - M_eff, C_eff by first-harmonic projection, F_hat = (w^2 M_eff - i w C_eff) X_hat, per cycle and
//     averaged, with standard errors over cycles (reduce/harmonic_projection.hpp);
//   - energy per cycle pi C_eff w |X|^2, loss factor C_eff / (M_eff w), M_eff / M_bag,
//     C_b / (M_b w) = C_eff / (M_bag w) (docs/reference-study.md, section 2: the bag's real mass), Gamma = |X| w^2 / g,
//     d / |X| with d the free clearance of the contents along e when settling ended;
//   - the impacts (reduce/impacts.hpp): their phase phi in the study's convention (x = |X| cos theta,
//     phi = theta at the impact modulo pi, so that the cavity speed at impact is w |X| sin phi, Eq. 11a),
//     impacts per cycle, mean peak force and duration (resolved to about one sample interval), and the
//     restitution e of each impact from the contents' centre-of-mass velocity normal to the wall
//     (the study's Eq. (9): -v_after / v_before); e inverted from C_b/(M_b w) and phi with Eq. (19a).
// Column names and units: reduced_columns() (documented in docs/outputs.md).
#pragma once
#include <complex>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "bagdem/io/results_file.hpp"
#include "bagdem/reduce/interval.hpp"
#include "bagdem/scene.hpp"

namespace bagdem {

// What the reduction needs to know of the scene (SI units).
struct ReductionContext {
  Vec3 direction = Vec3::UnitX();   // excitation direction e (unit)
  double bag_mass = 0;              // the contents' real mass: balls + film (film mass scaling undone) (kg)
  double primary_mass = 0;          // the structure's own mass (mass ratio); 0 under prescribed motion (kg)
  double balls = 0;                 // number of balls
  double ball_diameter = 0;         // mean ball diameter (m)
  double clearance = 0;             // free travel d of the contents along e when settling ended; NaN if unknown (m)
  double gravity = 9.81;            // |g| for Gamma (m/s^2); 9.81 when the scene has none
};
// The excitation direction of a scene: the primary's, or that of the cavity's harmonic motion
// (its displacement a quarter period in); zero when the scene has neither.
Vec3 excitation_direction(const Scene& scene);

// The context of a scene. Its clearance is NaN (unknown): the run measures it on the live contents
// (run/clearance.hpp) and sets it.
ReductionContext reduction_context(const Scene& scene, const Vec3& direction);

// Samples along e over a run or one frequency point. t: the end of each sample interval (s);
// x, force: means over [t - interval, t] (m, N); v_rel: point samples at t (m/s).
struct CavitySeries {
  std::vector<double> t, x, force, v_rel;
};

// One row of reduced.csv. Every reduced figure carries its standard error (_se) and the half-width
// of its 95% interval (_ci95) over the window's correlated cycles (reduce/interval.hpp); an
// ensemble's table (--seeds) replaces them by the interval over the starts.
struct ReducedRow {
  double frequency = 0, cavity_amplitude = 0, gamma = 0, clearance_ratio = 0;
  double bag_mass = 0, mass_ratio = 0, balls = 0, ball_diameter = 0;
  double M_eff = 0, M_eff_se = 0, M_eff_ci95 = 0, C_eff = 0, C_eff_se = 0, C_eff_ci95 = 0, M_eff_ratio = 0;
  double Cb_over_Mbw = 0, Cb_over_Mbw_se = 0, Cb_over_Mbw_ci95 = 0;
  double loss_factor = 0, energy_per_cycle = 0, energy_per_cycle_se = 0, energy_per_cycle_ci95 = 0;
  // Energy the contents' contacts dissipated per cycle by the tallies (NaN with output.energy = false),
  // and the window's energy balance: (work on the contents - dissipated - change of stored energy)
  // / work, relative (NaN when unknown).
  double dissipated_per_cycle = kUnknown, energy_balance = kUnknown;
  double impact_phase = 0, impacts_per_cycle = 0, e_impact = 0, e_impact_sd = 0, e_impact_count = 0, e_eq19a = 0;
  double e_drop = kUnknown;  // from the drop test of the same contents, when it was run
  // The restitution a designer takes: the first available of e_impact, e_eq19a and e_drop (e_method),
  // with its interval; NaN and "none" when none is available.
  double e = kUnknown, e_se = kUnknown, e_ci95 = kUnknown;
  std::string e_method = "none";
  double peak_impact_force = 0, max_impact_force = 0, impact_duration = 0;
  double response_amplitude = 0;    // |Y| at the structure's response point (coupled runs; NaN otherwise)
  double cycles = 0;                // whole cycles of the window
  // 1 when the window is steady: the response settled, the energy balance closes within 1% and the
  // tallied dissipation is not negative; 0 flags the row (kept out of the peak reduction).
  double steady = 1;
  std::complex<double> displacement, force;  // X_hat (m) and F_hat (N), for the comparison
  static constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();
};

// The minimum of impacts with free flight before and after for a per-impact restitution.
inline constexpr std::size_t kMinImpactsForRestitution = 5;
// The largest relative misclosure of a steady window's energy balance.
inline constexpr double kSteadyBalanceTolerance = 0.01;

// Sets e, e_se, e_ci95 and e_method from the estimators in their order of preference: per impact
// (at least kMinImpactsForRestitution impacts; its interval `impact`, batch means over the impacts),
// Eq. (19a) (its interval mapped from that of C_b/(M_b w)), the drop test (no interval from one start).
void choose_restitution(ReducedRow& row, const Interval& impact);

// Cumulative energy series of the contents (results.h5's /energy): times t, and in `fields` the
// kinetic, elastic, work of the cavity, work of gravity and dissipated energy, in that order (J).
struct EnergyWindow {
  std::vector<double> t;
  std::vector<std::vector<double>> fields;
};
// Sets row.dissipated_per_cycle and row.energy_balance over [t0, t1] (row.cycles cycles; the
// series interpolated linearly): balance = (W_cavity + W_gravity - D - change of kinetic and elastic
// energy) / max(|W_cavity|, |D|). Leaves them NaN when the series does not cover the window.
void set_energy_balance(ReducedRow& row, const EnergyWindow& energy, double t0, double t1);
// Flags the row unsteady (steady = 0) when its energy balance is off by more than
// kSteadyBalanceTolerance or the tallied dissipation is negative; a steady = 0 stays.
void judge_steady(ReducedRow& row);

// Reduces whole cycles of f (Hz) after t_skip (s).
ReducedRow reduce_series(const CavitySeries& series, double f, double t_skip, const ReductionContext& context);

// The table's columns (name, unit) and a row's values in that order.
const std::vector<TableColumn>& reduced_columns();
std::vector<double> reduced_values(const ReducedRow& row);
// Its inverse: the row of those values and the e_method text.
ReducedRow reduced_row(const std::vector<double>& values, const std::string& e_method);
// Writes rows as CSV (header "name [unit]"), atomically.
void write_reduced_csv(const std::filesystem::path& path, const std::vector<ReducedRow>& rows);
// Reads a reduced.csv back (for compare and export); throws InputError naming the file if malformed.
std::vector<ReducedRow> read_reduced_csv(const std::filesystem::path& path);

// `bagdem reduce` of a run under prescribed harmonic cavity motion: reads out_dir/results.h5
// (complete), reduces the cycles after settling, the ramp and output.skip_cycles, writes
// out_dir/reduced.csv and returns the row. InputError when the run is not reducible (no harmonic
// motion, incomplete, fewer than 2 measured cycles). A coupled sweep reduces itself point by point
// (run/stepped_sine.cpp); reduce then rereads its reduced.csv.
std::vector<ReducedRow> reduce_run(const Scene& scene, const std::string& out_dir);

// Checks that results.h5 at `h5` holds a run of the scene's case (its resolved_config, the files it
// reads included; output.skip_cycles may differ): InputError naming the keys that differ, or
// `missing` when there is no results.h5.
void require_case_of_run(const std::filesystem::path& h5, const Scene& scene, const char* missing);

// The keys a reduction may give otherwise than its run (output.skip_cycles chooses what is reduced,
// not what was run): for results.h5 and a drop test alike.
inline const std::vector<std::string> kReducedAtAnyCycles = {"output.skip_cycles"};

// The restitution's columns: reduce attaches a drop test's e after the run, so they are not the
// run's record (results.h5's /reduced) and are left out of the checks against it.
inline constexpr const char* kRestitutionColumns[] = {"e_drop", "e", "e_se", "e_ci95"};

// A terminal table of the rows.
std::string describe_reduced(const std::vector<ReducedRow>& rows);
// The restitution three ways per row (per impact, Eq. 19a, drop test) and how far they disagree.
std::string describe_restitution(const std::vector<ReducedRow>& rows);
// Whether out_dir holds a drop test (drop_result.csv) of `scene`'s case: one of another case, or an
// edited one, is refused (InputError; reduce/drop_record.hpp), before anything is written.
bool check_drop_result(const std::string& out_dir, const Scene& scene);
// When out_dir/drop_result.csv exists (bagdem drop; checked by check_drop_result), sets e_drop of
// every row and rewrites out_dir/reduced.csv.
void attach_drop_result(std::vector<ReducedRow>& rows, const std::string& out_dir);

}  // namespace bagdem
