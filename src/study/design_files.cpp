// The files of `bagdem design` (study/design_files.hpp).
#include "bagdem/study/design_files.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "bagdem/case/overrides.hpp"
#include "bagdem/case/case_reader.hpp"
#include "bagdem/case/load_case.hpp"
#include "bagdem/io/atomic_file.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/reduce/predict.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;

namespace {
std::string cell(double x) { return std::isfinite(x) ? short_text(x) : ""; }

// The overrides that make a row's case: its candidate's, then its place on a beam.
std::vector<std::string> row_sets(const DesignSummary& s, const DesignRow& r, const std::vector<std::vector<std::string>>& sets) {
  Overrides o(sets.at(r.candidate));
  if (s.beam) o.set(keys::attach, r.position * s.length);
  return std::move(o).sets();
}
}  // namespace

void write_design(const DesignSummary& s, const std::vector<DesignRow>& rows) {
  std::vector<std::string> head = {"rank [1]", "status"};
  for (const Varied& v : s.candidates.vary) head.push_back(v.key);
  for (const char* c : {"position_xL [1]", "attach [m]", "added_mass [kg]", "mass_ratio [1]"}) head.push_back(c);
  for (int m : s.modes)
    for (const char* c : {"reduction_dB", "reduction_dB_lo", "reduction_dB_hi"}) head.push_back(std::string(c) + "_" + mode_label(m) + " [dB]");
  for (const char* c : {"objective_dB [dB]", "objective_dB_lo [dB]", "objective_dB_hi [dB]", "at_band_edge [1]", "interpolation_dB [dB]",
                        "pareto [1]", "dem_seeds [1]"})
    head.push_back(c);
  for (int m : s.modes)
    for (const char* c : {"dem_reduction_dB", "dem_reduction_dB_ci95"}) head.push_back(std::string(c) + "_" + mode_label(m) + " [dB]");
  for (const char* c : {"dem_objective_dB [dB]", "dem_objective_dB_ci95 [dB]", "map"}) head.push_back(c);
  std::string text;
  for (std::size_t k = 0; k < head.size(); ++k) text += (k ? "," : "") + csv_cell(head[k]);
  text += "\n";
  for (const DesignRow& r : rows) {
    std::vector<std::string> c = {r.rank ? std::to_string(r.rank) : "", r.status.text()};
    c.insert(c.end(), r.given.begin(), r.given.end());
    for (double x : {r.position, r.attach, r.added_mass, r.mass_ratio}) c.push_back(cell(x));
    for (std::size_t k = 0; k < s.modes.size(); ++k)
      for (double x : {r.db[k], r.db_lo[k], r.db_hi[k]}) c.push_back(cell(x));
    for (double x : {r.objective, r.objective_lo, r.objective_hi}) c.push_back(cell(x));
    c.push_back(std::to_string(r.at_band_edge));
    c.push_back(cell(r.interpolation_db));
    c.push_back(r.pareto ? "1" : "0");
    c.push_back(std::to_string(r.dem_seeds));
    for (std::size_t k = 0; k < s.modes.size(); ++k)
      for (double x : {k < r.dem_db.size() ? r.dem_db[k] : NAN, k < r.dem_db_ci95.size() ? r.dem_db_ci95[k] : NAN}) c.push_back(cell(x));
    c.push_back(cell(r.dem_objective));
    c.push_back(cell(r.dem_objective_ci95));
    c.push_back(fs::path(r.map).filename().string());
    for (std::size_t k = 0; k < c.size(); ++k) text += (k ? "," : "") + csv_cell(c[k]);
    text += "\n";
  }
  write_atomically(fs::path(s.candidates.out_dir) / "design.csv", text);
}

const DesignRow* chosen_row(const std::vector<DesignRow>& rows) {
  const DesignRow* best = nullptr;
  for (const DesignRow& r : rows)
    if (r.status.ranked() && std::isfinite(r.dem_objective) && (!best || r.dem_objective > best->dem_objective)) best = &r;
  if (best) return best;
  for (const DesignRow& r : rows)
    if (r.rank == 1) return &r;
  return nullptr;
}

