// What `bagdem calibrate` reads (calibrate_targets.hpp): the targets, a key's unit and its bounds.
#include "calibrate_targets.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <toml++/toml.h>

#include "bagdem/error.hpp"
#include "bagdem/io/json.hpp"
#include "bagdem/units.hpp"

namespace bagdem::study {

Target parse_target(const std::string& text) {
  Target t;
  std::istringstream in(text);
  std::string part;
  auto bad = [&](const std::string& why) {
    throw InputError("--target", "", text, why + "; write --target mode=1,reduction_db=14.9 (the mode's number among the elastic modes, the measured peak reduction in dB)");
  };
  while (std::getline(in, part, ',')) {
    const auto eq = part.find('=');
    if (eq == std::string::npos) bad("'" + part + "' is not name=value");
    const std::string name = part.substr(0, eq), value = part.substr(eq + 1);
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || !std::isfinite(v)) bad(name + " = '" + value + "' is not a number");
    if (name == "mode") {
      if (v < 1 || v != std::floor(v)) bad("mode must be a whole number >= 1");
      t.mode = static_cast<int>(v);
    } else if (name == "reduction_db") {
      t.reduction_db = v;
    } else {
      bad("unknown name '" + name + "' (allowed: mode, reduction_db)");
    }
  }
  if (t.mode == 0 || !std::isfinite(t.reduction_db)) bad("both mode and reduction_db are needed");
  return t;
}

Targets read_targets_file(const std::string& path) {
  const std::string hint = " (a CSV of columns mode, reduction_db and at most one case key that sets each target's configuration, "
                           "e.g. bag.balls.mass_ratio)";
  Table t;
  try {
    t = read_csv(path);
  } catch (const std::exception& e) {
    throw InputError(path, "", "", std::string("cannot be read: ") + e.what());
  }
  if (t.columns.empty() || t.rows.empty()) throw InputError(path, "", "", "holds no targets" + hint);
  auto trimmed = [](const std::string& s) { return trim(s.rfind("\xEF\xBB\xBF", 0) == 0 ? s.substr(3) : s); };  // a byte-order mark too
  const std::size_t none = t.columns.size();
  std::size_t c_mode = none, c_db = none, c_config = none;
  Targets out;
  for (std::size_t c = 0; c < t.columns.size(); ++c) {
    const std::string name = trimmed(t.columns[c]);
    if (name.empty()) throw InputError(path, "column " + std::to_string(c + 1), "", "has no name" + hint);
    if ((name == "mode" && c_mode != none) || (name == "reduction_db" && c_db != none))
      throw InputError(path, name, "", "is the header of two columns: which one holds the figures is not clear" + hint);
    if (name == "mode") c_mode = c;
    else if (name == "reduction_db") c_db = c;
    else if (c_config == none) c_config = c, out.config_key = name;
    else throw InputError(path, name, "", "is a second configuration column (" + out.config_key + " is the first): one key sets the configurations" + hint);
  }
  if (c_mode == none || c_db == none) throw InputError(path, c_mode == none ? "mode" : "reduction_db", "", "is not a column" + hint);
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const std::vector<std::string>& row = t.rows[r];
    const std::string where = "row " + std::to_string(r + 1);
    if (row.size() != t.columns.size())
      throw InputError(path, where, "", "has " + std::to_string(row.size()) + " cells where the header has " + std::to_string(t.columns.size()));
    auto number = [&](std::size_t c) {
      const std::string cell = trimmed(row[c]);
      char* end = nullptr;
      const double v = std::strtod(cell.c_str(), &end);
      if (cell.empty() || *end != '\0' || !std::isfinite(v)) throw InputError(path, where + ", " + trimmed(t.columns[c]), row[c], "is not a number");
      return v;
    };
    Target target;
    const double mode = number(c_mode);
    if (mode < 1 || mode != std::floor(mode)) throw InputError(path, where + ", mode", row[c_mode], "must be a whole number >= 1 (the mode's number among the elastic modes)");
    target.mode = static_cast<int>(mode);
    target.reduction_db = number(c_db);
    if (c_config != none) {
      const Value v = parse_value(row[c_config]);
      std::size_t k = 0;
      while (k < out.configs.size() && out.configs[k].toml != v.toml) ++k;
      if (k == out.configs.size()) out.configs.push_back(v);
      target.config = k;
    }
    for (const Target& u : out.list)
      if (u.mode == target.mode && u.config == target.config)
        throw InputError(path, where, row[c_db], "repeats the target of mode " + std::to_string(u.mode) + out.where(u) + ": one figure per mode and configuration");
    out.list.push_back(target);
  }
  return out;
}

bool read_value(const std::string& given, Scale& scale, double& value) {
  const char* text = given.c_str();
  char* end = nullptr;
  value = std::strtod(text, &end);
  if (end == text || !std::isfinite(value)) return false;
  std::string unit(end);
  unit.erase(0, unit.find_first_not_of(" \t"));
  unit.erase(unit.find_last_not_of(" \t") + 1);
  std::string si_unit;
  const double one = si_number(unit.empty() ? "1" : "1 " + unit, &si_unit);
  if (!std::isfinite(one)) return false;
  scale = {unit, si_unit, one};
  return true;
}

