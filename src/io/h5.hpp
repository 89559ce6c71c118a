// Private to src: the HDF5 layer every file of bagdem goes through (results.h5, bag.h5, study.h5,
// export.h5, and reading results.h5 back for the reduction). One place for the owner of an HDF5
// identifier, the check of HDF5's return codes, the string type, attributes and whole datasets.
#pragma once
#include <hdf5.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace bagdem::h5 {

// Owns one hid_t and closes it with the matching H5?close.
class H5 {
 public:
  H5() = default;
  H5(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  H5(H5&& o) noexcept : id_(std::exchange(o.id_, H5I_INVALID_HID)), close_(o.close_) {}
  H5& operator=(H5&& o) noexcept {
    std::swap(id_, o.id_);
    std::swap(close_, o.close_);
    return *this;
  }
  H5(const H5&) = delete;
  H5& operator=(const H5&) = delete;
  ~H5() {
    if (id_ >= 0) close_(id_);
  }
  operator hid_t() const { return id_; }
  hid_t release() { return std::exchange(id_, H5I_INVALID_HID); }  // the caller closes it

 private:
  hid_t id_ = H5I_INVALID_HID;
  herr_t (*close_)(hid_t) = nullptr;
};

// HDF5 reports failure as a negative identifier or status. A Check passes a good one through and
// hands a failure's description to its file's `fail`, which throws (each file says what failed
// its own way: the file's path, an InputError for a file the user gave).
class Check {
 public:
  explicit Check(std::function<void(const std::string&)> fail) : fail_(std::move(fail)) {}
  // std::runtime_error(prefix + what + " (" + error_reason() + ")").
  static Check with_prefix(const std::string& prefix);
  [[noreturn]] void fail(const std::string& what) const;
  template <class T>
  T operator()(T r, const std::string& what) const {
    if (r < 0) fail(what);
    return r;
  }

 private:
  std::function<void(const std::string&)> fail_;
};

// A file written whole, flushed and closed with both checked: what the library writes at the close
// (data still cached, the superblock) fails there on a full disk, which a close in a destructor
// would drop, and the file would then be renamed into place broken.
inline void close_file(H5& file, const Check& ok, const std::string& what) {
  ok(H5Fflush(file, H5F_SCOPE_LOCAL), what);
  ok(H5Fclose(file.release()), what);
}

// The innermost description on HDF5's error stack after a failed call: for a failed write the
// system's reason ("No space left on device"); "" when the stack is empty.
std::string error_reason();

// Strings are variable-length UTF-8 (the text lives in the global heap, so a long one is not bound
// by the 64 KiB object-header limit of fixed-length attributes).
H5 string_type(const Check& ok);

// A group; `ordered` tracks link creation order, so readers list its members as written.
H5 create_group(hid_t parent, const std::string& name, const Check& ok, bool ordered = false);

// Scalar (or 1-D, `count` values) attributes; one of that name is replaced.
void write_attribute(hid_t obj, const std::string& name, double value, const Check& ok);
void write_attribute(hid_t obj, const std::string& name, const double* values, hsize_t count, const Check& ok);
void write_attribute(hid_t obj, const std::string& name, const std::string& value, const Check& ok);

// A dataset of shape `dims` written whole from `data` (in `mem_type`), with a "unit" attribute.
H5 write_dataset(hid_t group, const std::string& name, const std::vector<hsize_t>& dims, hid_t file_type,
                 hid_t mem_type, const void* data, const std::string& unit, const Check& ok);
// A 1-D dataset of strings.
H5 write_strings(hid_t group, const std::string& name, const std::vector<std::string>& cells, const Check& ok);

// Reading: a dataset's dimensions; all of its values as doubles (row-major, flattened); the text
// of a string attribute, variable- or fixed-length.
std::vector<hsize_t> dims(hid_t ds, const Check& ok);
std::vector<double> read_doubles(hid_t ds, const std::string& name, const Check& ok);
std::string read_string(hid_t attr, const std::string& name, const Check& ok);

}  // namespace bagdem::h5
