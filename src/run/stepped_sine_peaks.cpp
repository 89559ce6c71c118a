// The peaks of a stepped sine (run/stepped_sine_peaks.hpp, run/stepped_sine.hpp).
#include "stepped_sine_peaks.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>

#include "bagdem/error.hpp"
#include "bagdem/reduce/summary.hpp"
#include "bagdem/io/atomic_file.hpp"
#include "bagdem/io/recorded_table.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/structure/response.hpp"
#include "stepped_sine_files.hpp"

namespace bagdem {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

std::vector<ModePoints> group_by_mode(const Primary& P, const std::vector<SteppedSinePoint>& points) {
  std::vector<ModePoints> out;
  if (points.empty()) return out;
  std::vector<const SteppedSinePoint*> pts;
  for (const SteppedSinePoint& p : points) pts.push_back(&p);
  std::sort(pts.begin(), pts.end(), [](const SteppedSinePoint* a, const SteppedSinePoint* b) { return a->frequency < b->frequency; });
  for (std::size_t m : P.evaluated_modes(pts.front()->frequency, pts.back()->frequency)) {
    ModePoints mp{m, {}};
    for (const SteppedSinePoint* p : pts)
      if (P.nearest_elastic_mode(p->frequency) == m) mp.points.push_back(p);
    if (!mp.points.empty()) out.push_back(std::move(mp));
  }
  return out;
}

std::vector<double> refinement_frequencies(const ModePoints& m, double dt, std::size_t n) {
  const auto& p = m.points;
  std::size_t k = 0;
  for (std::size_t i = 1; i < p.size(); ++i)
    if (std::abs(p[i]->receptance) > std::abs(p[k]->receptance)) k = i;
  if (k == 0 || k + 1 >= p.size()) return {};
  const SteppedSinePoint* side = std::abs(p[k - 1]->receptance) > std::abs(p[k + 1]->receptance) ? p[k - 1] : p[k + 1];
  const double a = p[k]->frequency, b = side->frequency, parts = static_cast<double>(n + 1);
  std::vector<std::size_t> used = {steps_per_cycle(a, dt), steps_per_cycle(b, dt)};
  std::vector<double> out;
  for (std::size_t j = 1; j <= n; ++j) {
    const double J = static_cast<double>(j), f = ((parts - J) * a + J * b) / parts;  // n = 1: (a + b) / 2
    const std::size_t N = steps_per_cycle(f, dt);
    if (std::find(used.begin(), used.end(), N) != used.end() || !(std::abs(f - a) > 1e-4 * a)) continue;
    used.push_back(N), out.push_back(f);
  }
  return out;
}

void write_peaks_csv(const std::filesystem::path& path, const std::vector<ModePeak>& peaks) {
  static const std::vector<TableColumn> columns = {
      {"mode", "1"}, {"bare_frequency", "Hz"}, {"bare_peak", "m/N"}, {"frequency", "Hz"}, {"peak", "m/N"},
      {"simulated_frequency", "Hz"}, {"simulated_peak", "m/N"}, {"peak_ci95", "m/N"}, {"reduction_dB", "dB"},
      {"reduction_dB_ci95", "dB"}, {"reduction_percent", "%"}, {"at_band_edge", "1"}, {"unsteady_points", "1"}};
  std::vector<std::vector<double>> rows;
  for (const ModePeak& m : peaks)
    rows.push_back({static_cast<double>(m.mode), m.bare_frequency, m.bare_peak, m.frequency, m.peak, m.simulated_frequency,
                    m.simulated_peak, m.peak_ci95, m.reduction_db, m.reduction_db_ci95, m.reduction_percent,
                    m.at_band_edge ? 1.0 : 0.0, static_cast<double>(m.unsteady_points)});
  write_table_csv(path, columns, rows);
}

std::vector<ModePeak> sweep_peaks(const Primary& P, const std::vector<SteppedSinePoint>& points) {
  std::vector<ModePeak> out;
  // The modes and their bands from every point; the damped peak from the steady ones alone. Points
  // left out must not narrow the band the bare structure is searched in (were the points around
  // the bare resonance unsteady, the steady ones' band would miss it).
  for (const ModePoints& all : group_by_mode(P, points)) {
    std::vector<const SteppedSinePoint*> steady;
    for (const SteppedSinePoint* p : all.points)
      if (p->steady) steady.push_back(p);
    if (steady.empty()) continue;
    std::vector<double> f, mag;
    for (const SteppedSinePoint* p : steady) f.push_back(p->frequency), mag.push_back(std::abs(p->receptance));
    ModePeak mp;
    mp.name = P.dof_names[all.dof];
    mp.mode = P.elastic_mode_number(all.dof);
    const std::size_t top = static_cast<std::size_t>(std::max_element(mag.begin(), mag.end()) - mag.begin());
    // The peak is refined through the largest and its steady neighbours, which is exact for one
    // mode; a point left out between them (it did not settle) leaves the three to span a stretch
    // the response was not measured on, and a damper's response there need not be one mode's (a
    // refinement across such a gap once read 11 times the largest response). The largest simulated
    // stands then: the warning of the left-out points says so.
    const bool gap = top > 0 && top + 1 < f.size() && std::any_of(all.points.begin(), all.points.end(), [&](const SteppedSinePoint* p) {
                       return !p->steady && p->frequency > f[top - 1] && p->frequency < f[top + 1];
                     });
    const Peak damped = gap ? Peak{f[top], mag[top]} : find_peak(f, mag, f.front(), f.back());
    const Peak bare = bare_peak(P, all.points.front()->frequency, all.points.back()->frequency);
    mp.frequency = damped.frequency, mp.peak = damped.magnitude;
    mp.simulated_frequency = f[top], mp.simulated_peak = mag[top];
    mp.peak_ci95 = steady[top]->receptance_ci95;
    mp.at_band_edge = top == 0 || top + 1 == f.size();
    mp.bare_frequency = bare.frequency, mp.bare_peak = bare.magnitude;
    mp.reduction_db = reduction_db(bare.magnitude, damped.magnitude);
    mp.reduction_percent = reduction_percent(mp.reduction_db);
    // dB of the relative half-width: 20 log10(1 + ci / |H|), the larger side.
    mp.reduction_db_ci95 = mp.simulated_peak > 0 ? 20 * std::log10(1 + mp.peak_ci95 / mp.simulated_peak) : kNaN;
    mp.unsteady_points = all.points.size() - steady.size();
    out.push_back(mp);
  }
  return out;
}


std::vector<ModePeak> recompute_stepped_sine_peaks(const Primary& P, const std::filesystem::path& out) {
  const std::filesystem::path summary_path = out / "summary.json", peaks_path = out / "peaks.csv";
  if (!std::filesystem::exists(summary_path))
    throw InputError(summary_path.string(), "", "", "no complete stepped-sine sweep here (its summary.json is missing)");
  Summary summary = read_summary(summary_path);
  if (summary.kind != SummaryKind::stepped_sine)
    throw InputError(summary_path.string(), "", "", "no complete stepped-sine sweep here (its summary.json has no peaks of a stepped-sine sweep)");
  require_recorded_table(out / "sweep.csv", out / "results.h5", "sweep", kSteppedSineColumns);
  const std::vector<ModePeak> peaks = sweep_peaks(P, read_stepped_sine_csv(out / "sweep.csv"));
  // The bare peaks depend on the structure alone: they must be those the run recorded.
  const std::vector<std::vector<double>> recorded = read_table_csv(peaks_path, {{"mode", "1"}, {"bare_peak", "m/N"}});
  bool same = recorded.size() == peaks.size();
  for (std::size_t k = 0; same && k < peaks.size(); ++k)
    same = recorded[k][0] == static_cast<double>(peaks[k].mode) && std::abs(recorded[k][1] - peaks[k].bare_peak) <= 1e-9 * peaks[k].bare_peak;
  if (!same)
    throw InputError(peaks_path.string(), "bare_peak", "", "the case's bare structure differs from the run's: give the case and the --set the run was made with");
  write_peaks_csv(peaks_path, peaks);
  summary.peaks = peaks;
  write_summary(summary_path, summary);
  return peaks;
}

std::vector<std::string> missing_peaks(const Primary& P, const std::vector<SteppedSinePoint>& points) {
  std::vector<std::string> out;
  if (points.empty()) return out;
  const std::vector<ModePoints> modes = group_by_mode(P, points);
  if (modes.empty()) {
    const auto [lo, hi] = std::minmax_element(points.begin(), points.end(), [](const SteppedSinePoint& a, const SteppedSinePoint& b) { return a.frequency < b.frequency; });
    std::ostringstream m;
    m << "no peak reduction: the swept band " << lo->frequency << "-" << hi->frequency
      << " Hz holds no natural frequency of the structure (bagdem check lists them): set excitation.around_modes, or the frequencies around one";
    out.push_back(m.str());
  }
  for (const ModePoints& m : modes)
    if (std::none_of(m.points.begin(), m.points.end(), [](const SteppedSinePoint* p) { return p->steady; }))
      out.push_back("no peak reduction for " + P.dof_names[m.dof] + ": every one of its " + std::to_string(m.points.size()) +
                    " points was unsteady (the warnings above say why): raise excitation.max_cycles or excitation.steady_tolerance");
  return out;
}

std::string describe_peak(const ModePeak& m) {
  std::ostringstream o;
  o << std::setprecision(4) << m.name << ": ";
  if (m.at_band_edge) o << "AT THE BAND'S EDGE (the peak may lie outside the swept band; widen excitation.span): ";
  o << "peak " << m.peak << " m/N at " << std::setprecision(5) << m.frequency << " Hz (largest simulated " << std::setprecision(4)
    << m.simulated_peak << " +- " << m.peak_ci95 << " m/N at " << std::setprecision(5) << m.simulated_frequency << " Hz; bare "
    << std::setprecision(4) << m.bare_peak << " m/N at " << std::setprecision(5) << m.bare_frequency << " Hz): reduction "
    << (m.at_band_edge ? "at most " : "") << std::fixed << std::setprecision(2) << m.reduction_db << " +- " << m.reduction_db_ci95
    << " dB = " << std::setprecision(1) << m.reduction_percent << "%";
  if (m.unsteady_points > 0)
    o << " (" << m.unsteady_points << " unsteady point" << (m.unsteady_points > 1 ? "s" : "") << " left out"
      << (m.frequency == m.simulated_frequency && m.peak == m.simulated_peak ? "; the peak is the largest simulated, not refined across them" : "")
      << ")";
  return o.str();
}

}  // namespace bagdem
