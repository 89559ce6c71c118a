// Prediction from an effective-field map (study/characterize.hpp): a structure's steady response
// with the damper, without running DEM. The single-harmonic balance: the contents act on the
// cavity as the impedance Z = -w^2 M_eff + i w C_eff (their force Re(-Z U e^{iwt}), U the cavity's
// amplitude), with M_eff and C_eff those the map measured at the cavity's own amplitude |U| and
// frequency. So at each frequency the cavity's amplitude X solves
//     X = |phi_b . Q(F, w, Z(X, w))|,   Q: Primary::steady_amplitudes,
// a scalar equation in X. Every root inside the map's amplitude range is a steady solution: all
// are found by sampling the residual on a log grid of X and refining each sign change by bisection,
// so the branches of a folded response (a jump, a turning point) appear as several solutions at
// one frequency. A response that would lie outside the map is refused, never extrapolated.
//
// Interpolation: bilinear in (log Gamma, f) on the map's grid, Gamma = X w^2 / g.
// Intervals: the map's 95% half-widths shift M_eff and C_eff together to the four corners
// (M_eff +- ci, C_eff +- ci); each corner is predicted again and the spread of the peak reduction
// over the corners and the mean is its interval. Where a corner leaves the map (or a cell has one
// start, whose interval is not known), so does the interval: NaN, never the range of the others.
// Resolution: linear interpolation between grid lines h apart errs by up to |f''| h^2 / 8 for a
// smooth f; f'' is estimated at each node from its neighbours (second divided differences in
// log Gamma, and in f within each band), less what the cells' scatter could make of it. M_eff and C_eff shifted by those bounds to the four corners
// are predicted again like the interval's, and the largest change of the peak reduction is the
// map's interpolation error at that answer. A map with 2 lines along an axis (2 frequencies a band)
// has no curvature to estimate and cannot check its own interpolation: it is said so.
#pragma once
#include <cmath>
#include <complex>
#include <numbers>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bagdem/structure/primary.hpp"

namespace bagdem {

// The grid of an effective-field map, as characterize plans it (study/characterize.hpp, MapPlan)
// and predict reads it (EffectiveMap): acceleration ratios by frequencies, and the one conversion
// between a cavity's amplitude and Gamma = X w^2 / g at a frequency.
struct MapAxes {
  std::vector<double> gamma, frequency;  // ascending (unit: 1, Hz)
  double g = 9.81;                       // |gravity| of the scene, 9.81 without gravity (unit: m/s^2)
  double amplitude_of(double G, double f) const {  // X = Gamma g / (2 pi f)^2 (unit: m)
    const double w = 2 * std::numbers::pi * f;
    return G * g / (w * w);
  }
  double gamma_of(double X, double f) const {  // Gamma = X (2 pi f)^2 / g
    const double w = 2 * std::numbers::pi * f;
    return X * w * w / g;
  }
};

// The map's figures that the prediction needs, on its grid (cells Gamma-major: [i * nf + j]).
struct EffectiveMap : MapAxes {
  std::vector<double> M_eff, M_eff_ci95;          // (unit: kg)
  std::vector<double> C_eff, C_eff_ci95;          // (unit: N s/m)
  std::string source;                             // the file read, for messages
  std::vector<std::pair<double, double>> bands;   // the bands characterize mapped (unit: Hz); empty: told by the lines' spacing

