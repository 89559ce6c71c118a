// Tables of numbers as CSV (io/table_csv.hpp).
#include "bagdem/io/table_csv.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "bagdem/error.hpp"
#include "../run/output_files.hpp"

namespace bagdem {

void write_table_csv(const std::filesystem::path& path, const std::vector<TableColumn>& columns,
                     const std::vector<std::vector<double>>& rows) {
  std::ostringstream s;
  s << std::setprecision(12);
  for (std::size_t k = 0; k < columns.size(); ++k) s << (k ? "," : "") << columns[k].name << " [" << columns[k].unit << "]";
  s << "\n";
  for (const std::vector<double>& r : rows) {
    for (std::size_t k = 0; k < r.size(); ++k) {
      s << (k ? "," : "");
      if (std::isnan(r[k])) s << "nan";
      else s << r[k];
    }
    s << "\n";
  }
  write_atomically(path, s.str());
}

std::vector<std::vector<double>> read_table_csv(const std::filesystem::path& path, const std::vector<TableColumn>& columns) {
  std::ifstream f(path);
  if (!f) throw InputError(path.string(), "", "", "cannot be opened");
  std::string line;
  std::getline(f, line);
  std::vector<std::string> header;
  {
    std::stringstream h(line);
    std::string cell;
    while (std::getline(h, cell, ',')) header.push_back(cell.substr(0, cell.find(" [")));
  }
  std::vector<std::size_t> index;
  for (const TableColumn& c : columns) {
    std::size_t k = 0;
    while (k < header.size() && header[k] != c.name) ++k;
    if (k == header.size()) throw InputError(path.string(), c.name, "", "column missing from the table");
    index.push_back(k);
  }
  std::vector<std::vector<double>> rows;
  while (std::getline(f, line)) {
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::stringstream r(line);
    std::string cell;
    while (std::getline(r, cell, ',')) cells.push_back(cell);
    std::vector<double> row;
    for (std::size_t j = 0; j < index.size(); ++j) {
      const std::string& v = index[j] < cells.size() ? cells[index[j]] : std::string();
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

namespace {
// Splits a CSV line; a cell in double quotes may hold commas ("" is a quote).
std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') cells.back() += '"', ++i;
      else if (c == '"') quoted = false;
      else cells.back() += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      cells.emplace_back();
    } else if (c != '\r') {
      cells.back() += c;
    }
  }
  return cells;
}
}  // namespace

TextTable read_text_table(const std::filesystem::path& path) {
  std::ifstream f(path);
  if (!f) throw InputError(path.string(), "", "", "cannot be opened");
  TextTable t;
  std::string line;
  if (!std::getline(f, line)) throw InputError(path.string(), "", "", "is empty: no header");
  for (const std::string& h : split_csv(line)) {
    const std::size_t b = h.rfind(" [");
    const bool unit = b != std::string::npos && h.back() == ']';
    t.names.push_back(unit ? h.substr(0, b) : h);
    t.units.push_back(unit ? h.substr(b + 2, h.size() - b - 3) : "");
  }
  while (std::getline(f, line)) {
    if (line.empty()) continue;
    std::vector<std::string> cells = split_csv(line);
    if (cells.size() != t.names.size())
      throw InputError(path.string(), "", "", "row " + std::to_string(t.rows.size() + 1) + " has " + std::to_string(cells.size()) +
                                                 " cells for " + std::to_string(t.names.size()) + " columns");
    t.rows.push_back(std::move(cells));
  }
  return t;
}

}  // namespace bagdem
