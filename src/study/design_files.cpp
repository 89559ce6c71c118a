// The files of `bagdem design` (study/design_files.hpp).
#include "bagdem/study/design_files.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "bagdem/case/overrides.hpp"
#include "bagdem/case/case_reader.hpp"
#include "bagdem/case/load_case.hpp"
#include "bagdem/io/atomic_file.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/reduce/predict.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;

// A row's standing as design.csv writes it, and read back.
std::string Status::text() const {
  switch (kind) {
    case Standing::ranked: return "ranked";
    case Standing::over_budget: return "over budget";
    case Standing::does_not_load: return "does not load: " + why;
    case Standing::no_map: return "no map (its runs failed)";
    case Standing::other_damper: return "map of another damper (" + why + ")";
    case Standing::outside_map: return "outside the map " + why;
    case Standing::mode_not_in_stepped_sine: return "mode " + why + " not in the sweep at this place";
    case Standing::screened: return "screened only (" + why + ")";
  }
  return why;
}

Status Status::parse(const std::string& t) {
  auto between = [&](const std::string& head, const std::string& tail) -> std::optional<std::string> {
    if (t.size() < head.size() + tail.size() || t.compare(0, head.size(), head) != 0 || t.compare(t.size() - tail.size(), tail.size(), tail) != 0)
      return std::nullopt;
    return t.substr(head.size(), t.size() - head.size() - tail.size());
  };
  for (Standing k : {Standing::ranked, Standing::over_budget, Standing::no_map})
    if (t == Status{k, ""}.text()) return {k, ""};
  if (auto w = between("does not load: ", "")) return {Standing::does_not_load, *w};
  if (auto w = between("map of another damper (", ")")) return {Standing::other_damper, *w};
  if (auto w = between("outside the map ", "")) return {Standing::outside_map, *w};
  if (auto w = between("mode ", " not in the sweep at this place")) return {Standing::mode_not_in_stepped_sine, *w};
  if (auto w = between("screened only (", ")")) return {Standing::screened, *w};
  throw InputError("design.csv", "status", t, "is none of the statuses design writes (docs/bag-design.md)");
}

namespace {
std::string cell(double x) { return std::isfinite(x) ? short_text(x) : ""; }

// The overrides that make a row's case: its candidate's, then its place on a beam, then a pair's
// second bag.
std::vector<std::string> row_sets(const DesignSummary& s, const DesignRow& r, const std::vector<std::vector<std::string>>& sets) {
  Overrides o(sets.at(r.candidate));
  if (s.beam) o.set(keys::attach, r.position * s.length);
  std::vector<std::string> out = std::move(o).sets();
  if (r.pair) out.push_back("dampers=" + second_damper(candidate_keys(s.candidates, r.candidate2), r.attach2));
  return out;
}
}  // namespace

std::vector<std::pair<std::string, std::string>> candidate_keys(const StudySpec& cand, std::size_t c) {
  const Plan grid = make_plan(cand);
  std::vector<std::pair<std::string, std::string>> keys;
  for (std::size_t k = 0; k < cand.vary.size(); ++k) keys.emplace_back(cand.vary[k].key, cand.vary[k].values.at(grid.points.at(c).choice.at(k)).toml);
  return keys;
}

