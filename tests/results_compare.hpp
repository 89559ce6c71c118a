// Test support: every dataset of an HDF5 file read back as raw bytes (HDF5 C API), and the check
// that two files hold the same datasets, shape for shape and bit for bit (checkpoint/resume).
#pragma once
#include <gtest/gtest.h>
#include <hdf5.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace bagdem::testing {

struct RawDataset {
  std::vector<hsize_t> dims;
  std::vector<unsigned char> bytes;
};

inline herr_t collect_dataset_names(hid_t group, const char* name, const H5L_info_t*, void* data) {
  const hid_t obj = H5Oopen(group, name, H5P_DEFAULT);
  if (obj < 0) return 0;
  if (H5Iget_type(obj) == H5I_DATASET) static_cast<std::vector<std::string>*>(data)->push_back(std::string("/") + name);
  H5Oclose(obj);
  return 0;
}

// Every dataset of the file: name -> dims and raw bytes (read in the native form of its type).
inline std::map<std::string, RawDataset> read_all_datasets(const std::filesystem::path& path) {
  std::map<std::string, RawDataset> out;
  const hid_t f = H5Fopen(path.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(f, 0) << path;
  if (f < 0) return out;
  std::vector<std::string> names;
  H5Lvisit(f, H5_INDEX_NAME, H5_ITER_INC, collect_dataset_names, &names);
  for (const auto& name : names) {
    RawDataset d;
    const hid_t ds = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
    const hid_t space = H5Dget_space(ds);
    d.dims.resize(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
    H5Sget_simple_extent_dims(space, d.dims.data(), nullptr);
    const hid_t ftype = H5Dget_type(ds);
    const hid_t mtype = H5Tget_native_type(ftype, H5T_DIR_DEFAULT);
    const auto npoints = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space));
    d.bytes.assign(npoints * H5Tget_size(mtype), 0);
    if (npoints > 0) {
      EXPECT_GE(H5Dread(ds, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, d.bytes.data()), 0) << name;
    }
    H5Tclose(mtype);
    H5Tclose(ftype);
    H5Sclose(space);
    H5Dclose(ds);
    out[name] = std::move(d);
  }
  H5Fclose(f);
  return out;
}

inline std::string dims_text(const std::vector<hsize_t>& dims) {
  std::string s = "[";
  for (std::size_t k = 0; k < dims.size(); ++k) s += (k ? ", " : "") + std::to_string(dims[k]);
  return s + "]";
}

// Every dataset of A (read from file a) is in B (from b) with the same shape and bits, and B has no
// other. String datasets are compared as their pointers would be: leave them out of such files.
inline void expect_same_datasets(const std::map<std::string, RawDataset>& A, const std::filesystem::path& a,
                                 const std::map<std::string, RawDataset>& B, const std::filesystem::path& b) {
  EXPECT_FALSE(A.empty()) << "no datasets in " << a;
  EXPECT_EQ(A.size(), B.size()) << a << " vs " << b;
  for (const auto& [name, da] : A) {
    const auto it = B.find(name);
    if (it == B.end()) {
      ADD_FAILURE() << name << " missing in " << b;
      continue;
    }
    const RawDataset& db = it->second;
    EXPECT_EQ(da.dims, db.dims) << name << ": " << dims_text(da.dims) << " vs " << dims_text(db.dims);
    if (da.dims != db.dims) continue;
    if (da.bytes != db.bytes) {
      std::size_t k = 0;
      while (k < da.bytes.size() && da.bytes[k] == db.bytes[k]) ++k;
      ADD_FAILURE() << name << " differs (first differing byte " << k << " of " << da.bytes.size() << ")";
    }
  }
}

inline void expect_same_datasets(const std::filesystem::path& a, const std::filesystem::path& b) {
  expect_same_datasets(read_all_datasets(a), a, read_all_datasets(b), b);
}

}  // namespace bagdem::testing