  // M_eff and C_eff at cavity amplitude X (m) and frequency f (Hz), each shifted by `m_sign` and
  // `c_sign` times its 95% half-width; nullopt outside the grid (Gamma or f beyond its ends) or in
  // a cell whose corners lack a figure.
  std::optional<std::pair<double, double>> at(double X, double f, int m_sign = 0, int c_sign = 0) const;
  // Whether one of the map's bands holds f (those recorded; else told by band_gap), to a relative 1e-8 at its ends (a sweep's frequencies and the map's
  // are each rounded to their own digits); a frequency so close is taken at the end.
  bool covers(double f) const;
  // Whether the lines j and j + 1 of the frequencies lie in two bands (nothing is mapped between), for
  // a map that does not record its bands: a gap wider than the spacing on either side of it.
  bool band_gap(std::size_t j) const;
  // The amplitude range of the grid at frequency f: Gamma's ends as X (unit: m).
  std::pair<double, double> amplitude_range(double f) const;
  // The same map with M_eff_ci95 and C_eff_ci95 replaced by the bound of the interpolation's error
  // at each node, |f''| h^2 / 8 summed over the two axes (h the larger spacing beside the node; an
  // end node takes its inner neighbour's f''; the frequencies' bands, parted by gaps over 3 times
  // the median spacing, each on their own); NaN where an axis (a band) has fewer than 3 lines.
  EffectiveMap interpolation_bounds() const;
};

// Reads map.csv (the columns of docs/characterize.md). Throws InputError naming the file and what
// is wrong (a missing column, a grid that is not Gamma x frequency).
EffectiveMap read_effective_map(const std::filesystem::path& map_csv);

// One steady solution at a frequency: the cavity's amplitude and the response at x_a.
struct HarmonicSolution {
  double cavity_amplitude = 0;  // X (unit: m)
  double response = 0;          // |Y| at x_a (unit: m)
  std::vector<double> cavities;  // several dampers: every cavity's X in their order (the first is
                                 // cavity_amplitude); empty with one (unit: m)
};

// One damper of a structure that carries several (a case's [[dampers]]): its map and the shapes'
// values at its cavity, phi(x_b) (Primary::at_cavity of its own scene).
struct MappedDamper {
  const EffectiveMap* map = nullptr;
  Eigen::VectorXd at_cavity;
  std::string name;
};

// The solutions at one frequency. `outside` says why there is none: "" (solutions found), "below"
// (the response lies below the map's smallest amplitude), "above" (beyond its largest), "band"
// (the frequency is outside the map's), "gap" (cells without figures in the way) or, with several
// dampers, "unsolved" (no start of Newton's method converged).
struct FrequencyPrediction {
  double frequency = 0;  // (unit: Hz)
  std::vector<HarmonicSolution> solutions;
  std::string outside;
  std::size_t outside_damper = 0;  // several dampers: whose map the response left (its index)
};

FrequencyPrediction predict_at(const Primary& primary, const EffectiveMap& map, double force, double frequency, int m_sign = 0,
                               int c_sign = 0);

// Several dampers (reduce/predict_several.cpp): each contents' impedance read from its own map at
// its own cavity's amplitude, so the cavities' amplitudes X_k solve together
//     X_k = |phi_k . Q(F, w, Z_1(X_1, w), ..., Z_n(X_n, w))|,   k = 1..n,
// (Primary::steady_amplitudes with several cavities), n equations in log X solved by Newton's
// method with a difference Jacobian and a halving line search, from the solutions at the
// frequency before (`near`: the branches continued), from the bare structure's amplitudes scaled by
// 2^12 ... 2^-12 (a damper's mass may move the resonance, so the damped response can lie above the
// bare one as well as below) and from 12 points along every map's range at one Gamma: distinct
// roots are the branches. One damper takes predict_at above (the same bits). A frequency with no
// root says "above" or "below" when a start ended against that end of a map's range, "gap" when
// it met cells without figures, else "unsolved" (no start converged), and `outside_damper` which
// damper's map.
FrequencyPrediction predict_at(const Primary& primary, const std::vector<MappedDamper>& dampers, double force, double frequency,
                               int m_sign = 0, int c_sign = 0, const std::vector<HarmonicSolution>* near = nullptr);

// Band-limited random force (excitation.kind = "random": a multisine of `lines` equal lines evenly
// over [lo, hi], its ends included, RMS F_rms): the equivalent-linear response. The contents' impedance is read at one
// amplitude A for every line, A = sqrt(2) sigma_U (the amplitude of a sine of the cavity's RMS
// sigma_U), and sigma_U^2 = sum over the lines of |U_k|^2 / 2 with U_k the cavity's amplitude under
// that line alone (Primary::steady_amplitudes, each line's force amplitude F_rms sqrt(2 / lines));
// A is iterated from the bare structure's (A <- (A + sqrt(2) sigma_U(A)) / 2) until it changes by
// less than 1e-10 relative. `outside` as FrequencyPrediction's when a line or A leaves the map.
struct RandomPrediction {
  double cavity_rms = 0, response_rms = 0;  // sigma_U at x_b and sigma_Y at x_a (unit: m)
  double bare_response_rms = 0;             // sigma_Y of the bare structure (unit: m)
  int iterations = 0;
  bool converged = false;
  std::string outside;
};
RandomPrediction predict_random(const Primary& primary, const EffectiveMap& map, double rms, double lo, double hi, int lines = 201,
                                int m_sign = 0, int c_sign = 0);

// predict_random at the map's means, and the range of the response RMS over the map's four
// interval corners (NaN when a corner leaves the map or does not converge: the interval is not known).
struct RandomPredictionRange {
  RandomPrediction mean;
  double response_rms_lo = 0, response_rms_hi = 0;  // NaN unless all four corners converge inside the map (unit: m)
  int corners = 0;                                   // of the four, those that did
};
RandomPredictionRange predict_random_range(const Primary& primary, const EffectiveMap& map, double rms, double lo, double hi,
                                           int lines = 201);

// A structure's response over a mode's band at one force level: the largest solution at each
// frequency against the bare structure, and the peak reduction with its interval.
struct PredictedMode {
  std::size_t mode = 0;                   // elastic mode number
  double lo = 0, hi = 0;                  // its band (unit: Hz)
  std::vector<FrequencyPrediction> points;  // the map's means, at `frequencies` over the band
  std::vector<double> bare;               // |H_bare| F at x_a at the same frequencies (unit: m)
  double bare_peak = 0, bare_frequency = 0;  // the bare structure's peak, as a sweep finds it (bare_peak) (unit: m, Hz)
  double peak = 0, peak_frequency = 0;    // the damped peak: the largest solution over the band (unit: m, Hz)
  double peak_cavity_gamma = 0;           // the cavity's Gamma = X w^2 / g there: where the map is read (unit: 1)
  double reduction_db = 0;                // 20 log10(bare_peak / peak)
  double reduction_db_lo = 0, reduction_db_hi = 0;  // its range over the map's interval corners; NaN unless all four are inside the map (unit: dB)
  int corners = 0;                        // of the four corners, those inside the map at every frequency of the band
  bool at_band_edge = false;              // the damped peak is the band's first or last frequency: it may lie
                                          // beyond the band, and the reduction is then only a bound (at most)
  // The resolution check: the largest change of reduction_db over the interpolation bounds' four
  // corners (NaN: the map has too few lines to estimate them, or a corner leaves the map) (unit: dB).
  double interpolation_db = NAN;
  std::vector<double> outside;            // frequencies the map does not cover (the prediction is then refused)
  std::string outside_why;                // the first one's reason: below, above, band
  std::size_t outside_damper = 0;         // several dampers: whose map it is (index)
};

// An estimated interpolation error above this is "a map too coarse for the answer" (unit: dB): a
// third of the 1.5 dB within which predictions met coupled DEM (docs/characterize.md).
inline constexpr double kInterpolationWarning = 0.5;

// What predict_modes works out besides the means: the interval over the corners, and the resolution check.
enum class Checks { none, interval, all };
// The case's evaluated modes (Primary::evaluated_modes over `frequencies`, each band the span of
// the frequencies nearest its mode), `points` evenly spaced frequencies per band.
std::vector<PredictedMode> predict_modes(const Primary& primary, const EffectiveMap& map, double force,
                                         const std::vector<double>& frequencies, int points = 400, Checks checks = Checks::all);
// The same with several dampers, every map shifted to the same corner of its interval together
// (and to its interpolation bounds together); `primary` the case's own damper's (its mass matrix
// holds every cavity's mass). One damper gives the bits of the call above.
std::vector<PredictedMode> predict_modes(const Primary& primary, const std::vector<MappedDamper>& dampers, double force,
                                         const std::vector<double>& frequencies, int points = 400, Checks checks = Checks::all);

}  // namespace bagdem
