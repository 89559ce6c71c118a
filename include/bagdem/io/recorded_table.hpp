// A table's CSV checked against the table a complete results.h5 recorded (io/results_file.hpp).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "bagdem/io/results_file.hpp"  // TableColumn

namespace bagdem {

// A table's CSV (`csv`, its `columns`) against the table /<group> of the complete results file `h5`
// that recorded it: every number to the CSV's 12 digits, the same rows. InputError naming the CSV,
// the column and the first row that differs (a table edited by hand, damaged, or another run's).
void require_recorded_table(const std::filesystem::path& csv, const std::filesystem::path& h5, const std::string& group,
                            const std::vector<TableColumn>& columns);

}  // namespace bagdem