namespace {
// The columns of design.csv, in order, for the chosen modes and the varied keys.
std::vector<std::string> design_columns(const DesignTable& t) {
  std::vector<std::string> head = {"rank [1]", "status"};
  for (const std::string& v : t.varied) head.push_back(v);
  for (const char* c : {"position_xL [1]", "attach [m]"}) head.push_back(c);
  if (t.pairs) {
    for (const std::string& v : t.varied) head.push_back(v + "_2");
    for (const char* c : {"position_xL_2 [1]", "attach_2 [m]"}) head.push_back(c);
  }
  for (const char* c : {"added_mass [kg]", "mass_ratio [1]"}) head.push_back(c);
  for (int m : t.modes)
    for (const char* c : {"reduction_dB", "reduction_dB_lo", "reduction_dB_hi"}) head.push_back(std::string(c) + "_" + mode_label(m) + " [dB]");
  for (const char* c : {"objective_dB [dB]", "objective_dB_lo [dB]", "objective_dB_hi [dB]", "at_band_edge [1]", "interpolation_dB [dB]",
                        "pareto [1]", "dem_seeds [1]"})
    head.push_back(c);
  for (int m : t.modes)
    for (const char* c : {"dem_reduction_dB", "dem_reduction_dB_ci95"}) head.push_back(std::string(c) + "_" + mode_label(m) + " [dB]");
  for (const char* c : {"dem_objective_dB [dB]", "dem_objective_dB_ci95 [dB]", "map"}) head.push_back(c);
  if (t.pairs) head.push_back("map_2");
  return head;
}

// A row's cells in design_columns' order.
std::vector<std::string> design_cells(const DesignTable& t, const DesignRow& r) {
  std::vector<std::string> c = {r.rank ? std::to_string(r.rank) : "", r.status.text()};
  c.insert(c.end(), r.given.begin(), r.given.end());
  for (double x : {r.position, r.attach}) c.push_back(cell(x));
  if (t.pairs) {
    c.insert(c.end(), r.given2.begin(), r.given2.end());
    for (double x : {r.position2, r.attach2}) c.push_back(cell(x));
  }
  for (double x : {r.added_mass, r.mass_ratio}) c.push_back(cell(x));
  for (std::size_t k = 0; k < t.modes.size(); ++k)
    for (double x : {r.db[k], r.db_lo[k], r.db_hi[k]}) c.push_back(cell(x));
  for (double x : {r.objective, r.objective_lo, r.objective_hi}) c.push_back(cell(x));
  c.push_back(std::to_string(r.at_band_edge));
  c.push_back(cell(r.interpolation_db));
  c.push_back(r.pareto ? "1" : "0");
  c.push_back(std::to_string(r.dem_seeds));
  for (std::size_t k = 0; k < t.modes.size(); ++k)
    for (double x : {k < r.dem_db.size() ? r.dem_db[k] : NAN, k < r.dem_db_ci95.size() ? r.dem_db_ci95[k] : NAN}) c.push_back(cell(x));
  c.push_back(cell(r.dem_objective));
  c.push_back(cell(r.dem_objective_ci95));
  c.push_back(fs::path(r.map).filename().string());
  if (t.pairs) c.push_back(fs::path(r.map2).filename().string());
  return c;
}

// Reads one row back, cell by cell in design_columns' order.
struct CellReader {
  const TextTable& t;
  const std::vector<std::string>& row;
  std::size_t at = 0;
  const std::string& next() { return row[at++]; }
  [[noreturn]] void refuse(const std::string& value, const std::string& allowed) const {
    throw InputError(t.path, t.names[at - 1], value, allowed);
  }
  double number() {  // empty: undefined (NaN)
    const std::string& s = next();
    if (s.empty()) return NAN;
    char* end = nullptr;
    const double x = std::strtod(s.c_str(), &end);
    if (end != s.c_str() + s.size()) refuse(s, "is not a number");
    return x;
  }
  int count() {  // empty: 0
    const double x = number();
    if (std::isnan(x)) return 0;
    if (x < 0 || x != std::floor(x)) refuse(row[at - 1], "is not a count");
    return static_cast<int>(x);
  }
};

int mode_of_label(const TextTable& t, const std::string& column, const std::string& label) {
  if (label == "random") return 0;
  char* end = nullptr;
  const long m = label.rfind("mode", 0) == 0 ? std::strtol(label.c_str() + 4, &end, 10) : 0;
  if (m < 1 || *end != '\0') throw InputError(t.path, column, label, "names no mode (\"mode1\", ..., or \"random\")");
  return static_cast<int>(m);
}
}  // namespace

