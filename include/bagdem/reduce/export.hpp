// `bagdem export`: the reduced-parameter table of a run or a study for FE and continuum codes.
//
// Input: DIR/reduced.csv (a run's, one row per driven frequency; or a study's merged table, whose
// extra columns are the study's inputs: point, status, seed, each varied key as written and as an SI
// number "<key> [unit]"). Output, all with the same columns (docs/outputs.md lists them):
//   <to>.csv   header "name [unit]", one row per frequency (and point);
//   <to>.json  {"columns": [{"name", "unit", "description"}...], "rows": [{name: value}...]}
//              (numbers as JSON numbers, null for NaN; the inputs' strings as strings);
//   <to>.h5    /export/<name>: float64 datasets with a "unit" and a "description" attribute, string
//              datasets for the text inputs.
// Every file is written to a temporary name and renamed.
#pragma once
#include <string>
#include <vector>

namespace bagdem {

// The exported columns of reduced.csv, in order, with their meaning.
struct ExportColumn {
  const char* name;
  const char* description;
};
const std::vector<ExportColumn>& export_columns();

// Writes the formats asked for ("csv", "json", "h5") at `to` (default dir/export) and returns the
// paths written. Throws InputError naming the file when dir/reduced.csv is missing or malformed.
std::vector<std::string> export_reduced(const std::string& dir, const std::string& to, const std::vector<std::string>& formats);

// Removes dir/export.csv, .json and .h5 where they are an earlier export (never a file of the
// user's), and says so: a study that runs again makes new tables, and an export of the earlier
// ones would be left beside them, stale.
void remove_earlier_export(const std::string& dir);

}  // namespace bagdem
