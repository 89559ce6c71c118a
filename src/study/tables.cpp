// Merging the points' tables (study/study.hpp): CSV in and out, the merged table with the inputs
// in front, the ensemble statistics over the seeds, and the files in OUT.
// A point's own cells are copied as text, so the merged table holds exactly what the run wrote.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "bagdem/io/atomic_file.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/reduce/export.hpp"
#include "bagdem/reduce/interval.hpp"
#include "bagdem/study/study.hpp"
#include "bagdem/units.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The shortest text that reads back to the same double.
std::string number_text(double x) {
  if (std::isnan(x)) return "nan";
  char b[32];
  const auto r = std::to_chars(b, b + sizeof b, x);
  return std::string(b, r.ptr);
}

// A cell as a number: the whole cell must be one (surrounding blanks allowed); "nan" is NaN.
std::optional<double> cell_number(const std::string& cell) {
  const char* s = cell.c_str();
  while (*s == ' ' || *s == '\t') ++s;
  if (!*s) return std::nullopt;
  char* end = nullptr;
  const double x = std::strtod(s, &end);
  if (end == s) return std::nullopt;
  while (*end == ' ' || *end == '\t') ++end;
  if (*end) return std::nullopt;
  return x;
}

// "name [unit]" -> ("name", "unit"); a plain name has unit "".
std::pair<std::string, std::string> split_column(const std::string& c) {
  const auto open = c.rfind(" [");
  if (open == std::string::npos || c.empty() || c.back() != ']') return {c, ""};
  return {c.substr(0, open), c.substr(open + 2, c.size() - open - 3)};
}

std::string with_unit(const std::string& name, const std::string& unit) { return unit.empty() ? name : name + " [" + unit + "]"; }

// The unit of a varied key's SI column: that of its first value with a unit; "SI" when every
// value is a plain number (its unit is the case's for that key, which the sweep does not know).
std::string key_unit(const Varied& v) {
  for (const Value& x : v.values) {
    std::string u;
    si_number(x.given, &u);
    if (!u.empty()) return u;
  }
  return "SI";
}

std::size_t inputs_width(const Plan& plan) { return 3 + 2 * plan.spec.vary.size(); }

}  // namespace

Table read_csv(const std::string& path) {
  std::vector<std::vector<std::string>> rows = read_csv_cells(path);
  Table t;
  if (rows.empty()) return t;
  t.columns = rows.front();
  t.rows.assign(rows.begin() + 1, rows.end());
  return t;
}

std::string csv_cell(const std::string& c) {
  if (c.find_first_of(",\"\n\r") == std::string::npos) return c;
  std::string o = "\"";
  for (char ch : c) o += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return o + '"';
}

std::string csv_text(const Table& t) {
  auto put = [](std::string& o, const std::vector<std::string>& cells) {
    for (std::size_t k = 0; k < cells.size(); ++k) {
      if (k) o += ',';
      o += csv_cell(cells[k]);
    }
    o += '\n';
  };
  std::string o;
  put(o, t.columns);
  for (const auto& r : t.rows) put(o, r);
  return o;
}

double si_number(const std::string& given, std::string* unit) {
  if (unit) unit->clear();
  if (const auto plain = cell_number(given)) return std::isfinite(*plain) ? *plain : kNaN;
  const std::optional<Quantity> q = parse_any_quantity(given);
  if (!q) return kNaN;
  if (unit && q->has_unit) *unit = q->dim.si_unit();
  return q->si;
}

std::optional<Table> merge_table(const Plan& plan, const std::vector<bool>& done, const std::string& name) {
  const std::size_t n = plan.points.size();
  std::vector<std::optional<Table>> own(n);
  bool any = false;
  for (std::size_t i = 0; i < n; ++i) {
    const fs::path f = fs::path(plan.point_dir(plan.points[i])) / (name + ".csv");
    if (fs::is_regular_file(f)) own[i] = read_csv(f.string()), any = true;
  }
  if (!any) return std::nullopt;

  Table m;
  m.columns = {"point", "status", "seed"};
  // Each varied value as an SI number, once.
  std::vector<std::vector<std::string>> si(plan.spec.vary.size());
  for (std::size_t k = 0; k < plan.spec.vary.size(); ++k) {
    const Varied& v = plan.spec.vary[k];
    const std::string unit = key_unit(v);
    m.columns.push_back(v.key);
    m.columns.push_back(v.key + " [" + unit + "]");
    for (const Value& x : v.values) {
      std::string u;
      const double number = si_number(x.given, &u);
      si[k].push_back(number_text(u.empty() || u == unit ? number : kNaN));  // a unit of another dimension: not this column's
    }
  }
  // The points' own columns: their union, in order of appearance.
  std::map<std::string, std::size_t> where;
  for (const auto& t : own)
    if (t)
      for (const std::string& c : t->columns)
        if (!where.count(c)) where[c] = m.columns.size(), m.columns.push_back(c);

  for (std::size_t i = 0; i < n; ++i) {
    const Point& p = plan.points[i];
    std::vector<std::string> front = {std::to_string(p.index), done[i] ? "done" : "failed",
                                      std::to_string(p.seed > 0 ? p.seed : p.case_seed)};
    for (std::size_t k = 0; k < plan.spec.vary.size(); ++k) {
      front.push_back(plan.spec.vary[k].values[p.choice[k]].given);
      front.push_back(si[k][p.choice[k]]);
    }
    front.resize(m.columns.size());
    if (!own[i] || own[i]->rows.empty()) {
      m.rows.push_back(front);  // no table from this point: its own cells stay empty
      continue;
    }
    for (const auto& r : own[i]->rows) {
      std::vector<std::string> row = front;
      for (std::size_t c = 0; c < r.size() && c < own[i]->columns.size(); ++c) row[where[own[i]->columns[c]]] = r[c];
      m.rows.push_back(row);
    }
  }
  return m;
}

