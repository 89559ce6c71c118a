// `bagdem characterize CASE`: the damper alone, its effective field mapped once. The case's contents
// (a bag, a loose bed) in their cavity under prescribed harmonic motion x(t) = X sin(2 pi f t) along
// the excitation direction, over a grid of amplitude x frequency, several perturbed starts per
// cell; each run reduced (reduce/reduce.hpp) and the starts combined per cell into the map of
// M_eff, C_eff, C_b/(M_b w), e and the loss factor, each with its 95% interval over the starts
// (reduce/interval.hpp, independent_interval). The particle-damper literature's reduction of an
// isolated damper to its effective mass and dissipation as functions of amplitude and frequency
// (Meyer et al., Granular Matter 23, 2021; Meyer & Seifried, Comp. Part. Mech. 7, 2020).
//
// The grid: amplitudes from acceleration ratios Gamma = X w^2 / g log-spaced over [Gamma_lo,
// Gamma_hi] at every frequency (so X = Gamma g / w^2 differs from column to column), frequencies
// evenly spaced over each band of the case's stepped-sine sweep (a band per evaluated mode) or over
// --band. A case with a primary structure runs without it: every point is the case with
//   primary = {kind = "prescribed"}, excitation = {kind = "none"},
//   cavity.motion = {kind = "harmonic", amplitude, frequency, direction = primary.direction,
//                    ramp = 2 / f (a smooth start)},
//   simulation.duration = (2 + skip + cycles) / f, output.skip_cycles = skip,
// where skip and cycles are at least --skip and --cycles and span at least --skip-time and
// --window-time seconds (a bag settles into its motion in a time, not in a number of cycles: at a
// high mode's frequency a few cycles are a few milliseconds; docs/characterize.md),
// (a bag filled to a mass ratio keeps its balls: bag.balls.primary_mass = the structure's mass),
// run by the study machinery (study.hpp: OUT/point-NNN, resumable, J at once, MPI ranks sharing
// the points). docs/characterize.md has the outputs' columns.
#pragma once
#include <string>
#include <vector>

#include "bagdem/reduce/map_table.hpp"
#include "bagdem/reduce/predict.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "bagdem/scene.hpp"
#include "bagdem/study/damper_record.hpp"

namespace bagdem::study {

struct CharacterizeArgs {
  std::string dir;                          // CASE_DIR
  std::vector<double> gamma = {0.5, 20};    // --gamma lo,hi: the acceleration ratios' range
  int amplitudes = 8;                       // --amplitudes: Gamma values, log-spaced
  std::vector<double> band;                 // --band lo,hi (Hz): default the case's sweep band(s)
  int frequencies = 6;                      // --frequencies: per band, evenly spaced, ends included
  int seeds = 5;                            // --seeds: perturbed starts per cell
  int cycles = 20;                          // --cycles: the measured cycles of each run, at least
  int skip = 5;                             // --skip: start-up cycles left out before them, at least
  double window_time = 0.25;                // --window-time: the measured window, at least (unit: s)
  double skip_time = 0.1;                   // --skip-time: the start-up left out, at least (unit: s)
  std::vector<std::string> sets;            // --set: overrides of every run
  int jobs = 0, threads = 0, cores = 0;
  std::string out;                          // default CASE_DIR/map
  bool check = false;                       // --check: plan and load, print the grid, run nothing
  std::string executable = "/proc/self/exe";
};

// The start-up cycles left out and the cycles measured at frequency f (unit: Hz): at least the
// counts asked and at least the times asked, whole cycles.
std::pair<int, int> run_cycles(const CharacterizeArgs& args, double f);

// What characterize is to run (SI units): the map's grid, which the map read back has too
// (MapAxes, reduce/predict.hpp; the map itself is one type: map.csv's cells, MapCell, read as
// EffectiveMap), the direction it shakes in and the damper it characterises.
struct MapPlan {
  MapAxes axes;
  std::vector<std::pair<double, double>> bands;  // the frequency bands of axes.frequency, lo and hi (unit: Hz)
  Vec3 direction = Vec3::UnitX(); // the prescribed motion's direction (unit vector)
  DamperRecord damper;            // the damper characterised (study/damper_record.hpp): OUT/damper.toml
  // The displacement amplitude of cell (i, j) (unit: m).
  double amplitude(std::size_t i, std::size_t j) const { return axes.amplitude_of(axes.gamma[i], axes.frequency[j]); }
};

// The plan of the command's options on a loaded scene. Throws InputError (naming the option or the
// case key) for a range that is not positive and ascending, fewer than 2 amplitudes or frequencies,
// or no band (a case without a stepped-sine sweep needs --band), and no direction (neither a
// primary structure nor harmonic cavity motion).
MapPlan map_plan(const Scene& scene, const CharacterizeArgs& args);

// The bands of a stepped-sine sweep: its frequencies sorted and split where a gap exceeds 3 times
// the median gap (one band per evaluated mode), each as [lowest, highest].
std::vector<std::pair<double, double>> stepped_sine_bands(std::vector<double> frequencies);

// One cell of the map (MapCell): reduce/map_table.hpp, with map.csv's columns.

// A cell from its starts' reduced rows: every figure's mean and 95% interval over the steady
// starts that have it (NaN where none, and an interval NaN with fewer than 2); an unsteady window
// (ReducedRow::steady = 0) is counted in `starts` and left out of the figures.
MapCell map_cell(double gamma, double frequency, double amplitude, const std::vector<ReducedRow>& starts);

// The map's tables: OUT/map.csv (a row per cell), OUT/map.json and OUT/map.h5 (a dataset per
// figure, [amplitudes x frequencies]), each to a temporary name and renamed. Columns and units:
// docs/characterize.md.
void write_map(const std::string& out_dir, const MapPlan& grid, const std::vector<MapCell>& cells, const std::string& case_dir);

// `bagdem predict CASE --map DIR` (src/study/predict_command.cpp; reduce/predict.hpp): the case's
// structure with the map's damper, without DEM.
struct PredictArgs {
  std::string dir;                       // CASE_DIR
  std::vector<std::string> maps;         // --map: a directory holding map.csv (or the file) for every damper, or NAME=DIR for one
  std::vector<std::string> amplitudes;   // force levels as written ("0.2 N"); default the case's
  int points = 400;                      // frequencies per mode's band
  std::vector<std::string> random;       // --random: RMS force levels of a band-limited random force ("0.05 N")
  std::vector<double> band;              // --band lo,hi (Hz) of the random force
  int lines = 201;                       // --lines: the random force's lines (excitation.kind = "random"'s default: 200 intervals)
  std::vector<std::string> sets;
  std::string out;                       // default CASE_DIR/predict
};
// 0 done, 2 bad input or a response outside the map (nothing written), 1 a system error.
int predict_command(const PredictArgs& args);

struct StudySpec;
struct Plan;
// The study that characterizes args.dir: its runs as the points of a study (loads the case; fills
// `grid`). Throws InputError.
StudySpec characterize_spec(const CharacterizeArgs& args, MapPlan& grid);
// After the runs: each cell from its finished points' reduced.csv, written as OUT/map.*.
struct MapOutcome {
  std::size_t missing = 0;   // runs without a result (failed or not run)
  std::size_t unsteady = 0;  // runs whose window was not steady (left out of the figures)
};
MapOutcome write_map_of(const Plan& plan, const std::vector<bool>& finished, const MapPlan& grid);

// Returns the exit code: 0 every cell done, 2 bad input (nothing run), 3 a run failed (the map is
// written with the cells that have starts).
int characterize_command(const CharacterizeArgs& args);

}  // namespace bagdem::study
