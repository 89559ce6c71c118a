// The modal table (structure/modal_table.hpp): read, checked, and written from a primary.
#include "bagdem/structure/modal_table.hpp"

#include <cmath>
#include <cstdlib>

#include "bagdem/error.hpp"
#include "bagdem/io/table_csv.hpp"

namespace bagdem {

namespace {

struct Column {
  const char* name;
  const char* unit;
  bool required;
  double ModalRow::*field;
};
const Column kColumns[] = {
    {"frequency", "Hz", true, &ModalRow::frequency},
    {"damping_ratio", "1", true, &ModalRow::damping_ratio},
    {"modal_mass", "kg", true, &ModalRow::modal_mass},
    {"shape_attach", "1", true, &ModalRow::shape_attach},
    {"shape_force", "1", true, &ModalRow::shape_force},
    {"shape_response", "1", true, &ModalRow::shape_response},
    {"slope_attach", "1/m", false, &ModalRow::slope_attach},
    {"curvature_attach", "1/m^2", false, &ModalRow::curvature_attach},
};

}  // namespace

ModalTable read_modal_table(const std::filesystem::path& path) {
  const TextTable t = read_text_table(path);
  const std::string file = path.string();
  ModalTable m;
  std::vector<std::size_t> at;
  for (const Column& c : kColumns) at.push_back(t.column({c.name, c.unit}, "the modal table (docs/case-schema.md, [primary] modal)", c.required));
  m.has_slope = at[6] != t.names.size();
  m.has_curvature = at[7] != t.names.size();
  const std::size_t rigid = t.find("rigid_body");
  if (t.rows.empty()) throw InputError(file, "", "", "has no modes: one row per mode after the header");
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    ModalRow row;
    const std::string where = " (row " + std::to_string(r + 1) + ")";
    for (std::size_t c = 0; c < std::size(kColumns); ++c) {
      if (at[c] == t.names.size()) continue;
      const std::string& v = t.rows[r][at[c]];
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != '\0' || !std::isfinite(x)) throw InputError(file, kColumns[c].name, v, "must be a finite number" + where);
      row.*kColumns[c].field = x;
    }
    if (rigid != t.names.size()) {
      const std::string& v = t.rows[r][rigid];
      if (v != "0" && v != "1") throw InputError(file, "rigid_body", v, "must be 0 or 1" + where);
      row.rigid_body = v == "1";
    }
    if (!(row.frequency > 0)) throw InputError(file, "frequency", t.rows[r][at[0]], "must be > 0 Hz (give a rigid-body mode its suspension's frequency)" + where);
    if (!(row.damping_ratio >= 0 && row.damping_ratio < 1)) throw InputError(file, "damping_ratio", t.rows[r][at[1]], "must be in [0, 1)" + where);
    if (!(row.modal_mass > 0)) throw InputError(file, "modal_mass", t.rows[r][at[2]], "must be > 0 kg" + where);
    if (r > 0 && row.frequency < m.rows.back().frequency)
      throw InputError(file, "frequency", t.rows[r][at[0]], "must not decrease from row to row (modes in frequency order)" + where);
    m.rows.push_back(row);
  }
  return m;
}

void write_modal_table(const std::filesystem::path& path, const Primary& p) {
  std::vector<TableColumn> columns;
  for (const Column& c : kColumns) columns.push_back({c.name, c.unit});
  columns.push_back({"rigid_body", "1"});
  std::vector<std::vector<double>> rows;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const auto K = static_cast<Eigen::Index>(k);
    // The structure's own mass matrix without the cavity's (M = I for the beams, M_p for sdof).
    const double m = p.mass(K, K) - p.cavity_mass * p.at_cavity[K] * p.at_cavity[K];
    rows.push_back({p.natural_frequency[k], p.damping_ratio[k], m, p.at_cavity[K], p.at_force[K], p.at_response[K],
                    p.slope_at_cavity[K], 2 * p.load_fit(K, 2), p.rigid_body[k] ? 1.0 : 0.0});
  }
  write_table_csv(path, columns, rows, {}, {}, 17);
}

}  // namespace bagdem
