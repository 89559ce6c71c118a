// The restitution of rows that have no other estimate: the drop test of the same contents
// (run/drop_test.hpp), run once per run or sweep and shared by its rows (the contents and the
// launch speed, the case's expected impact speed, are the same for every row).
#pragma once
#include <filesystem>
#include <vector>

#include "bagdem/reduce/reduce.hpp"
#include "bagdem/scene.hpp"

namespace bagdem {

// When a row's e_method is "none", runs the drop test into out_dir (drop.csv, drop_result.csv),
// sets e_drop of every row and chooses e again where it was "none". A drop test that cannot run
// (no room between the contents and the walls, or no rebound) leaves the rows as they are and
// returns why; an empty string otherwise.
std::string drop_where_no_restitution(const Scene& scene, std::vector<ReducedRow>& rows,
                                      const std::filesystem::path& out_dir, bool quiet);

}  // namespace bagdem
