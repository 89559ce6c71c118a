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

#include "../io/h5_handle.hpp"
#include "bagdem/study/study.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;
using h5::H5;

namespace {

hid_t ok(hid_t id, const std::string& what) {
  if (id < 0) throw std::runtime_error("study.h5: " + what);
  return id;
}

std::optional<double> as_number(const std::string& cell) {
  if (cell.empty()) return std::numeric_limits<double>::quiet_NaN();
  char* end = nullptr;
  const double x = std::strtod(cell.c_str(), &end);
  if (end == cell.c_str() || *end) return std::nullopt;
  return x;
}

H5 string_type() {
  H5 t(ok(H5Tcopy(H5T_C_S1), "cannot copy a type"), H5Tclose);
  ok(H5Tset_size(t, H5T_VARIABLE), "cannot make a string type");
  ok(H5Tset_cset(t, H5T_CSET_UTF8), "cannot make a string type");
  return t;
}

H5 ordered_group(hid_t parent, const std::string& name) {
  H5 gcpl(ok(H5Pcreate(H5P_GROUP_CREATE), "cannot create group " + name), H5Pclose);
  ok(H5Pset_link_creation_order(gcpl, H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED), "cannot create group " + name);
  return H5(ok(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, gcpl, H5P_DEFAULT), "cannot create group " + name), H5Gclose);
}

void write_strings(hid_t group, const std::string& name, const std::vector<std::string>& cells) {
  const hsize_t n = cells.size();
  H5 space(ok(H5Screate_simple(1, &n, nullptr), "cannot create a dataspace"), H5Sclose);
  H5 type = string_type();
  H5 ds(ok(H5Dcreate2(group, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "cannot create dataset " + name), H5Dclose);
  std::vector<const char*> p;
  for (const auto& c : cells) p.push_back(c.c_str());
  if (n > 0) ok(H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, p.data()), "cannot write " + name);
}

void write_numbers(hid_t group, const std::string& name, const std::vector<double>& x, const std::string& unit) {
  const hsize_t n = x.size();
  H5 space(ok(H5Screate_simple(1, &n, nullptr), "cannot create a dataspace"), H5Sclose);
  H5 ds(ok(H5Dcreate2(group, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "cannot create dataset " + name),
        H5Dclose);
  if (n > 0) ok(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, x.data()), "cannot write " + name);
  H5 type = string_type();
  H5 scalar(ok(H5Screate(H5S_SCALAR), "cannot create a dataspace"), H5Sclose);
  H5 attr(ok(H5Acreate2(ds, "unit", type, scalar, H5P_DEFAULT, H5P_DEFAULT), "cannot write the unit of " + name), H5Aclose);
  const char* u = unit.c_str();
  ok(H5Awrite(attr, type, &u), "cannot write the unit of " + name);
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
  {
    H5 file(ok(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "cannot create " + tmp), H5Fclose);
    for (const auto& [name, t] : tables) {
      H5 g = ordered_group(file, dataset_name(name));
      H5 inputs;
      for (std::size_t c = 0; c < t.columns.size(); ++c) {
        std::vector<std::string> cells;
        for (const auto& r : t.rows) cells.push_back(c < r.size() ? r[c] : "");
        if (given.count(t.columns[c])) {
          if (inputs < 0) inputs = ordered_group(g, "given");
          write_strings(inputs, dataset_name(t.columns[c]), cells);
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
        if (numeric) write_numbers(g, dataset_name(col), x, unit);
        else write_strings(g, dataset_name(col), cells);
      }
    }
  }
  fs::rename(tmp, path);
}

}  // namespace bagdem::study
