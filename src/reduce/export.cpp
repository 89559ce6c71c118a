// `bagdem export` (reduce/export.hpp).
#include "bagdem/reduce/export.hpp"
#include "bagdem/reduce/reduce.hpp"

#include <hdf5.h>

#include <algorithm>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "bagdem/error.hpp"
#include "bagdem/io/atomic_file.hpp"
#include "bagdem/io/json.hpp"
#include "bagdem/io/recorded_table.hpp"
#include "bagdem/io/table_csv.hpp"
#include "../io/h5.hpp"

namespace bagdem {
namespace fs = std::filesystem;

const std::vector<ExportColumn>& export_columns() {
  static const std::vector<ExportColumn> c = {
      {"frequency", "drive frequency"},
      {"cavity_amplitude", "amplitude |X| of the cavity's displacement along the excitation"},
      {"gamma", "dimensionless acceleration Gamma = |X| w^2 / g"},
      {"clearance_ratio", "d/|X|: the contents' free travel along the excitation when settled over |X|"},
      {"bag_mass", "the bag's real mass M_b (balls and film)"},
      {"mass_ratio", "M_b / M_p (the structure's own mass); NaN under prescribed motion"},
      {"balls", "number of balls"},
      {"ball_diameter", "mean ball diameter"},
      {"M_eff", "effective mass: F_hat = (w^2 M_eff - i w C_eff) X_hat, first harmonic over whole steady cycles"},
      {"M_eff_se", "standard error of M_eff (batch means over the correlated cycles, or over the starts of an ensemble)"},
      {"M_eff_ci95", "half-width of M_eff's 95% interval"},
      {"M_eff_ratio", "M_eff / M_b"},
      {"C_eff", "effective viscous damping C_b"},
      {"C_eff_se", "standard error of C_eff"},
      {"C_eff_ci95", "half-width of C_eff's 95% interval"},
      {"Cb_over_Mbw", "C_b / (M_b w) with the real bag mass (the study's Eq. 19a quantity)"},
      {"Cb_over_Mbw_se", "its standard error"},
      {"Cb_over_Mbw_ci95", "half-width of its 95% interval"},
      {"loss_factor", "C_eff / (M_eff w)"},
      {"energy_per_cycle", "energy the contents dissipate per cycle, pi C_eff w |X|^2"},
      {"energy_per_cycle_se", "its standard error"},
      {"energy_per_cycle_ci95", "half-width of its 95% interval"},
      {"dissipated_per_cycle", "energy the contents' contacts dissipated per cycle by the tallies (NaN without output.energy)"},
      {"energy_balance", "relative misclosure of the energy balance over the window (NaN when unknown)"},
      {"impact_phase", "phi: the cavity's phase at the impacts (x = |X| cos theta, phi = theta mod pi)"},
      {"impacts_per_cycle", "impacts on the walls per cycle"},
      {"e_impact", "restitution of the bag from each impact between free flights: -v_after/v_before of its centre of mass (mean of at least 5, else NaN)"},
      {"e_impact_sd", "standard deviation of the per-impact restitution"},
      {"e_eq19a", "restitution inverted from C_b/(M_b w) and phi with the study's Eq. (19a)"},
      {"e_drop", "restitution from the drop test of the same contents, NaN if not run"},
      {"e", "the restitution to use: the first available of e_impact, e_eq19a, e_drop"},
      {"e_se", "its standard error"},
      {"e_ci95", "half-width of its 95% interval"},
      {"e_method", "which estimator gave e: impact, eq19a, drop or none"},
      {"peak_impact_force", "mean over impacts of the peak wall force (resolved to the sample interval)"},
      {"impact_duration", "mean impact duration (to about one sample interval)"},
      {"response_amplitude", "|Y| at the structure's response point (coupled runs)"},
      {"cycles", "steady cycles reduced"},
      {"steady", "1 when the window is steady (settled, energy balance within 1%, dissipation not negative); 0 flags the row"}};
  return c;
}

namespace {

std::string json_number(const std::string& cell) {
  char* end = nullptr;
  const double v = std::strtod(cell.c_str(), &end);
  if (cell.empty() || *end != '\0' || !std::isfinite(v)) return "null";
  std::ostringstream o;
  o << std::setprecision(17) << v;
  return o.str();
}

// A number as bagdem's tables write it: decimal (no spaces, no hexadecimal), nan or inf, and
// representable (no overflow or underflow).
bool is_written_number(const std::string& cell) {
  if (cell.empty() || cell.find_first_of(" \t\r\nxXpP") != std::string::npos) return false;
  char* end = nullptr;
  errno = 0;
  std::strtod(cell.c_str(), &end);
  return *end == '\0' && errno != ERANGE;
}

bool numeric_column(const TextTable& t, std::size_t k) {
  for (const auto& r : t.rows) {
    char* end = nullptr;
    std::strtod(r[k].c_str(), &end);
    if (r[k].empty() || *end != '\0') return false;
  }
  return true;
}

// export.h5: group /export, a 1-D dataset per column (numbers float64, text as strings), each
// with its "unit" and "description".
void write_h5(const fs::path& path, const TextTable& t, const std::vector<std::size_t>& cols, const std::vector<std::string>& descriptions) {
  const fs::path tmp = path.string() + ".part";
  const h5::Check ok = h5::Check::with_prefix("export file " + tmp.string() + ": ");
  {
    h5::H5 file(ok(H5Fcreate(tmp.string().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "cannot create it"), H5Fclose);
    h5::H5 g = h5::create_group(file, "export", ok, true);
    for (std::size_t j = 0; j < cols.size(); ++j) {
      const std::size_t k = cols[j];
      std::vector<std::string> cells;
      for (const auto& r : t.rows) cells.push_back(r[k]);
      h5::H5 ds;
      if (numeric_column(t, k)) {
        std::vector<double> v;
        for (const auto& c : cells) v.push_back(std::strtod(c.c_str(), nullptr));
        ds = h5::write_dataset(g, t.names[k], {v.size()}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data(), t.units[k], ok);
      } else {
        ds = h5::write_strings(g, t.names[k], cells, ok);
        h5::write_attribute(ds, "unit", t.units[k], ok);
      }
      h5::write_attribute(ds, "description", descriptions[j], ok);
    }
    h5::close_file(file, ok, "cannot write it");
  }
  fs::rename(tmp, path);
}

// Every reduced table bagdem writes has each of the known columns (appended to `cols`, their
// descriptions to `descriptions`). Every column with a unit holds numbers as bagdem writes them
// (decimal, nan or inf; a study's varied keys in SI too), the text ones aside: a table without one,
// or with another cell there (a header line repeated, a cut or edited cell), is damaged and
// refused rather than exported as text.
void check_reduced_table(const fs::path& in, const TextTable& t, const std::vector<ExportColumn>& known, std::vector<std::size_t>& cols,
                         std::vector<std::string>& descriptions) {
  for (const ExportColumn& c : known) {
    const std::size_t k = t.find(c.name);
    if (k == t.names.size())
      throw InputError(in.string(), c.name, "", "is not a column: the table is damaged or not one bagdem wrote (run or reduce again)");
    cols.push_back(k), descriptions.push_back(c.description);
  }
  // A study's row of a point that did not finish has no figures: said as such, not as damage.
  if (const std::size_t status = t.find("status"); status < t.names.size())
    for (std::size_t r = 0; r < t.rows.size(); ++r)
      if (t.rows[r][status] != "done")
        throw InputError(in.string(), "row " + std::to_string(r + 1) + ", status", t.rows[r][status],
                         "is a point that did not finish: its figures are not there. Run the study again (its point's log.txt says "
                         "why it failed), then export");
  for (std::size_t k = 0; k < t.names.size(); ++k) {
    if (t.units[k].empty() || t.units[k] == "text") continue;
    for (std::size_t r = 0; r < t.rows.size(); ++r)
      if (!is_written_number(t.rows[r][k]))
        throw InputError(in.string(), "row " + std::to_string(r + 1) + ", " + t.names[k], t.rows[r][k],
                         "is not a number: the table is damaged (run or reduce again)");
  }
}

// Only an earlier export is replaced: a CSV table that is not a run's or a study's own, export.json's
// head, an HDF5 file with /export.
bool earlier_export(const fs::path& path, const std::string& head) {
  // A run's or a study's own tables are never an export, whatever their head.
  const std::string name = path.filename().string();
  if (name.find("_ensemble.") != std::string::npos) return false;
  for (const char* own : {"reduced", "sweep", "peaks", "compare", "bare_curve", "drop", "drop_result", "map", "design", "calibrate", "trade"})
    if (name == std::string(own) + ".csv" || name == std::string(own) + ".json") return false;
  // An export's table: the reduced quantities (M_eff, Cb_over_Mbw, ...) without a run's raw columns.
  // A table of another kind whose head has units ("frequency [Hz],amplitude [m]") is not one.
  // The whole first line (a study's inputs come first: the head's first bytes may not reach them).
  if (path.extension() == ".csv") {
    std::ifstream in(path, std::ios::binary);
    std::string first;
    std::getline(in, first);
    const std::string line = "," + first;
    return is_bagdem_table_head(first) && line.find(",M_eff [") != std::string::npos && line.find(",Cb_over_Mbw [") != std::string::npos &&
           line.find(",displacement_re [") == std::string::npos;
  }
  if (path.extension() == ".json") return head.rfind("{\n  \"source\": ", 0) == 0;
  if (head.rfind("\x89HDF\r\n\x1a\n", 0) != 0) return false;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(path.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const bool has = f >= 0 && H5Lexists(f, "export", H5P_DEFAULT) > 0;
  if (f >= 0) H5Fclose(f);
  return has;
}

// reduced.csv as its run or study recorded it (results.h5's or study.h5's /reduced), where there is
// that record: an edited table is refused, not exported. The reduced figures only: not a study's
// inputs, not the restitution's columns (reduce attaches a drop test's e after the run).
void require_as_recorded(const fs::path& dir, const fs::path& csv, const TextTable& t) {
  for (const char* name : {"results.h5", "study.h5"}) {
    const fs::path h5 = dir / name;
    if (!fs::exists(h5)) continue;
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    std::vector<TableColumn> cols;
    {
      const h5::H5 f(H5Fopen(h5.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
      if (f < 0) throw InputError(h5.string(), "", "", "cannot be read: a damaged record of " + csv.string());
      const bool has = H5Lexists(f, "/reduced", H5P_DEFAULT) > 0;
      for (std::size_t k = 0; has && k < t.names.size(); ++k) {
        const std::string& n = t.names[k];
        if (t.units[k].empty() || t.units[k] == "text" ||
            std::any_of(std::begin(kRestitutionColumns), std::end(kRestitutionColumns), [&](const char* e) { return n == e; }))
          continue;
        // A study's inputs (case keys, given and in SI under one name) are not figures of the run.
        if (n.find('/') == std::string::npos && n.find('.') == std::string::npos && H5Lexists(f, ("/reduced/" + n).c_str(), H5P_DEFAULT) > 0)
          cols.push_back({t.names[k].c_str(), t.units[k].c_str()});
      }
    }
    if (!cols.empty()) require_recorded_table(csv, h5, "reduced", cols);
    return;
  }
}

}  // namespace

void remove_earlier_export(const std::string& dir) {
  for (const char* f : {"export.csv", "export.json", "export.h5"}) {
    const fs::path path = fs::path(dir) / f;
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) continue;
    if (earlier_export(path, file_head(path)) && fs::remove(path, ec))
      std::fprintf(stderr, "removed %s: an export of the earlier tables (bagdem export makes it again)\n", path.c_str());
  }
}

std::vector<std::string> export_reduced(const std::string& dir, const std::string& to, const std::vector<std::string>& formats) {
  const fs::path in = fs::path(dir) / "reduced.csv";
  if (!fs::exists(in)) throw InputError(in.string(), "", "", "is missing: run (or reduce) the case or the study first");
  TextTable t = read_text_table(in);
  // A study's table holds each varied key twice, as written ("0.3 N") and in SI ("... [kg m/s^2]"):
  // one name in the exported files, so the text is "<key> (given)", as study.h5's given/<key>.
  for (std::size_t k = 0; k < t.names.size(); ++k)
    if (t.units[k].empty() && std::count(t.names.begin(), t.names.end(), t.names[k]) > 1) t.names[k] += " (given)";
  for (std::size_t k = 0; k < t.names.size(); ++k)
    if (std::count(t.names.begin(), t.names.end(), t.names[k]) > 1)
      throw InputError(in.string(), t.names[k], "", "names two columns: a damaged table (export writes one column per name)");
  // The study's inputs first (every column that is not a reduced quantity), then the reduced ones.
  std::vector<std::size_t> cols;
  std::vector<std::string> descriptions;
  const std::vector<ExportColumn>& known = export_columns();
  auto is_known = [&](const std::string& name) {
    for (const ExportColumn& c : known)
      if (name == c.name) return true;
    return false;
  };
  static const char* kRaw[] = {"displacement_re", "displacement_im", "force_re", "force_im", "e_impact_count", "max_impact_force"};
  for (std::size_t k = 0; k < t.names.size(); ++k) {
    bool raw = false;
    for (const char* r : kRaw) raw = raw || t.names[k] == r;
    if (!is_known(t.names[k]) && !raw) cols.push_back(k), descriptions.push_back("study input");
  }
  check_reduced_table(in, t, known, cols, descriptions);
  require_as_recorded(dir, in, t);
  const fs::path base = to.empty() ? fs::path(dir) / "export" : fs::path(to);
  std::error_code ec;
  for (fs::path up = base.parent_path(); !up.empty() && up != up.parent_path(); up = up.parent_path())
    if (fs::exists(up, ec) && !fs::is_directory(up, ec))
      throw InputError(to.empty() ? "out" : "--to", "", base.string(), "lies under " + up.string() + ", which is a file, not a directory: give another path");
  for (const std::string& f : formats)
    check_output_target(base.string() + "." + f, to.empty() ? "out" : "--to", earlier_export, "an export bagdem wrote (export." + f + ")");
  if (!base.parent_path().empty()) fs::create_directories(base.parent_path());
  std::vector<std::string> written;
  for (const std::string& f : formats) {
    const fs::path path = base.string() + "." + f;
    if (f == "csv") {
      std::ostringstream o;
      for (std::size_t j = 0; j < cols.size(); ++j) o << (j ? "," : "") << t.names[cols[j]] << " [" << t.units[cols[j]] << "]";
      o << "\n";
      for (const auto& r : t.rows) {
        for (std::size_t j = 0; j < cols.size(); ++j) {
          const std::string& c = r[cols[j]];
          const bool quote = c.find(',') != std::string::npos;
          o << (j ? "," : "") << (quote ? "\"" : "") << c << (quote ? "\"" : "");
        }
        o << "\n";
      }
      write_atomically(path, o.str());
    } else if (f == "json") {
      std::ostringstream o;
      o << "{\n  \"source\": \"" << json_escape(in.string()) << "\",\n  \"columns\": [\n";
      for (std::size_t j = 0; j < cols.size(); ++j)
        o << "    {\"name\": \"" << json_escape(t.names[cols[j]]) << "\", \"unit\": \"" << json_escape(t.units[cols[j]])
          << "\", \"description\": \"" << json_escape(descriptions[j]) << "\"}" << (j + 1 < cols.size() ? ",\n" : "\n");
      o << "  ],\n  \"rows\": [\n";
      std::vector<bool> numeric;
      for (std::size_t k : cols) numeric.push_back(numeric_column(t, k));
      for (std::size_t i = 0; i < t.rows.size(); ++i) {
        o << "    {";
        for (std::size_t j = 0; j < cols.size(); ++j) {
          const std::string& c = t.rows[i][cols[j]];
          o << (j ? ", " : "") << "\"" << json_escape(t.names[cols[j]]) << "\": ";
          if (numeric[j]) o << json_number(c);
          else o << '"' << json_escape(c) << '"';
        }
        o << "}" << (i + 1 < t.rows.size() ? ",\n" : "\n");
      }
      o << "  ]\n}\n";
      write_atomically(path, o.str());
    } else if (f == "h5") {
      write_h5(path, t, cols, descriptions);
    } else {
      throw InputError(dir, "--formats", f, "must be csv, json or h5");
    }
    written.push_back(path.string());
  }
  return written;
}

}  // namespace bagdem
