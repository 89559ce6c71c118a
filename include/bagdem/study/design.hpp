// `bagdem design CASE`: the bag chosen by search, DEM characterizing each candidate once and the
// harmonic balance ranking it at every position (study/characterize.hpp, reduce/predict.hpp), DEM
// checking the winners. The loop the particle-damper literature describes (an isolated damper's
// effective field, coupled to the structure; Meyer et al., Granular Matter 23, 2021):
//   1. candidates: the grid of the bag's keys (--vary or a study's [vary], as bagdem sweep; default
//      3 ball sizes x 3 fills within the mass budget), each one the case with those keys set;
//   2. a candidate whose added mass (balls and film) exceeds --budget x the structure's mass is
//      left out; the others get a map each (bagdem characterize's runs, OUT/maps/map-HASH, the hash
//      of the case, the candidate's keys and the map's grid: a map already built is reused);
//   3. every candidate at every --positions x/L (a beam; the case's own place otherwise) is
//      predicted at the case's force: for a stepped-sine case each chosen mode's peak reduction
//      with its range over the map's intervals, the objective the smallest over the chosen modes
//      (the worst mode: a design is as good as its weakest mode), its range that of that mode; for
//      a random force (excitation.kind = "random") the in-band RMS response's reduction against
//      the bare structure's, 20 log10(bare / damped) (reduce/predict.hpp, predict_random), the
//      "mode" 0 of the tables;
//   4. the best --verify candidates, each at its best position, are run coupled, --verify-seeds starts each
//      (a study in OUT/verify), their reductions' mean and 95% interval beside the prediction (a
//      random force's: each start's in-band RMS, summary.json's band_response_rms_m, against the
//      bare structure's predicted RMS, which is linear and exact);
//   5. OUT/design.csv (every pair ranked, the Pareto front of objective against added mass marked,
//      the refused ones with why), OUT/design.json, and OUT/chosen: the case directory of the best
//      verified pair (the DEM's objective; the prediction's when nothing was verified).
// docs/bag-design.md has the columns, the defaults and the run time.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "bagdem/study/characterize.hpp"

namespace bagdem {
struct EffectiveMap;   // reduce/predict.hpp
struct PredictedMode;  // reduce/predict.hpp
enum class Checks;     // reduce/predict.hpp
}

