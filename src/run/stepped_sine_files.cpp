// A stepped sine's own tables (stepped_sine_files.hpp).
#include "stepped_sine_files.hpp"

#include <omp.h>

#include <algorithm>
#include <iomanip>
#include <numbers>
#include <sstream>

#include "bagdem/io/json.hpp"
#include "stepped_sine_peaks.hpp"

namespace bagdem {
namespace fs = std::filesystem;

namespace {
constexpr double kTwoPi = 2 * std::numbers::pi;
}  // namespace

const std::vector<TableColumn> kSteppedSineColumns = {
    {"requested_frequency", "Hz"}, {"frequency", "Hz"},
    {"response_re", "m"},          {"response_im", "m"},
    {"receptance_re", "m/N"},      {"receptance_im", "m/N"},
    {"bare_receptance_re", "m/N"}, {"bare_receptance_im", "m/N"},
    {"acceleration_re", "m/s^2"},  {"acceleration_im", "m/s^2"},
    {"accelerance_abs", "m/s^2/N"}, {"bare_accelerance_abs", "m/s^2/N"},
    {"cavity_re", "m"},            {"cavity_im", "m"},
    {"contents_force_re", "N"},    {"contents_force_im", "N"},
    {"work_external_per_cycle", "J"}, {"dissipated_structure_per_cycle", "J"},
    {"dissipated_contents_per_cycle", "J"}, {"energy_balance", "1"},
    {"receptance_abs_ci95", "m/N"},
    {"cycles", "1"},               {"steady", "1"},
    {"spread", "1"},
    {"change", "1"},               {"wall_time", "s"}};

std::vector<double> stepped_sine_row(const SteppedSinePoint& p) {
  const double w = kTwoPi * p.frequency;
  return {p.requested, p.frequency, p.response.real(), p.response.imag(), p.receptance.real(), p.receptance.imag(),
          p.bare.real(), p.bare.imag(), -w * w * p.response.real(), -w * w * p.response.imag(), w * w * std::abs(p.receptance), w * w * std::abs(p.bare), p.cavity.real(),
          p.cavity.imag(), p.contents_force.real(), p.contents_force.imag(), p.work_external, p.dissipated_structure,
          p.dissipated_contents, p.balance, p.receptance_ci95, static_cast<double>(p.cycles), p.steady ? 1.0 : 0.0, p.spread, p.change,
          p.wall_seconds};
}

void write_stepped_sine_csv(const fs::path& path, const std::vector<SteppedSinePoint>& points) {
  std::vector<std::vector<double>> rows;
  for (const SteppedSinePoint& p : points) rows.push_back(stepped_sine_row(p));
  write_table_csv(path, kSteppedSineColumns, rows);
}

std::vector<SteppedSinePoint> read_stepped_sine_csv(const fs::path& path) {
  std::vector<SteppedSinePoint> points;
  for (const std::vector<double>& r : read_table_csv(path, kSteppedSineColumns)) {
    SteppedSinePoint p;
    p.requested = r[0], p.frequency = r[1], p.response = {r[2], r[3]}, p.receptance = {r[4], r[5]}, p.bare = {r[6], r[7]};
    p.cavity = {r[12], r[13]}, p.contents_force = {r[14], r[15]};
    p.work_external = r[16], p.dissipated_structure = r[17], p.dissipated_contents = r[18], p.balance = r[19];
    p.receptance_ci95 = r[20], p.cycles = static_cast<std::size_t>(r[21]), p.steady = r[22] != 0;
    p.spread = r[23], p.change = r[24], p.wall_seconds = r[25];
    points.push_back(p);
  }
  return points;
}

void write_bare_curve(const fs::path& path, const Primary& P, const std::vector<SteppedSinePoint>& points) {
  static const std::vector<TableColumn> columns = {{"frequency", "Hz"}, {"bare_receptance_abs", "m/N"}, {"bare_accelerance_abs", "m/s^2/N"}};
  if (points.empty()) return;
  double lo = points.front().frequency, hi = lo;
  for (const SteppedSinePoint& p : points) lo = std::min(lo, p.frequency), hi = std::max(hi, p.frequency);
  std::vector<std::vector<double>> rows;
  const int n = hi > lo ? 400 : 1;
  for (int k = 0; k < n; ++k) {
    const double f = n > 1 ? lo + (hi - lo) * k / (n - 1) : lo, w = kTwoPi * f, h = std::abs(P.bare_receptance(w));
    rows.push_back({f, h, w * w * h});
  }
  write_table_csv(path, columns, rows);
}

Summary stepped_sine_summary(const Scene& scene, const SteppedSineReport& rep, std::size_t particles, std::size_t chains) {
  Summary s;
  s.kind = SummaryKind::stepped_sine;
  s.case_file = scene.case_file, s.particles = particles, s.dt = scene.dt, s.threads = omp_get_max_threads();
  s.chains = chains, s.wall_time = rep.wall_seconds, s.points = rep.points.size();
  s.not_steady = static_cast<std::size_t>(std::count_if(rep.points.begin(), rep.points.end(), [](const SteppedSinePoint& p) { return !p.steady; }));
  s.force_amplitude = scene.primary->amplitude;
  s.peaks_missing = missing_peaks(*scene.primary, rep.points);  // why a mode has no peak
  s.peaks = rep.peaks;
  return s;
}

}  // namespace bagdem