std::string write_chosen_case(const DesignSummary& s, const std::vector<DesignRow>& rows, const std::vector<std::vector<std::string>>& sets) {
  const DesignRow* r = chosen_row(rows);
  if (!r) return "";
  const fs::path from = s.candidates.case_dir, to = fs::path(s.candidates.out_dir) / "chosen", part = to.string() + ".part";
  fs::remove_all(part);
  fs::create_directories(part);
  for (const fs::directory_entry& e : fs::directory_iterator(from))
    if (e.is_regular_file() && e.path().filename() != "case.toml") fs::copy_file(e.path(), part / e.path().filename());
  const std::vector<std::string> o = row_sets(s, *r, sets);
  std::string header = "# The bag chosen by bagdem design (" + s.candidates.out_dir + "/design.csv, rank " + std::to_string(r->rank) + "): " +
                       from.string() + "/case.toml with\n";
  for (const std::string& x : o) header += "#   " + x + "\n";
  char figures[240];
  std::snprintf(figures, sizeof figures, "# Predicted worst-mode reduction %.2f dB (%.2f to %.2f)", r->objective, r->objective_lo, r->objective_hi);
  header += figures;
  if (std::isfinite(r->dem_objective)) {
    std::snprintf(figures, sizeof figures, "; coupled DEM %.2f +- %.2f dB over %d starts", r->dem_objective, r->dem_objective_ci95, r->dem_seeds);
    header += figures;
  }
  header += ".\n# The comments of the original case are in its file.\n\n";
  write_atomically(part / "case.toml", header + CaseReader((from / "case.toml").string(), o).text() + "\n");
  load_case(part.string(), {});  // ready: it loads as it is
  fs::remove_all(to);
  fs::rename(part, to);
  return to.string();
}

void print_design(const DesignSummary& s, const std::vector<DesignRow>& rows) {
  std::printf("rank  %-44s %9s %8s  %-26s %s\n", "candidate", "x/L", "mass", "worst mode, predicted [dB]", "coupled DEM [dB]");
  int shown = 0;
  for (const DesignRow& r : rows) {
    if (!r.status.ranked() || (shown >= 10 && !r.pareto && !std::isfinite(r.dem_objective))) continue;
    ++shown;
    std::string v;
    for (std::size_t k = 0; k < r.given.size(); ++k) v += (k ? ", " : "") + r.given[k];
    char pred[64], dem[64] = "";
    std::snprintf(pred, sizeof pred, "%s%6.2f (%.2f to %.2f)%s", r.at_band_edge ? "<=" : "", r.objective, r.objective_lo, r.objective_hi,
                  r.pareto ? " P" : "");
    if (std::isfinite(r.dem_objective)) std::snprintf(dem, sizeof dem, "%.2f +- %.2f (%d)", r.dem_objective, r.dem_objective_ci95, r.dem_seeds);
    std::printf("%4d  %-44s %9s %7.2f%%  %-26s %s\n", r.rank, v.c_str(), s.beam ? short_text(r.position).c_str() : "-", 100 * r.mass_ratio, pred, dem);
  }
  std::printf("(P: on the Pareto front of reduction against added mass)\n");
  int edge = 0;
  for (const DesignRow& r : rows) edge += r.status.ranked() && r.at_band_edge > 0;
  if (edge > 0)
    std::printf("<=: %d ranked row%s predict a peak at the band's edge (at_band_edge in design.csv): the peak may lie beyond the band, "
                "so the reduction is only a bound; widen excitation.span\n", edge, edge > 1 ? "s" : "");
  int coarse = 0, unchecked = 0;
  for (const DesignRow& r : rows) {
    if (!r.status.ranked()) continue;
    if (std::isnan(r.interpolation_db)) ++unchecked;
    else if (r.interpolation_db > kInterpolationWarning) ++coarse;
  }
  if (coarse + unchecked > 0)
    std::printf("warning: the maps are too coarse for %d ranked row%s (an estimated interpolation error above %.1f dB) and too coarse to "
                "check for %d (interpolation_dB in design.csv, empty): those predictions may be off by more than their ranges; "
                "a finer map (--amplitudes, --frequencies) or the coupled check (--verify) tells\n",
                coarse, coarse == 1 ? "" : "s", kInterpolationWarning, unchecked);
}

}  // namespace bagdem::study
