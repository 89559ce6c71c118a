// Small tables of numbers as CSV files (sweep.csv, reduced.csv, peaks.csv, compare.csv): a header
// of "name [unit]" entries, then one row of numbers per line (full precision, "nan" for a missing
// figure). Written atomically (a temporary name, then rename), so a reader never sees half a table.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "bagdem/io/results_file.hpp"

namespace bagdem {

// Text columns, when given, follow the numbers (one cell per row and text column; quoted as CSV
// needs). Numbers with `digits` significant digits (17: every digit a double holds).
void write_table_csv(const std::filesystem::path& path, const std::vector<TableColumn>& columns,
                     const std::vector<std::vector<double>>& rows, const std::vector<TableColumn>& text_columns = {},
                     const std::vector<std::vector<std::string>>& text_rows = {}, int digits = 12);

// A cell as RFC 4180 wants it: quoted when it holds a comma, a quote or a line break.
std::string csv_cell(const std::string& value);

// Reads the given columns (by name, any order and extra columns in the file allowed) of a table;
// throws InputError naming the file and the column when one is missing, in another unit (the
// rule of TextTable::column) or a value is not a number.
std::vector<std::vector<double>> read_table_csv(const std::filesystem::path& path, const std::vector<TableColumn>& columns);

// The cells of a CSV file, row by row (RFC 4180: a quoted cell may hold commas, quotes as "" and
// line breaks; CRLF or LF line ends; blank lines skipped). Throws std::runtime_error when the file
// cannot be read.
std::vector<std::vector<std::string>> read_csv_cells(const std::filesystem::path& path);

// Any table as text: names and units from the header, the cells as written (studies add string
// columns such as the varied keys' values). Throws InputError naming the file if it cannot be read
// or a row has another number of cells than the header.
struct TextTable {
  std::string path;  // the file read, for messages
  std::vector<std::string> names, units;
  std::vector<std::vector<std::string>> rows;
  // Index of a column, or names.size() when absent.
  std::size_t find(const std::string& name) const;
  // Index of the column `c.name`, which must be in `c.unit` (a table whose header names another
  // unit holds other numbers: a damaged or foreign file): InputError naming the file, the column,
  // the unit found and the one required. Absent: InputError naming `what` the table is, or
  // names.size() when not `required`.
  std::size_t column(const TableColumn& c, const std::string& what = "the table", bool required = true) const;
};
TextTable read_text_table(const std::filesystem::path& path);

}  // namespace bagdem
