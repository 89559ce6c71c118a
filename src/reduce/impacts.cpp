// Impacts in the contents' force on the cavity, and their restitution (reduce/impacts.hpp).
#include "bagdem/reduce/impacts.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#include "bagdem/reduce/harmonic_projection.hpp"

namespace bagdem {

namespace {

// One impact: the samples above the threshold [first, last], the pulse's feet [foot_first, foot_last]
// (inclusive), and its side.
struct Run {
  std::size_t first = 0, last = 0, foot_first = 0, foot_last = 0;
  int side = 0;
};

int sign(double x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); }

Impact describe(const std::vector<double>& t, const std::vector<double>& F, const Run& r, double delta) {
  Impact m;
  // Interval k is [t_k - Delta, t_k]; every kept run and foot starts at sample 1 or later.
  m.t_start = t[r.first - 1];
  m.t_end = t[r.last];
  m.t_foot_start = t[r.foot_first - 1];
  m.t_foot_end = t[r.foot_last];
  double weighted_time = 0, weight = 0;
  for (std::size_t k = r.foot_first; k <= r.foot_last; ++k) {
    m.impulse += F[k] * delta;
    weighted_time += std::abs(F[k]) * (t[k] - 0.5 * delta);  // interval k's midpoint
    weight += std::abs(F[k]);
  }
  for (std::size_t k = r.first; k <= r.last; ++k) m.peak_force = std::max(m.peak_force, std::abs(F[k]));
  m.t_centroid = weighted_time / weight;
  m.side = m.impulse != 0 ? sign(m.impulse) : r.side;
  return m;
}

}  // namespace

std::vector<Impact> find_impacts(const std::vector<double>& t, const std::vector<double>& force, double t_skip,
                                 double threshold_fraction, double merge_gap) {
  if (force.size() != t.size())
    throw std::invalid_argument("find_impacts: " + std::to_string(force.size()) + " force values for " +
                                std::to_string(t.size()) + " times");
  if (!(threshold_fraction > 0 && threshold_fraction < 1))
    throw std::invalid_argument("find_impacts: threshold_fraction = " + std::to_string(threshold_fraction) +
                                " must lie in (0, 1)");
  if (!(merge_gap >= 0) || !std::isfinite(merge_gap))
    throw std::invalid_argument("find_impacts: merge_gap = " + std::to_string(merge_gap) + " s must be >= 0");
  const double delta = sample_interval(t);
  const std::size_t S = t.size();
  std::size_t i0 = 0;
  while (i0 < S && t[i0] < t_skip) ++i0;
  double largest = 0;
  for (std::size_t k = i0; k < S; ++k) largest = std::max(largest, std::abs(force[k]));
  if (largest == 0) return {};
  const double threshold = threshold_fraction * largest;
  auto above = [&](std::size_t k) { return std::abs(force[k]) > threshold; };

  // Maximal runs above the threshold of one sign.
  std::vector<Run> runs;
  for (std::size_t k = i0; k < S;) {
    if (!above(k)) {
      ++k;
      continue;
    }
    Run r{.first = k, .last = k, .foot_first = k, .foot_last = k, .side = sign(force[k])};
    while (r.last + 1 < S && above(r.last + 1) && sign(force[r.last + 1]) == r.side) ++r.last;
    k = r.last + 1;
    // Cut by the record: started before the first analysed sample (or the record), or still going.
    const bool cut_at_start = r.first == 0 || (r.first == i0 && above(i0 - 1) && sign(force[i0 - 1]) == r.side);
    const bool cut_at_end = r.last + 1 == S;
    if (!cut_at_start && !cut_at_end) runs.push_back(r);
  }

  // Merge neighbours of one side closer than merge_gap: gap = t_start(next) - t_end(previous).
  std::vector<Run> merged;
  for (const Run& r : runs) {
    if (!merged.empty()) {
      Run& prev = merged.back();
      const double gap = t[r.first - 1] - t[prev.last];
      if (prev.side == r.side && gap < merge_gap) {
        prev.last = r.last;
        continue;
      }
    }
    merged.push_back(r);
  }

  // The feet: outwards while |F| falls and keeps the impact's sign, never before sample 1 (interval 0
  // has no recorded start), t_skip, or the previous impact's foot.
  std::vector<Impact> impacts;
  impacts.reserve(merged.size());
  std::size_t lowest = std::max<std::size_t>(i0, 1);
  auto tail = [&](std::size_t from, std::size_t to, int side) {
    return sign(force[to]) == side && std::abs(force[to]) < std::abs(force[from]);
  };
  for (Run& r : merged) {
    r.foot_first = r.first;
    while (r.foot_first > lowest && tail(r.foot_first, r.foot_first - 1, r.side)) --r.foot_first;
    r.foot_last = r.last;
    while (r.foot_last + 1 < S && tail(r.foot_last, r.foot_last + 1, r.side)) ++r.foot_last;
    lowest = r.foot_last + 1;
    impacts.push_back(describe(t, force, r, delta));
  }
  return impacts;
}

