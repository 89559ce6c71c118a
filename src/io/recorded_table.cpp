// A table's CSV checked against its record (io/recorded_table.hpp).
#include "bagdem/io/recorded_table.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>

#include "bagdem/error.hpp"
#include "bagdem/io/table_csv.hpp"
#include "h5.hpp"

namespace bagdem {

using h5::H5;

void require_recorded_table(const std::filesystem::path& csv, const std::filesystem::path& h5, const std::string& group,
                            const std::vector<TableColumn>& columns) {
  const std::vector<std::vector<double>> rows = read_table_csv(csv, columns);
  if (!std::filesystem::exists(h5)) throw InputError(h5.string(), "", "", "is missing: the run's record (run it again)");
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const h5::Check ok([&](const std::string& what) { throw InputError(h5.string(), "/" + group, "", what + ": not the record of a complete run"); });
  const H5 file(ok(H5Fopen(h5.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "cannot be read"), H5Fclose);
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const std::string name = "/" + group + "/" + columns[c].name;
    const H5 ds(ok(H5Dopen2(file, name.c_str(), H5P_DEFAULT), "has no " + name), H5Dclose);
    const std::vector<double> recorded = h5::read_doubles(ds, name, ok);
    std::size_t r = 0;  // the first row that differs
    while (r < rows.size() && r < recorded.size() &&
           (rows[r][c] == recorded[r] || std::abs(rows[r][c] - recorded[r]) <= 1e-11 * std::max(std::abs(rows[r][c]), std::abs(recorded[r])) ||
            (std::isnan(rows[r][c]) && std::isnan(recorded[r]))))
      ++r;
    if (r < rows.size() || recorded.size() != rows.size())
      throw InputError(csv.string(), columns[c].name, "",
                       recorded.size() != rows.size()
                           ? "has " + std::to_string(rows.size()) + " rows where " + h5.filename().string() + "'s /" + group + " has " + std::to_string(recorded.size()) +
                                 ": not this run's table (run it again)"
                           : "differs from " + h5.filename().string() + "'s /" + group + " at row " + std::to_string(r + 1) +
                                 ": the table was edited or is another run's (run it again)");
  }
}

}  // namespace bagdem