void write_design_csv(const fs::path& path, const DesignTable& t) {
  std::vector<std::string> head = design_columns(t);
  std::string text;
  for (std::size_t k = 0; k < head.size(); ++k) text += (k ? "," : "") + csv_cell(head[k]);
  text += "\n";
  for (const DesignRow& r : t.rows) {
    const std::vector<std::string> c = design_cells(t, r);
    for (std::size_t k = 0; k < c.size(); ++k) text += (k ? "," : "") + csv_cell(c[k]);
    text += "\n";
  }
  write_atomically(path, text);
}

DesignTable read_design_csv(const fs::path& path) {
  const TextTable t = read_text_table(path);
  DesignTable d;
  // The varied keys lie between status and position_xL; the modes are named by the reduction columns.
  const std::size_t status = t.find("status"), position = t.find("position_xL");
  if (t.find("rank") != 0 || status != 1 || position >= t.names.size())
    throw InputError(t.path, "", "", "is not a design.csv: its columns do not start rank, status, the varied keys, position_xL");
  d.varied.assign(t.names.begin() + 2, t.names.begin() + static_cast<std::ptrdiff_t>(position));
  d.pairs = t.find("position_xL_2") < t.names.size();
  for (std::size_t k = 0; k < t.names.size(); ++k) {
    const std::string& n = t.names[k];
    const std::string prefix = "reduction_dB_";
    if (n.rfind(prefix, 0) == 0 && n.find("_lo") == std::string::npos && n.find("_hi") == std::string::npos)
      d.modes.push_back(mode_of_label(t, n, n.substr(prefix.size())));
  }
  // The header must be the one this table writes for those keys and modes.
  const std::vector<std::string> head = design_columns(d);
  bool same = head.size() == t.names.size();
  for (std::size_t k = 0; same && k < head.size(); ++k)
    same = head[k] == t.names[k] + (t.units[k].empty() ? "" : " [" + t.units[k] + "]");
  if (!same) throw InputError(t.path, "", "", "is not a design.csv of this bagdem: its columns differ from those design writes");
  for (const std::vector<std::string>& row : t.rows) {
    CellReader c{t, row};
    DesignRow r;
    r.rank = c.count();
    const std::string status = c.next();
    try {
      r.status = Status::parse(status);
    } catch (const InputError&) {
      c.refuse(status, "is none of the statuses design writes (docs/bag-design.md)");
    }
    for (std::size_t k = 0; k < d.varied.size(); ++k) r.given.push_back(c.next());
    r.position = c.number(), r.attach = c.number();
    if ((r.pair = d.pairs)) {
      for (std::size_t k = 0; k < d.varied.size(); ++k) r.given2.push_back(c.next());
      r.position2 = c.number(), r.attach2 = c.number();
    }
    r.added_mass = c.number(), r.mass_ratio = c.number();
    for (std::size_t k = 0; k < d.modes.size(); ++k) r.db.push_back(c.number()), r.db_lo.push_back(c.number()), r.db_hi.push_back(c.number());
    r.objective = c.number(), r.objective_lo = c.number(), r.objective_hi = c.number();
    r.at_band_edge = c.count();
    r.interpolation_db = c.number();
    r.pareto = c.count() != 0;
    r.dem_seeds = c.count();
    for (std::size_t k = 0; k < d.modes.size(); ++k) r.dem_db.push_back(c.number()), r.dem_db_ci95.push_back(c.number());
    r.dem_objective = c.number(), r.dem_objective_ci95 = c.number();
    r.map = c.next();
    if (d.pairs) r.map2 = c.next();
    d.rows.push_back(std::move(r));
  }
  return d;
}

