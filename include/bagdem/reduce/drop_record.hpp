// The drop test's record, drop_result.toml beside drop_result.csv (bagdem drop, and a run's own drop
// test): the case the test was run with, as resolved, and drop_result.csv's fingerprint. reduce
// attaches a drop test's e only to a run of the same case, and never an edited figure.
#pragma once
#include <filesystem>

#include "bagdem/scene.hpp"

namespace bagdem {

// Writes the record of `csv`: scene.resolved and the fingerprint of `table`, the table's bytes (written
// first, under a temporary name, and renamed to csv after the record).
void write_drop_record(const std::filesystem::path& table, const std::filesystem::path& csv, const Scene& scene);

// Refuses (InputError) a drop_result.csv whose record says it is of another case than `scene`
// (output.skip_cycles may differ, as for results.h5) or that changed since it was written. Returns
// false when there is no record (a drop test of a bagdem before the record: used unchecked).
bool check_drop_record(const std::filesystem::path& csv, const Scene& scene);

}  // namespace bagdem
