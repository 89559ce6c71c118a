// Impacts of the contents on the cavity walls, found in the contents' force on the cavity, and the
// restitution of each impact.
//
// Conventions: SI units. The force F is the component along the excitation axis of the force the
// contents exert on the cavity, recorded as interval means F_k = (1/Delta) integral over
// [t_k - Delta, t_k] (docs/reference-study.md, section 5; io/results_file.hpp), at uniform times t_k. Contents
// moving in +x hit the +x wall and push the cavity in +x: F > 0, side = +1.
//
// An impact is a maximal run of samples with |F_k| > threshold and one sign (a run is split where F
// changes sign, so each impact has one side); threshold = threshold_fraction * max |F_k| after t_skip.
// Consecutive impacts of the same side separated by less than merge_gap (from the end of one to the
// start of the next, t_start' - t_end) are merged into one, with the samples between. A run that the
// record cuts (at its first sample, or at t_skip while the sample before t_skip is above the
// threshold too, or at its last sample) is left out: its impulse and duration are unknown.
// Timing, from the samples a .. b above the threshold:
//   t_start = t_a - Delta (the start of the first interval above the threshold), t_end = t_b
//   peak_force = max |F_k|
// Impulse, from the whole pulse: the samples below the threshold at the pulse's ends still carry
// impulse (a half-sine at threshold fraction 0.05 keeps about 1% of it there), so the impulse and the
// centroid extend from a .. b outwards to the pulse's feet a' .. b': as long as |F| keeps falling and
// keeps its sign (stopping at a zero, a sign change or a local minimum of |F|, at t_skip, and at the
// previous impact's foot):
//   t_foot_start = t_a' - Delta, t_foot_end = t_b'
//   impulse    = sum_k F_k Delta over [a', b'] = integral of F over [t_foot_start, t_foot_end], exact
//   t_centroid = sum_k |F_k| (t_k - Delta/2) / sum_k |F_k| over [a', b']: interval midpoints weighted
//                by force
// For a pulse that rises from and falls back to zero the impulse is its whole impulse, exact (the
// interval means telescope); a steady background force (friction on the cavity floor) ends the feet
// at its level, and the part of the background under the pulse is counted.
// Resolution: interval means keep the impulse exactly but not the shape inside an interval.
//  * Duration: if the force is near linear across each threshold crossing, t_start and t_end lie
//    within Delta/2 of the times the force crosses the threshold, so the duration is known to about
//    one sample interval (to 2 Delta at worst). It is the time above the threshold: a half-sine of
//    duration tau at threshold fraction q is above it for tau (1 - (2/pi) asin q).
//  * Peak: the mean over an interval, below the true peak: for a half-sine of duration tau by about
//    (pi Delta / tau)^2 / 24 at best, and a pulse shorter than Delta is spread over a whole interval.
//  * Centroid: exact for a pulse symmetric about an interval boundary or midpoint; otherwise off by
//    a fraction of Delta (a pulse inside one interval is put at the interval's midpoint).
//
// Restitution (docs/reference-study.md, section 5 (i); the study's Eq. (9)): from the contents' centre-of-mass
// velocity relative to the cavity, v (point samples at the same times), e = -v_after / v_before, with
// v_before the sample at t_foot_start (the last sample before any of the pulse's force) and v_after
// the sample at t_foot_end (the first sample after all of it), so the whole velocity change counts.
// Only impacts in which the contents approach the wall that was hit count: v_before * side > 0
// (contents moving in +x hit the +x wall, side +1). Others (the bag pushed by a wall it is leaving,
// or pulled by its strings) are skipped.
#pragma once
#include <functional>
#include <limits>
#include <vector>

namespace bagdem {

struct Impact {
  double t_start = 0, t_end = 0;  // first and last sample time above the threshold, widened by one interval before (s)
  double t_foot_start = 0, t_foot_end = 0;  // the same for the whole pulse, foot to foot: what impulse, centroid cover (s)
  double t_centroid = 0;          // force-weighted mean time (unit: s)
  double peak_force = 0;          // largest |F_k| (unit: N)
  double impulse = 0;             // integral of F over the whole pulse (unit: N s), signed
  int side = 0;                   // sign of the impulse: which wall (+1 / -1 along the axis)
  double duration() const { return t_end - t_start; }  // (unit: s)
};

// Impacts in an interval-mean force signal (uniform samples), in time order. threshold_fraction in
// (0, 1), merge_gap >= 0 (unit: s; 0 merges nothing). Throws std::invalid_argument for sizes that
// differ, non-uniform t, or parameters out of range. No impacts when F is zero after t_skip.
std::vector<Impact> find_impacts(const std::vector<double>& t, const std::vector<double>& force, double t_skip,
                                 double threshold_fraction = 0.05, double merge_gap = 0);

struct RestitutionStats {
  std::vector<double> values;   // e of each counted impact, in time order
  // Mean, sample sd (n - 1) and sd / sqrt(n); NaN when undefined (no values; fewer than 2 for sd and error).
  double mean = 0, sd = 0, standard_error = 0;
  // The contents' restitution as one body: the mean, or NaN when the mean is negative. A negative
  // mean says the contents' centre of mass keeps moving towards the wall after the pulses (a bed
  // that fills its box and shears rather than rebounds): no restitution of a body to report.
  double body() const { return mean >= 0 ? mean : std::numeric_limits<double>::quiet_NaN(); }
};

// Which impacts give a restitution (the study's Eq. (9) assumes an instantaneous impact between
// free flights): the contents must fly free of every wall for `span` before the pulse's first foot
// and after its last one (|F| at or below `threshold` at every sample there, and the span inside
// the record), and approach the wall at `min_approach_speed` or faster. Otherwise the velocities
// around the pulse carry other walls' forces, or a slow approach turns the ratio into noise.
// The default asks nothing.
struct FreeFlight {
  double span = 0;                // (unit: s)
  double threshold = 0;           // (unit: N)
  double min_approach_speed = 0;  // (unit: m/s)
};

// The wall's velocity along the axis at time t (unit: m/s), for the velocities' frame (below); a
// null function keeps the velocities relative to the cavity at each sample.
using WallVelocity = std::function<double(double)>;

// Restitution of each impact from the relative velocity v (contents' centre of mass minus cavity,
// along the same axis, point samples at the times t; unit: m/s), over [t_foot_start, t_foot_end].
// An impact without a sample at or before t_foot_start or at or after t_foot_end is skipped, and so
// is one that fails `rule` (which reads the force F at the times t; it may be empty when the rule
// asks no free flight).
// The frame. A bag's impact lasts a good part of a period, and the wall accelerates meanwhile: the
// velocities relative to the wall at the two feet differ by the wall's own change of velocity, which
// can exceed the approach speed itself (and give e > 1). With `wall`, both velocities are taken
// relative to the wall's velocity at the impact's centroid t_c instead:
//     u = v_rel + v_wall(t_foot) - v_wall(t_c),    e = -u_after / u_before,
// the restitution of the instantaneous impact at t_c that exchanges the same momentum. In that
// inertial frame the wall moves by a (t - t_c) to first order, and its work on the contents,
// a integral of F (t - t_c) dt, vanishes by the centroid's definition: a passive bed gives e <= 1.
// Throws std::invalid_argument for sizes that differ or non-uniform t.
RestitutionStats impact_restitution(const std::vector<Impact>& impacts, const std::vector<double>& t,
                                    const std::vector<double>& v, const std::vector<double>& force = {},
                                    const FreeFlight& rule = {}, const WallVelocity& wall = {});

}  // namespace bagdem
