// OUT/study.h5 (study/study.hpp, write_study_h5): the merged tables as HDF5, a group per table and
// a 1-D dataset per column, in column order (link creation order is tracked). Numbers are float64
// with a "unit" attribute (a variable-length UTF-8 string, as in results.h5); empty cells are NaN.
// Text columns, and the varied values as written (under <table>/given/), are variable-length
// UTF-8 strings. The file is written as study.h5.part and renamed.
#include <hdf5.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <set>
#include <stdexcept>

#include "../io/h5.hpp"
#include "bagdem/study/study.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;
using h5::H5;

namespace {

std::optional<double> as_number(const std::string& cell) {
  if (cell.empty()) return std::numeric_limits<double>::quiet_NaN();
  char* end = nullptr;
  const double x = std::strtod(cell.c_str(), &end);
  if (end == cell.c_str() || *end) return std::nullopt;
  return x;
}

// A dataset name: the column's name without its unit; '/' would make a path.
std::string dataset_name(std::string name) {
  for (char& c : name)
    if (c == '/') c = '_';
  return name;
}

}  // namespace

void write_study_h5(const std::string& path, const std::vector<std::pair<std::string, Table>>& tables,
                    const std::vector<std::string>& given_keys) {
  const std::string tmp = path + ".part";
  const std::set<std::string> given(given_keys.begin(), given_keys.end());
  const h5::Check ok = h5::Check::with_prefix("study.h5: ");
  {
    H5 file(ok(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "cannot create " + tmp), H5Fclose);
    for (const auto& [name, t] : tables) {
      H5 g = h5::create_group(file, dataset_name(name), ok, true);
      H5 inputs;
      for (std::size_t c = 0; c < t.columns.size(); ++c) {
        std::vector<std::string> cells;
        for (const auto& r : t.rows) cells.push_back(c < r.size() ? r[c] : "");
        if (given.count(t.columns[c])) {
          if (inputs < 0) inputs = h5::create_group(g, "given", ok, true);
          h5::write_strings(inputs, dataset_name(t.columns[c]), cells, ok);
          continue;
        }
        // "name [unit]" -> dataset "name" with that unit; a plain name counts ("point", "n") are "1".
        std::string col = t.columns[c], unit = "1";
        if (const auto open = col.rfind(" ["); open != std::string::npos && col.back() == ']') {
          unit = col.substr(open + 2, col.size() - open - 3);
          col = col.substr(0, open);
        }
        std::vector<double> x;
        bool numeric = true;
        for (const auto& cell : cells) {
          const auto v = as_number(cell);
          if (!v) {
            numeric = false;
            break;
          }
          x.push_back(*v);
        }
        if (numeric)
          h5::write_dataset(g, dataset_name(col), {x.size()}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, x.data(), unit, ok);
        else
          h5::write_strings(g, dataset_name(col), cells, ok);
      }
    }
    h5::close_file(file, ok, "cannot write " + tmp);
  }
  fs::rename(tmp, path);
}

}  // namespace bagdem::study
