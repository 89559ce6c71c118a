// The HDF5 layer (h5.hpp).
#include "h5.hpp"

#include <stdexcept>

#include <zlib.h>

namespace bagdem::h5 {

namespace {
// HDF5 closes the files still open when the program exits. A file whose close failed (its last
// writes did not fit on a full disk) stays in HDF5's tables half torn down, and closing it again at
// exit crashes (SIGSEGV in H5F__close_cb, HDF5 1.10). bagdem closes every file itself, so that
// clean-up at exit is not wanted: switched off before the first HDF5 call (a static initializer).
[[maybe_unused]] const herr_t kNoCleanupAtExit = H5dont_atexit();

// The description of the innermost error on HDF5's stack.
herr_t innermost(unsigned n, const H5E_error2_t* e, void* out) {
  if (n == 0 && e->desc) *static_cast<std::string*>(out) = e->desc;
  return 0;
}
}  // namespace

std::string error_reason() {
  std::string desc;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, innermost, &desc);
  // The file drivers' "... errno = 28, error message = 'No space left on device', ...".
  const std::string key = "error message = '";
  const std::size_t at = desc.find(key);
  if (at == std::string::npos) return desc;
  const std::size_t end = desc.find('\'', at + key.size());
  return desc.substr(at + key.size(), end == std::string::npos ? std::string::npos : end - at - key.size());
}

Check Check::with_prefix(const std::string& prefix) {
  return Check([prefix](const std::string& what) {
    const std::string reason = error_reason();
    throw std::runtime_error(prefix + what + (reason.empty() ? "" : " (" + reason + ")"));
  });
}

void Check::fail(const std::string& what) const {
  fail_(what);
  throw std::logic_error("h5::Check: the fail function returned (" + what + ")");
}

H5 string_type(const Check& ok) {
  H5 t(ok(H5Tcopy(H5T_C_S1), "cannot copy a type"), H5Tclose);
  ok(H5Tset_size(t, H5T_VARIABLE), "cannot make a string type");
  ok(H5Tset_cset(t, H5T_CSET_UTF8), "cannot make a string type");
  return t;
}

H5 create_group(hid_t parent, const std::string& name, const Check& ok, bool ordered) {
  const std::string what = "cannot create group " + name;
  H5 gcpl(ok(H5Pcreate(H5P_GROUP_CREATE), what), H5Pclose);
  if (ordered) ok(H5Pset_link_creation_order(gcpl, H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED), what);
  return H5(ok(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, gcpl, H5P_DEFAULT), what), H5Gclose);
}

namespace {
void attribute(hid_t obj, const std::string& name, hid_t type, hid_t space, const void* value, const Check& ok) {
  const std::string what = "cannot write attribute " + name;
  if (ok(H5Aexists(obj, name.c_str()), what) > 0) ok(H5Adelete(obj, name.c_str()), what);
  H5 attr(ok(H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), what), H5Aclose);
  ok(H5Awrite(attr, type, value), what);
}
}  // namespace

void write_attribute(hid_t obj, const std::string& name, double value, const Check& ok) {
  H5 space(ok(H5Screate(H5S_SCALAR), "cannot make a dataspace"), H5Sclose);
  attribute(obj, name, H5T_NATIVE_DOUBLE, space, &value, ok);
}

void write_attribute(hid_t obj, const std::string& name, const double* values, hsize_t count, const Check& ok) {
  H5 space(ok(H5Screate_simple(1, &count, nullptr), "cannot make a dataspace"), H5Sclose);
  attribute(obj, name, H5T_NATIVE_DOUBLE, space, values, ok);
}

void write_attribute(hid_t obj, const std::string& name, const std::string& value, const Check& ok) {
  H5 type = string_type(ok);
  H5 space(ok(H5Screate(H5S_SCALAR), "cannot make a dataspace"), H5Sclose);
  const char* text = value.c_str();
  attribute(obj, name, type, space, &text, ok);
}

H5 write_dataset(hid_t group, const std::string& name, const std::vector<hsize_t>& dims, hid_t file_type,
                 hid_t mem_type, const void* data, const std::string& unit, const Check& ok) {
  const std::string what = "cannot write dataset " + name;
  H5 space(ok(H5Screate_simple(int(dims.size()), dims.data(), nullptr), what), H5Sclose);
  H5 ds(ok(H5Dcreate2(group, name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), what), H5Dclose);
  if (!dims.empty() && dims[0] > 0) ok(H5Dwrite(ds, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), what);
  write_attribute(ds, "unit", unit, ok);
  return ds;
}

H5 write_strings(hid_t group, const std::string& name, const std::vector<std::string>& cells, const Check& ok) {
  const std::string what = "cannot write dataset " + name;
  const hsize_t n = cells.size();
  H5 space(ok(H5Screate_simple(1, &n, nullptr), what), H5Sclose);
  H5 type = string_type(ok);
  H5 ds(ok(H5Dcreate2(group, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), what), H5Dclose);
  std::vector<const char*> p;
  for (const auto& c : cells) p.push_back(c.c_str());
  if (n > 0) ok(H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, p.data()), what);
  return ds;
}

std::vector<hsize_t> dims(hid_t ds, const Check& ok) {
  H5 space(ok(H5Dget_space(ds), "cannot get a dataspace"), H5Sclose);
  std::vector<hsize_t> d(ok(H5Sget_simple_extent_ndims(space), "bad dataspace"));
  ok(H5Sget_simple_extent_dims(space, d.data(), nullptr), "bad dataspace");
  return d;
}

std::vector<double> read_doubles(hid_t ds, const std::string& name, const Check& ok) {
  std::size_t n = 1;
  for (hsize_t d : dims(ds, ok)) n *= d;
  std::vector<double> v(n);
  if (n > 0) ok(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "cannot read " + name);
  // A sealed series (ResultsFile::seal): its values must be those the run wrote.
  if (H5Aexists(ds, "crc32") > 0) {
    double recorded = -1;
    H5 a(ok(H5Aopen(ds, "crc32", H5P_DEFAULT), "attribute crc32 of " + name), H5Aclose);
    ok(H5Aread(a, H5T_NATIVE_DOUBLE, &recorded), "attribute crc32 of " + name);
    const auto crc = static_cast<double>(crc32_z(0, reinterpret_cast<const Bytef*>(v.data()), v.size() * sizeof(double)));
    if (crc != recorded) ok.fail(name + ": its values differ from the CRC-32 the run recorded when it completed (the file was damaged or edited)");
  }
  return v;
}

std::string read_string(hid_t attr, const std::string& name, const Check& ok) {
  H5 type(ok(H5Aget_type(attr), "attribute " + name), H5Tclose);  // read as stored
  std::string out;
  if (H5Tis_variable_str(type) > 0) {
    char* s = nullptr;
    ok(H5Aread(attr, type, &s), "attribute " + name);
    if (s) out = s;
    H5free_memory(s);
  } else {
    std::vector<char> buf(H5Tget_size(type) + 1, '\0');
    ok(H5Aread(attr, type, buf.data()), "attribute " + name);
    out = buf.data();  // up to the first NUL (null-terminated or padded)
  }
  return out;
}

}  // namespace bagdem::h5