RestitutionStats impact_restitution(const std::vector<Impact>& impacts, const std::vector<double>& t,
                                    const std::vector<double>& v, const std::vector<double>& force,
                                    const FreeFlight& rule) {
  if (v.size() != t.size())
    throw std::invalid_argument("impact_restitution: " + std::to_string(v.size()) + " velocities for " +
                                std::to_string(t.size()) + " times");
  if (rule.span > 0 && force.size() != t.size())
    throw std::invalid_argument("impact_restitution: " + std::to_string(force.size()) + " forces for " +
                                std::to_string(t.size()) + " times");
  // Free flight over [from, to]: inside the record, and no sample there above the threshold.
  auto free_over = [&](double from, double to) {
    if (rule.span <= 0) return true;
    if (from < t.front() || to > t.back()) return false;
    const auto first = std::lower_bound(t.begin(), t.end(), from), last = std::upper_bound(t.begin(), t.end(), to);
    for (auto k = first; k != last; ++k)
      if (std::abs(force[static_cast<std::size_t>(k - t.begin())]) > rule.threshold) return false;
    return true;
  };
  const double delta = sample_interval(t);
  const double tolerance = 1e-6 * delta;  // t_start and t_end are sample times, up to round-off
  RestitutionStats stats;
  for (const Impact& m : impacts) {
    // The last sample at or before the pulse's first foot and the first at or after its last.
    const auto before = std::upper_bound(t.begin(), t.end(), m.t_foot_start + tolerance);
    const auto after = std::lower_bound(t.begin(), t.end(), m.t_foot_end - tolerance);
    if (before == t.begin() || after == t.end()) continue;
    const double v_before = v[static_cast<std::size_t>(before - t.begin()) - 1];
    const double v_after = v[static_cast<std::size_t>(after - t.begin())];
    // The contents must approach the wall that was hit: towards +x for the +x wall (side +1).
    if (!(v_before * m.side > 0) || std::abs(v_before) < rule.min_approach_speed) continue;
    // Interval k covers [t_k - Delta, t_k]: the flight before ends with the sample at t_foot_start,
    // the flight after starts with the interval after t_foot_end.
    if (!free_over(m.t_foot_start - rule.span + tolerance, m.t_foot_start + tolerance) ||
        !free_over(m.t_foot_end + delta - tolerance, m.t_foot_end + rule.span - tolerance))
      continue;
    stats.values.push_back(-v_after / v_before);
  }
  const std::size_t n = stats.values.size();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  stats.mean = stats.sd = stats.standard_error = kNaN;
  if (n == 0) return stats;
  double sum = 0;
  for (double e : stats.values) sum += e;
  stats.mean = sum / static_cast<double>(n);
  if (n < 2) return stats;
  double ss = 0;
  for (double e : stats.values) ss += (e - stats.mean) * (e - stats.mean);
  stats.sd = std::sqrt(ss / static_cast<double>(n - 1));
  stats.standard_error = stats.sd / std::sqrt(static_cast<double>(n));
  return stats;
}

}  // namespace bagdem