Table ensemble_table(const Plan& plan, const Table& merged) {
  const std::size_t front = inputs_width(plan);
  const std::size_t ncol = merged.columns.size();
  // Group the done points' rows by combination and row index within the point's table.
  struct Group {
    std::size_t combination = 0, row = 0;
    std::vector<const std::vector<std::string>*> rows;  // one per done seed
    const std::vector<std::string>* any = nullptr;       // a row of the group, for the inputs
  };
  std::map<std::pair<std::size_t, std::size_t>, Group> groups;
  std::map<std::size_t, std::size_t> row_in_point;
  for (const auto& r : merged.rows) {
    const auto idx = static_cast<std::size_t>(std::stoul(r[0]));
    const Point& p = plan.points.at(idx);
    const std::size_t k = row_in_point[idx]++;
    Group& g = groups[{p.combination, k}];
    g.combination = p.combination, g.row = k, g.any = &r;
    if (r[1] == "done") g.rows.push_back(&r);
  }
  // A column of the points is numeric when every non-empty cell of a done row is a number.
  std::vector<bool> numeric(ncol, true);
  for (std::size_t c = front; c < ncol; ++c)
    for (const auto& r : merged.rows)
      if (r[1] == "done" && !r[c].empty() && !cell_number(r[c])) numeric[c] = false;

  Table e;
  for (std::size_t c = 3; c < front; ++c) e.columns.push_back(merged.columns[c]);
  e.columns.push_back("row");
  e.columns.push_back("n");
  for (std::size_t c = front; c < ncol; ++c) {
    if (!numeric[c]) {
      e.columns.push_back(merged.columns[c]);
      continue;
    }
    const auto [name, unit] = split_column(merged.columns[c]);
    for (const char* stat : {"_mean", "_sd", "_se", "_ci95"}) e.columns.push_back(with_unit(name + stat, unit));
  }
  for (const auto& [key, g] : groups) {
    std::vector<std::string> row(g.any->begin() + 3, g.any->begin() + static_cast<long>(front));
    row.push_back(std::to_string(g.row));
    row.push_back(std::to_string(g.rows.size()));
    for (std::size_t c = front; c < ncol; ++c) {
      if (!numeric[c]) {
        // Text is kept when the seeds agree on it.
        std::string common = g.rows.empty() ? "" : (*g.rows[0])[c];
        for (const auto* r : g.rows)
          if ((*r)[c] != common) common.clear();
        row.push_back(common);
        continue;
      }
      std::vector<double> x;
      for (const auto* r : g.rows)
        if (const auto v = cell_number((*r)[c])) x.push_back(*v);
      const Interval in = independent_interval(x);
      const double sd = in.se * std::sqrt(static_cast<double>(x.size()));
      for (double s : {in.mean, sd, in.se, in.ci95}) row.push_back(number_text(s));
    }
    e.rows.push_back(row);
  }
  return e;
}

std::vector<std::string> merge_tables(const Plan& plan, const std::vector<bool>& done) {
  const fs::path out = plan.spec.out_dir;
  std::vector<std::pair<std::string, Table>> h5;
  std::vector<std::string> written;
  for (const std::string& name : plan.spec.tables) {
    const std::optional<Table> m = merge_table(plan, done, name);
    if (!m) continue;
    write_atomically(out / (name + ".csv"), csv_text(*m));
    written.push_back(name + ".csv (" + std::to_string(m->rows.size()) + " rows)");
    h5.emplace_back(name, *m);
    if (plan.spec.seeds > 1) {
      const Table e = ensemble_table(plan, *m);
      write_atomically(out / (name + "_ensemble.csv"), csv_text(e));
      written.push_back(name + "_ensemble.csv (" + std::to_string(e.rows.size()) + " rows)");
      h5.emplace_back(name + "_ensemble", e);
    }
  }
  if (!h5.empty()) {
    std::vector<std::string> keys;
    for (const Varied& v : plan.spec.vary) keys.push_back(v.key);
    write_study_h5((out / "study.h5").string(), h5, keys);
    written.push_back("study.h5");
  }
  return written;
}

void remove_merged_tables(const Plan& plan) {
  const fs::path out = plan.spec.out_dir;
  for (const std::string& name : plan.spec.tables)
    for (const std::string& f : {name + ".csv", name + "_ensemble.csv"}) {
      fs::remove(out / f);
      fs::remove(out / (f + ".part"));
    }
  fs::remove(out / "study.h5");
  fs::remove(out / "study.h5.part");
  remove_earlier_export(out.string());
}

}  // namespace bagdem::study
