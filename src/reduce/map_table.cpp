// map.csv, written and read through one table of columns (reduce/map_table.hpp).
#include "bagdem/reduce/map_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "bagdem/error.hpp"
#include "bagdem/io/table_csv.hpp"

namespace bagdem {

namespace {

const MapFigure kFigures[] = {
    {"gamma_measured", "gamma_measured_ci95", "1", &MapCell::gamma_measured},
    {"M_eff", "M_eff_ci95", "kg", &MapCell::M_eff},
    {"C_eff", "C_eff_ci95", "N s/m", &MapCell::C_eff},
    {"Cb_over_Mbw", "Cb_over_Mbw_ci95", "1", &MapCell::Cb_over_Mbw},
    {"loss_factor", "loss_factor_ci95", "1", &MapCell::loss_factor},
    {"M_eff_ratio", "M_eff_ratio_ci95", "1", &MapCell::M_eff_ratio},
    {"energy_per_cycle", "energy_per_cycle_ci95", "J", &MapCell::energy_per_cycle},
    {"e", "e_ci95", "1", &MapCell::e},
};

// The grid's columns and the counts, by where a cell keeps them.
const TableColumn kGamma{"gamma", "1"}, kFrequency{"frequency", "Hz"}, kAmplitude{"amplitude", "m"};
const TableColumn kStarts{"starts", "1"}, kSteady{"steady_starts", "1"}, kEStarts{"e_starts", "1"};
const char* const kEMethod = "e_method";

}  // namespace

std::span<const MapFigure> map_figures() { return kFigures; }

void write_map_csv(const std::filesystem::path& path, const std::vector<MapCell>& cells) {
  std::vector<TableColumn> columns = {kGamma, kFrequency, kAmplitude, kStarts, kSteady};
  for (const MapFigure& f : kFigures) {
    columns.push_back({f.name, f.unit});
    columns.push_back({f.ci95, f.unit});
  }
  columns.push_back(kEStarts);
  std::vector<std::vector<double>> rows;
  std::vector<std::vector<std::string>> methods;
  for (const MapCell& c : cells) {
    std::vector<double> r = {c.gamma, c.frequency, c.amplitude, double(c.starts), double(c.steady)};
    for (const MapFigure& f : kFigures) r.insert(r.end(), {(c.*f.field).mean, (c.*f.field).ci95});
    r.push_back(double(c.e_starts));
    rows.push_back(r);
    methods.push_back({c.e_method});
  }
  write_table_csv(path, columns, rows, {{kEMethod, "text"}}, methods);
}

std::vector<MapCell> read_map_csv(const std::filesystem::path& path, std::initializer_list<MapField> needed) {
  const TextTable t = read_text_table(path);
  std::vector<MapCell> cells(t.rows.size());
  const std::string what = "the map (is it a map.csv of bagdem characterize?)";
  // A column's numbers into each cell (absent and not required: left as they are). An axis is a
  // number > 0; a figure a finite number or nan.
  auto read = [&](const TableColumn& c, bool required, bool axis, auto&& store) {
    const std::size_t k = t.column(c, what, required);
    if (k == t.names.size()) return false;
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
      const std::string& cell = t.rows[r][k];
      char* end = nullptr;
      const double x = cell.empty() || cell == "nan" ? std::nan("") : std::strtod(cell.c_str(), &end);
      if ((end && *end != '\0') || std::isinf(x) || (axis && !(std::isfinite(x) && x > 0)))
        throw InputError(path.string(), c.name, "'" + cell + "'",
                         std::string(axis ? "must be a number > 0" : "must be a finite number or nan") + " (row " + std::to_string(r + 1) + ")");
      store(cells[r], x);
    }
    return true;
  };
  read(kGamma, true, true, [](MapCell& m, double x) { m.gamma = x; });
  read(kFrequency, true, true, [](MapCell& m, double x) { m.frequency = x; });
  read(kAmplitude, false, true, [](MapCell& m, double x) { m.amplitude = x; });
  auto count = [](std::size_t MapCell::*field) {
    return [field](MapCell& m, double x) { m.*field = std::isfinite(x) && x >= 0 ? static_cast<std::size_t>(x) : 0; };
  };
  read(kStarts, false, false, count(&MapCell::starts));
  read(kSteady, false, false, count(&MapCell::steady));
  read(kEStarts, false, false, count(&MapCell::e_starts));
  for (const MapFigure& f : kFigures) {
    const bool required = std::find(needed.begin(), needed.end(), f.field) != needed.end();
    const MapField field = f.field;
    if (!read({f.name, f.unit}, required, false, [field](MapCell& m, double x) { (m.*field).mean = x; }))
      for (MapCell& m : cells) (m.*field).mean = std::nan("");
    if (!read({f.ci95, f.unit}, required, false, [field](MapCell& m, double x) { (m.*field).ci95 = x; }))
      for (MapCell& m : cells) (m.*field).ci95 = std::nan("");
  }
  if (const std::size_t k = t.find(kEMethod); k < t.names.size())
    for (std::size_t r = 0; r < t.rows.size(); ++r) cells[r].e_method = t.rows[r][k];
  return cells;
}

}  // namespace bagdem
