// Test support: reading HDF5 files back (results.h5, bag.h5) with the C API, so tests check what is
// on disk independently of the writer's code.
#pragma once
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <vector>

namespace bagdem::testing {

struct Doubles {
  std::vector<hsize_t> dims;
  std::vector<double> values;
};

struct Ints {
  std::vector<hsize_t> dims;
  std::vector<std::int32_t> values;
  bool int32 = false;  // stored as a 4-byte integer
};

namespace detail {
// Dimensions and all values of a dataset, converted to `type`.
template <class T>
bool read_all(hid_t file, const std::string& name, hid_t type, std::vector<hsize_t>& dims, std::vector<T>& values,
              bool* is_int32 = nullptr) {
  hid_t ds = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(ds, 0) << name;
  if (ds < 0) return false;
  if (is_int32) {
    hid_t stored = H5Dget_type(ds);
    *is_int32 = H5Tget_class(stored) == H5T_INTEGER && H5Tget_size(stored) == 4;
    H5Tclose(stored);
  }
  hid_t space = H5Dget_space(ds);
  dims.resize(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  hsize_t total = 1;
  for (hsize_t n : dims) total *= n;
  values.resize(total);
  if (total > 0) {
    EXPECT_GE(H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0) << name;
  }
  H5Sclose(space);
  H5Dclose(ds);
  return true;
}
}  // namespace detail

inline Doubles read_doubles(hid_t file, const std::string& name) {
  Doubles d;
  detail::read_all(file, name, H5T_NATIVE_DOUBLE, d.dims, d.values);
  return d;
}

inline Ints read_ints(hid_t file, const std::string& name) {
  Ints d;
  detail::read_all(file, name, H5T_NATIVE_INT32, d.dims, d.values, &d.int32);
  return d;
}

// A variable-length string attribute as stored ("<missing>" if absent).
inline std::string read_string_attribute(hid_t obj, const std::string& name) {
  hid_t attr = H5Aopen(obj, name.c_str(), H5P_DEFAULT);
  if (attr < 0) return "<missing>";
  hid_t type = H5Aget_type(attr);  // read as stored: HDF5 converts no ASCII <-> UTF-8
  char* text = nullptr;
  std::string out = "<not a variable-length string>";
  if (H5Tis_variable_str(type) > 0 && H5Aread(attr, type, &text) >= 0 && text) out = text;
  H5free_memory(text);
  H5Tclose(type);
  H5Aclose(attr);
  return out;
}

// The `unit` attribute of a dataset.
inline std::string unit_of(hid_t file, const std::string& dataset) {
  hid_t ds = H5Dopen2(file, dataset.c_str(), H5P_DEFAULT);
  if (ds < 0) return "<no dataset>";
  std::string u = read_string_attribute(ds, "unit");
  H5Dclose(ds);
  return u;
}

inline hid_t open_read(const std::string& path) {
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(f, 0) << path;
  return f;
}

}  // namespace bagdem::testing
