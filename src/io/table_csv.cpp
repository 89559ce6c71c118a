// Tables of numbers as CSV (io/table_csv.hpp).
#include "bagdem/io/table_csv.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "bagdem/error.hpp"
#include "bagdem/io/atomic_file.hpp"

namespace bagdem {

std::string csv_cell(const std::string& v) {
  if (v.find_first_of(",\"\r\n") == std::string::npos) return v;
  std::string q = "\"";
  for (char c : v) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

void write_table_csv(const std::filesystem::path& path, const std::vector<TableColumn>& columns,
                     const std::vector<std::vector<double>>& rows, const std::vector<TableColumn>& text_columns,
                     const std::vector<std::vector<std::string>>& text_rows, int digits) {
  std::ostringstream s;
  s << std::setprecision(digits);
  for (std::size_t k = 0; k < columns.size(); ++k) s << (k ? "," : "") << columns[k].name << " [" << columns[k].unit << "]";
  for (const TableColumn& c : text_columns) s << "," << c.name << " [" << c.unit << "]";
  s << "\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::vector<double>& r = rows[i];
    for (std::size_t k = 0; k < r.size(); ++k) {
      s << (k ? "," : "");
      if (std::isnan(r[k])) s << "nan";
      else s << r[k];
    }
    if (!text_columns.empty())
      for (const std::string& cell : text_rows.at(i)) s << "," << csv_cell(cell);
    s << "\n";
  }
  write_atomically(path, s.str());
}

std::vector<std::vector<double>> read_table_csv(const std::filesystem::path& path, const std::vector<TableColumn>& columns) {
  const TextTable t = read_text_table(path);
  std::vector<std::size_t> index;
  for (const TableColumn& c : columns) index.push_back(t.column(c));
  std::vector<std::vector<double>> rows;
  for (const std::vector<std::string>& cells : t.rows) {
    std::vector<double> row;
    for (std::size_t j = 0; j < index.size(); ++j) {
      const std::string& v = cells[index[j]];
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != '\0') throw InputError(path.string(), columns[j].name, v, "must be a number (row " + std::to_string(rows.size() + 1) + ")");
      row.push_back(x);
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

std::size_t TextTable::find(const std::string& name) const {
  std::size_t k = 0;
  while (k < names.size() && names[k] != name) ++k;
  return k;
}

std::size_t TextTable::column(const TableColumn& c, const std::string& what, bool required) const {
  const std::size_t k = find(c.name);
  if (k == names.size()) {
    if (required) throw InputError(path, std::string(c.name) + " [" + c.unit + "]", "", "column missing from " + what);
    return k;
  }
  if (units[k] != c.unit) throw InputError(path, c.name, "[" + units[k] + "]", std::string("must be in [") + c.unit + "]");
  return k;
}

std::vector<std::vector<std::string>> read_csv_cells(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot read " + path.string());
  std::ostringstream ss;
  ss << f.rdbuf();
  const std::string text = ss.str();
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string cell;
  bool quoted = false, any = false;
  for (std::size_t k = 0; k < text.size(); ++k) {
    const char c = text[k];
    if (quoted) {
      if (c == '"' && k + 1 < text.size() && text[k + 1] == '"') cell += '"', ++k;
      else if (c == '"') quoted = false;
      else cell += c;
      continue;
    }
    if (c == '"') {
      quoted = any = true;
    } else if (c == ',') {
      row.push_back(cell), cell.clear(), any = true;
    } else if (c == '\n' || c == '\r') {
      if (c == '\r' && k + 1 < text.size() && text[k + 1] == '\n') ++k;
      if (any || !cell.empty()) row.push_back(cell), rows.push_back(row);
      row.clear(), cell.clear(), any = false;
    } else {
      cell += c, any = true;
    }
  }
  if (any || !cell.empty()) row.push_back(cell), rows.push_back(row);
  return rows;
}

TextTable read_text_table(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) throw InputError(path.string(), "", "", "cannot be opened");
  std::vector<std::vector<std::string>> cells = read_csv_cells(path);
  if (cells.empty()) throw InputError(path.string(), "", "", "is empty: no header");
  TextTable t;
  t.path = path.string();
  if (!cells.front().empty() && cells.front()[0].rfind("\xEF\xBB\xBF", 0) == 0) cells.front()[0].erase(0, 3);  // a byte-order mark
  for (const std::string& h : cells.front()) {
    const std::size_t b = h.rfind(" [");
    const bool unit = b != std::string::npos && h.back() == ']';
    t.names.push_back(unit ? h.substr(0, b) : h);
    t.units.push_back(unit ? h.substr(b + 2, h.size() - b - 3) : "");
  }
  for (std::size_t r = 1; r < cells.size(); ++r) {
    if (cells[r].size() != t.names.size())
      throw InputError(path.string(), "", "", "row " + std::to_string(r) + " has " + std::to_string(cells[r].size()) +
                                                 " cells for " + std::to_string(t.names.size()) + " columns");
    t.rows.push_back(std::move(cells[r]));
  }
  return t;
}

}  // namespace bagdem