namespace bagdem::study {

struct DesignArgs {
  std::string dir;                       // CASE_DIR (a coupled stepped-sine sweep)
  std::vector<std::string> vary;         // --vary key=v1,v2,...: the candidates' grid (default: ball size x fill)
  std::vector<std::string> sets;         // --set: overrides of every run
  double budget = 0.1;                   // --budget: added mass / the structure's mass, at most (unit: 1)
  std::vector<double> positions;         // --positions: x/L of the bag (a beam; default 0.05, 0.10, ..., 0.95)
  std::vector<int> modes;                // --modes: the modes whose worst reduction is maximized (default the case's evaluated ones; 0: a random force's band)
  // The maps' grid (--gamma, --amplitudes, --frequencies, --seeds): coarser than characterize's own
  // default (a map per candidate), down to Gamma 0.02 (a bag off the antinode moves little).
  CharacterizeArgs map = [] {
    CharacterizeArgs m;
    m.gamma = {0.02, 20}, m.amplitudes = 6, m.frequencies = 4, m.seeds = 3;
    return m;
  }();
  int dampers = 1;                       // --dampers: 1 places one bag; 2 also searches pairs of bags (design_pairs.cpp)
  int verify = 3;                        // --verify: candidates run coupled (each at its best position); with
                                         // --dampers 2 also the best pairs
  int verify_seeds = 3;                  // --verify-seeds: starts each
  int jobs = 0, threads = 0, cores = 0;
  std::string out;                       // default CASE_DIR/design
  bool check = false;                    // --check: list the candidates and their masses, build nothing
  std::string executable = "/proc/self/exe";
};

// One candidate at one position, predicted (and verified).
// Where a candidate, or a candidate at a place, stands: ranked, or why not.
enum class Standing { ranked, over_budget, does_not_load, no_map, other_damper, outside_map, mode_not_in_stepped_sine, screened };
struct Status {
  Standing kind = Standing::ranked;
  std::string why;  // the detail design.csv adds to the kind's words (a loader's message, a mode, a map's reason)
  bool ranked() const { return kind == Standing::ranked; }
  // design.csv's status: "ranked", "over budget", "does not load: WHY", "no map (its runs failed)",
  // "map of another damper (WHY)", "outside the map WHY", "mode WHY not in the sweep at this place",
  // "screened only (WHY)" (a pair of bags predicted coarsely, not among the best predicted in full).
  std::string text() const;
  // The inverse of text(); InputError for a text that text() does not write.
  static Status parse(const std::string& text);
};

struct DesignRow {
  std::size_t candidate = 0;             // index into the candidates' grid
  std::vector<std::string> given;        // the candidate's values, as given (one per varied key)
  double position = 0, attach = 0;       // x/L (NaN without a beam) and x_b (unit: 1, m)
  double added_mass = 0, mass_ratio = 0; // balls and film, and over the structure's mass (unit: kg, 1)
  std::vector<double> db, db_lo, db_hi;  // per chosen mode: the predicted reduction and its range (unit: dB)
  double bare_rms = NAN;                 // a random force: the bare structure's in-band RMS at x_a (unit: m)
  double objective = 0, objective_lo = 0, objective_hi = 0;  // the worst mode's (unit: dB)
  int at_band_edge = 0;                  // chosen modes whose predicted peak lies at the band's edge (their reduction is a bound)
  double interpolation_db = NAN;         // the largest estimated interpolation error of the chosen modes' predictions
                                         // (reduce/predict.hpp; NaN: the map is too coarse to check, or a random force) (unit: dB)
  Status status;                         // ranked, over budget, or why predict refused
  bool pareto = false;                   // on the front of (objective up, added mass down) among the ranked
  int rank = 0;                          // 1 = best predicted objective (0: not ranked)
  std::string map;                       // its map's directory
  // A pair of bags (--dampers 2): the second bag's candidate, values, place and map (the first's are
  // the fields above; added_mass and mass_ratio are the pair's).
  bool pair = false;
  std::size_t candidate2 = 0;
  std::vector<std::string> given2;
  double position2 = NAN, attach2 = NAN;
  std::string map2;
  // The coupled check (NaN where not verified), per chosen mode and the worst: mean and 95% half-width.
  std::vector<double> dem_db, dem_db_ci95;
  double dem_objective = NAN, dem_objective_ci95 = NAN;
  int dem_seeds = 0;
};

// The worst of the modes' reductions, with that mode's range: sets objective, objective_lo/hi.
void set_objective(DesignRow& row);
// Ranks the "ranked" rows by objective (best first; ties by the smaller added mass) and marks the
// Pareto front: a row is on it when no other ranked row has at least its objective with less added
// mass, or more objective with no more added mass.
void rank_rows(std::vector<DesignRow>& rows);
// The default fills: 0.3, 0.6 and 0.95 of the budget as the balls' mass ratios, the film taking
// the rest of the top one (unit: 1).
std::vector<double> default_fills(double budget);
// The default ball sizes: the case's diameter x 1, 1.5 and 2 (unit: m).
// The tables' name of a chosen mode: "mode1", ..., "random" for 0 (a random force's band).
std::string mode_label(int mode);
std::vector<double> default_diameters(double diameter);

// 0 done, 2 bad input (nothing run), 3 a run failed (the design is written from what finished).
int design_command(const DesignArgs& args);

// --dampers 2 (design_pairs.cpp): every two ranked single rows whose cavities do not overlap on the
// beam and whose added masses together are within `budget_mass`, predicted together
// (reduce/predict.hpp, several dampers; the structure's mass matrix carrying both cavities'
// masses), the objective as a single row's. Every pair is screened at kPairScreenPoints
// frequencies a band without the interval; the best kPairsChecked are predicted again at 400 with
// the interval and the resolution check, and only they are ranked (the others "screened only").
// `sets[c]` are candidate c's overrides and `maps[c]` its map (null: none). Returns the pairs ranked,
// and in `overlapping` how many were left out for their cavities.
inline constexpr int kPairScreenPoints = 100;
inline constexpr std::size_t kPairsChecked = 20;
std::vector<DesignRow> predict_pairs(const std::filesystem::path& case_dir, const std::vector<std::vector<std::string>>& sets,
                                     const std::vector<const EffectiveMap*>& maps, const std::vector<DesignRow>& singles,
                                     const std::vector<int>& modes, double budget_mass, std::size_t& overlapping);
// The value of `dampers` that puts a pair's second bag on the structure (a [[dampers]] entry named
// "2", as TOML): its candidate's varied keys (`keys` with their TOML values) and its place x_b (m).
std::string second_damper(const std::vector<std::pair<std::string, std::string>>& keys, double attach);

// Every chosen mode's predicted reduction of a candidate at a place (the case with its overrides
// `sets`) from its map, into r (its status when it cannot be predicted; design_predict.cpp).
void predict_row(const std::filesystem::path& case_dir, const std::vector<std::string>& sets, const EffectiveMap& map,
                 const std::vector<int>& modes, DesignRow& r);
// The chosen modes' figures of a prediction into r: each mode's reduction (and its range unless
// `checks` is none), at_band_edge, interpolation_db (with Checks::all), the objective; or r's
// status when a mode leaves the maps or is not in the sweep (design_predict.cpp).
void set_predicted_modes(const std::vector<PredictedMode>& predicted, const std::vector<int>& modes, Checks checks, DesignRow& r);

}  // namespace bagdem::study