std::pair<double, double> read_bounds(const std::string& key, const std::string& bounds, const Scene& s, Scale& scale) {
  if (!bounds.empty()) {
    const std::vector<Value> v = parse_value_list(bounds);
    if (v.size() != 2) throw InputError("--bounds", "", bounds, "needs two values, lo,hi (e.g. --bounds '\"0.05 N\",\"2 N\"')");
    double lo = 0, hi = 0;
    Scale second;
    if (!read_value(v[0].given, scale, lo) || !read_value(v[1].given, second, hi))
      throw InputError("--bounds", "", bounds, "each bound must be a number, with a unit if the key has one");
    if (second.unit != scale.unit)
      throw InputError("--bounds", "", bounds, "the two bounds must be in one unit (" + (scale.unit.empty() ? "none" : scale.unit) + " and " +
                                                     (second.unit.empty() ? "none" : second.unit) + ")");
    if (!(lo < hi)) throw InputError("--bounds", "", bounds, "needs lo < hi");
    return {lo, hi};
  }
  double v = NAN;
  try {
    const toml::table t = toml::parse(s.resolved);
    const toml::node_view<const toml::node> n = t.at_path(key);
    if (const auto str = n.value<std::string>()) {
      if (!read_value(*str, scale, v)) v = NAN;
    } else if (const auto x = n.value<double>()) {
      v = *x;
    }
  } catch (const toml::parse_error&) {
  }
  if (!(v > 0))
    throw InputError("--bounds", key, "", "the case gives " + key + " no positive value to put default bounds around (its value / 4 and x 4): give --bounds lo,hi");
  return {v / 4, v * 4};
}

std::vector<int> evaluated_modes(const Primary& P) {
  const std::vector<double>& f = P.stepped_sine->frequencies;
  if (f.empty()) return {};
  const auto [lo, hi] = std::minmax_element(f.begin(), f.end());
  std::vector<int> modes;
  for (std::size_t d : P.evaluated_modes(*lo, *hi)) modes.push_back(static_cast<int>(P.elastic_mode_number(d)));
  return modes;
}

std::vector<double> target_reductions(const Scene& s, const std::vector<Target>& targets, const std::string& source) {
  if (!s.primary || !s.primary->stepped_sine)
    throw InputError(s.case_file, "excitation.kind", "", "calibrate needs a coupled stepped-sine sweep (a [primary] structure and excitation.kind = \"stepped-sine\"): its peak reduction is what is matched");
  const std::vector<int> modes = evaluated_modes(*s.primary);
  std::vector<double> db;
  for (const Target& t : targets) {
    if (std::find(modes.begin(), modes.end(), t.mode) == modes.end()) {
      std::string have;
      for (int m : modes) have += (have.empty() ? "" : ", ") + std::to_string(m);
      throw InputError(source, "", "mode=" + std::to_string(t.mode),
                       "the case's sweep evaluates the peak of mode" + std::string(modes.size() == 1 ? " " : "s ") + (have.empty() ? "none" : have) +
                           ": set excitation.around_modes to include mode " + std::to_string(t.mode));
    }
    db.push_back(t.reduction_db);
  }
  return db;
}

std::string mae_by_mode(const std::vector<Target>& targets, const std::vector<double>& residual) {
  std::vector<int> modes;
  for (const Target& t : targets)
    if (std::find(modes.begin(), modes.end(), t.mode) == modes.end()) modes.push_back(t.mode);
  std::string js = "[";
  for (std::size_t m = 0; m < modes.size(); ++m) {
    double sum = 0;
    int n = 0;
    for (std::size_t k = 0; k < targets.size(); ++k)
      if (targets[k].mode == modes[m]) sum += std::abs(residual[k]), ++n;
    js += (m ? ", " : "") + std::string("{\"mode\": ") + std::to_string(modes[m]) + ", \"figures\": " + std::to_string(n) +
          ", \"mae_dB\": " + json_number_text(sum / n) + "}";
    if (n > 1) std::printf("  mode %d: mean absolute residual %.2f dB over %d figures\n", modes[m], sum / n, n);
  }
  return js + "]";
}

void require_same_method(const std::string& out, bool maps) {
  namespace fs = std::filesystem;
  if (fs::exists(out) && !fs::is_directory(out)) throw InputError("--out", "", out, "is a file, not a directory");
  if (!fs::is_directory(out)) return;
  const char* again = ": give another --out, or delete it";
  if (fs::exists(fs::path(out) / "map.csv")) throw InputError("--out", "", out, "holds an effective-field map (bagdem characterize's): give another --out");
  if (maps && fs::exists(fs::path(out) / "round-00"))
    throw InputError("--out", "", out, std::string("holds a calibration by coupled DEM (round-00)") + again);
  if (!maps && fs::exists(fs::path(out) / "calibration.json") && read_json(fs::path(out) / "calibration.json").value("method", "") == "maps")
    throw InputError("--out", "", out, std::string("holds a calibration on maps (calibration.json)") + again);
}

}  // namespace bagdem::study