void write_design(const DesignSummary& s, const std::vector<DesignRow>& rows, bool pairs) {
  DesignTable t{{}, s.modes, rows, pairs};
  for (const Varied& v : s.candidates.vary) t.varied.push_back(v.key);
  write_design_csv(fs::path(s.candidates.out_dir) / (pairs ? "design-pairs.csv" : "design.csv"), t);
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

std::string write_chosen_case(const DesignSummary& s, const std::vector<DesignRow>& rows, const std::vector<std::vector<std::string>>& sets,
                              bool pairs) {
  const DesignRow* r = chosen_row(rows);
  const fs::path from = s.candidates.case_dir, to = fs::path(s.candidates.out_dir) / (pairs ? "chosen-pair" : "chosen"),
                 part = to.string() + ".part";
  if (!r) {  // nothing ranked: an earlier design's choice is not this one's
    fs::remove_all(to);
    return "";
  }
  fs::remove_all(part);
  fs::create_directories(part);
  for (const fs::directory_entry& e : fs::directory_iterator(from))
    if (e.is_regular_file() && e.path().filename() != "case.toml") fs::copy_file(e.path(), part / e.path().filename());
  const std::vector<std::string> o = row_sets(s, *r, sets);
  std::string header = std::string(r->pair ? "# The pair of bags" : "# The bag") + " chosen by bagdem design (" + s.candidates.out_dir +
                       (r->pair ? "/design-pairs.csv" : "/design.csv") + ", rank " + std::to_string(r->rank) + "): " + from.string() +
                       "/case.toml with\n";
  for (const std::string& x : o) header += "#   " + x + "\n";
  char figures[240];
  std::snprintf(figures, sizeof figures, "# Predicted worst-mode reduction %.2f dB (%.2f to %.2f)", r->objective, r->objective_lo, r->objective_hi);
  header += figures;
  if (std::isfinite(r->dem_objective)) {
    std::snprintf(figures, sizeof figures, "; coupled DEM %.2f +- %.2f dB over %d starts", r->dem_objective, r->dem_objective_ci95, r->dem_seeds);
    header += figures;
  }
  header += ".\n# The comments of the original case are in its file.\n\n";
  try {
    write_atomically(part / "case.toml", header + CaseReader((from / "case.toml").string(), o).text() + "\n");
    load_case(part.string(), {});  // ready: it loads as it is
  } catch (...) {
    fs::remove_all(part);
    throw;
  }
  fs::remove_all(to);
  fs::rename(part, to);
  return to.string();
}

void print_design(const DesignSummary& s, const std::vector<DesignRow>& rows) {
  const bool pairs = !rows.empty() && rows.front().pair;
  std::printf("rank  %-44s %9s %8s  %-26s %s\n", pairs ? "pair of bags (candidate @ x/L + candidate @ x/L)" : "candidate", "x/L", "mass",
              "worst mode, predicted [dB]", "coupled DEM [dB]");
  int shown = 0;
  for (const DesignRow& r : rows) {
    if (!r.status.ranked() || (shown >= 10 && !r.pareto && !std::isfinite(r.dem_objective))) continue;
    ++shown;
    std::string v;
    for (std::size_t k = 0; k < r.given.size(); ++k) v += (k ? ", " : "") + r.given[k];
    if (r.pair) {  // both bags, each at its place
      v += " @ " + short_text(r.position) + " +";
      for (std::size_t k = 0; k < r.given2.size(); ++k) v += (k ? ", " : " ") + r.given2[k];
      v += " @ " + short_text(r.position2);
    }
    char pred[64], dem[64] = "";
    std::snprintf(pred, sizeof pred, "%s%6.2f (%.2f to %.2f)%s", r.at_band_edge ? "<=" : "", r.objective, r.objective_lo, r.objective_hi,
                  r.pareto ? " P" : "");
    if (std::isfinite(r.dem_objective)) std::snprintf(dem, sizeof dem, "%.2f +- %.2f (%d)", r.dem_objective, r.dem_objective_ci95, r.dem_seeds);
    std::printf("%4d  %-44s %9s %7.2f%%  %-26s %s\n", r.rank, v.c_str(), s.beam && !r.pair ? short_text(r.position).c_str() : "-", 100 * r.mass_ratio, pred, dem);
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
                "check for %d (interpolation_dB in %s, empty): those predictions may be off by more than their ranges; "
                "a finer map (--amplitudes, --frequencies) or the coupled check (--verify) tells\n",
                coarse, coarse == 1 ? "" : "s", kInterpolationWarning, unchecked, pairs ? "design-pairs.csv" : "design.csv");
}

}  // namespace bagdem::study
