// bag.h5: a settled bag saved for reuse (layout in bag_file.hpp).
#include "bagdem/io/bag_file.hpp"

#include <hdf5.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "bagdem/error.hpp"
#include "h5.hpp"

namespace bagdem {

using h5::H5;

namespace {

// What a user can do about a file that is not a saved bag.
constexpr const char* kHowToMakeOne =
    "write one with `bagdem run` (it saves bag.h5 when the settle phase ends)";

// ---- writing --------------------------------------------------------------------------------

struct Writer {
  std::string path;  // the file being written (the .part name), for messages
  h5::Check ok = h5::Check::with_prefix("bag file " + path + ": ");

  void attribute(hid_t obj, const std::string& name, double value) { h5::write_attribute(obj, name, value, ok); }
  void attribute(hid_t obj, const std::string& name, const Vec3& value) {
    h5::write_attribute(obj, name, value.data(), 3, ok);
  }
  void attribute(hid_t obj, const std::string& name, const std::string& value) {
    h5::write_attribute(obj, name, value, ok);
  }
  void points(hid_t group, const char* name, const std::vector<Vec3>& x) {
    std::vector<double> flat(3 * x.size());
    for (std::size_t i = 0; i < x.size(); ++i)
      for (int c = 0; c < 3; ++c) flat[3 * i + c] = x[i][c];
    h5::write_dataset(group, name, {x.size(), 3}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, flat.data(), "m", ok);
  }
};

void write_file(Writer& w, const SavedBag& bag) {
  H5 file(w.ok(H5Fcreate(w.path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
               "cannot create file"),
          H5Fclose);
  {
    H5 film = h5::create_group(file, "film", w.ok);
    w.points(film, "rest", bag.rest.vertices);
    w.points(film, "position", bag.film_position);
    std::vector<std::int32_t> flat(3 * bag.rest.triangles.size());
    for (std::size_t t = 0; t < bag.rest.triangles.size(); ++t)
      for (int c = 0; c < 3; ++c) flat[3 * t + c] = std::int32_t(bag.rest.triangles[t][c]);
    h5::write_dataset(film, "triangles", {bag.rest.triangles.size(), 3}, H5T_STD_I32LE, H5T_NATIVE_INT32,
                      flat.data(), "1", w.ok);

    H5 balls = h5::create_group(file, "balls", w.ok);
    w.points(balls, "position", bag.ball_position);
    h5::write_dataset(balls, "radius", {bag.ball_radius.size()}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                      bag.ball_radius.data(), "m", w.ok);

    w.attribute(file, "shape", bag.shape);
    w.attribute(file, "axis", bag.axis);
    w.attribute(file, "side", bag.side);
    w.attribute(file, "size", bag.size);  // m
    w.attribute(file, "fill_fraction", bag.fill_fraction);
    w.attribute(file, "film_thickness", bag.film_thickness);  // m
    w.attribute(file, "program_version", std::string(BAGDEM_VERSION));
  }  // the groups close before the file
  h5::close_file(file, w.ok, "cannot write it");
}

// ---- reading --------------------------------------------------------------------------------

struct Reader {
  std::string path;
  hid_t file = H5I_INVALID_HID;

  // Not a saved bag, or a damaged one: InputError naming the file and what is allowed.
  [[noreturn]] void bad(const std::string& what) const {
    throw InputError(path, "", "", what + "; " + kHowToMakeOne);
  }
  [[noreturn]] void damaged(const std::string& what) const { bad("cannot read " + what + " (a damaged file?)"); }
  template <class T>
  T ok(T r, const std::string& what) const {
    if (r < 0) damaged(what);
    return r;
  }

  // Whether the object at an absolute path like "/film/rest" exists (each link in turn: HDF5
  // fails, rather than answering no, when a group on the way is missing).
  bool exists(const std::string& name) const {
    for (std::size_t at = name.find('/', 1);; at = name.find('/', at + 1)) {
      const std::string prefix = name.substr(0, at);
      if (H5Lexists(file, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
      if (at == std::string::npos) return true;
    }
  }

  H5 open(const std::string& name) const {
    if (!exists(name)) {
      std::string what = "not a saved bag (no " + name + ")";
      if (exists("/frames")) what += "; it looks like a results.h5";
      bad(what);
    }
    return H5(ok(H5Dopen2(file, name.c_str(), H5P_DEFAULT), name), H5Dclose);
  }

  // The dataset's dimensions; `columns` = 0 for [rows], else [rows, columns].
  hsize_t rows(hid_t ds, const std::string& name, hsize_t columns) const {
    H5 space(ok(H5Dget_space(ds), name), H5Sclose);
    const int rank = ok(H5Sget_simple_extent_ndims(space), name);
    hsize_t d[2] = {0, 0};
    if (rank != (columns ? 2 : 1))
      bad(name + " has rank " + std::to_string(rank) + ", not " + (columns ? "2" : "1"));
    ok(H5Sget_simple_extent_dims(space, d, nullptr), name);
    if (columns && d[1] != columns)
      bad(name + " has " + std::to_string(d[1]) + " columns, not " + std::to_string(columns));
    return d[0];
  }

  H5T_class_t type_class(hid_t ds, const std::string& name) const {
    H5 type(ok(H5Dget_type(ds), name), H5Tclose);
    return H5Tget_class(type);
  }

  std::vector<double> doubles(const std::string& name, hsize_t columns, hsize_t& n) const {
    H5 ds = open(name);
    n = rows(ds, name, columns);
    if (type_class(ds, name) != H5T_FLOAT) bad(name + " is not floating point");
    std::vector<double> v(n * (columns ? columns : 1));
    if (!v.empty())
      ok(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), name);
    for (double x : v)
      if (!std::isfinite(x)) bad(name + " holds a value that is not finite");
    return v;
  }

  std::vector<Vec3> points(const std::string& name) const {
    hsize_t n = 0;
    const std::vector<double> flat = doubles(name, 3, n);
    std::vector<Vec3> x(n);
    for (std::size_t i = 0; i < n; ++i) x[i] = Vec3(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]);
    return x;
  }

  std::vector<std::array<std::uint32_t, 3>> triangles(const std::string& name,
                                                      std::size_t vertices) const {
    H5 ds = open(name);
    const hsize_t n = rows(ds, name, 3);
    if (type_class(ds, name) != H5T_INTEGER) bad(name + " is not integer");
    std::vector<std::int64_t> flat(3 * n);  // holds int32 and uint32 indices alike
    if (n > 0) ok(H5Dread(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, flat.data()), name);
    std::vector<std::array<std::uint32_t, 3>> t(n);
    for (std::size_t k = 0; k < n; ++k)
      for (int c = 0; c < 3; ++c) {
        const std::int64_t v = flat[3 * k + c];
        if (v < 0 || std::uint64_t(v) >= vertices)
          bad(name + " row " + std::to_string(k) + " has vertex " + std::to_string(v) +
              ", outside the " + std::to_string(vertices) + " vertices of /film/rest");
        t[k][c] = std::uint32_t(v);
      }
    return t;
  }

  H5 attribute(const std::string& name) const {
    if (ok(H5Aexists(file, name.c_str()), "attribute " + name) <= 0)
      bad("not a saved bag (no attribute " + name + ")");
    return H5(ok(H5Aopen(file, name.c_str(), H5P_DEFAULT), "attribute " + name), H5Aclose);
  }

  // A double attribute of `count` values.
  std::vector<double> numbers(const std::string& name, hssize_t count) const {
    H5 attr = attribute(name);
    H5 space(ok(H5Aget_space(attr), "attribute " + name), H5Sclose);
    H5 type(ok(H5Aget_type(attr), "attribute " + name), H5Tclose);
    if (H5Tget_class(type) != H5T_FLOAT && H5Tget_class(type) != H5T_INTEGER)
      bad("attribute " + name + " is not a number");
    if (H5Sget_simple_extent_npoints(space) != count)
      bad("attribute " + name + " has " + std::to_string(H5Sget_simple_extent_npoints(space)) +
          " values, not " + std::to_string(count));
    std::vector<double> v(static_cast<std::size_t>(count));
    ok(H5Aread(attr, H5T_NATIVE_DOUBLE, v.data()), "attribute " + name);
    for (double x : v)
      if (!std::isfinite(x)) bad("attribute " + name + " is not finite");
    return v;
  }
  double number(const std::string& name) const { return numbers(name, 1)[0]; }
  Vec3 vector(const std::string& name) const {
    const std::vector<double> v = numbers(name, 3);
    return Vec3(v[0], v[1], v[2]);
  }

  // A scalar string attribute, variable- or fixed-length.
  std::string text(const std::string& name) const {
    H5 attr = attribute(name);
    H5 type(ok(H5Aget_type(attr), "attribute " + name), H5Tclose);
    if (H5Tget_class(type) != H5T_STRING) bad("attribute " + name + " is not a string");
    return h5::read_string(attr, name, h5::Check([this](const std::string& what) { damaged(what); }));
  }
};

}  // namespace

void save_bag(const std::string& path, const SavedBag& bag) {
  const std::size_t v = bag.rest.vertices.size();
  if (bag.film_position.size() != v)
    throw std::invalid_argument("bag file " + path + ": the film has " + std::to_string(v) +
                                " rest vertices but " + std::to_string(bag.film_position.size()) +
                                " positions");
  if (bag.ball_radius.size() != bag.ball_position.size())
    throw std::invalid_argument("bag file " + path + ": " +
                                std::to_string(bag.ball_position.size()) + " balls but " +
                                std::to_string(bag.ball_radius.size()) + " radii");
  if (v > std::size_t(std::numeric_limits<std::int32_t>::max()))
    throw std::invalid_argument("bag file " + path + ": too many vertices for int32 indices");
  for (const auto& t : bag.rest.triangles)
    for (std::uint32_t i : t)
      if (i >= v)
        throw std::invalid_argument("bag file " + path + ": a triangle has vertex " +
                                    std::to_string(i) + ", the film " + std::to_string(v));

  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // failures become exceptions, not stderr dumps
  Writer w{path + ".part"};
  try {
    write_file(w, bag);  // closes the file on leaving
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(w.path, ec);
    throw;
  }
  // Rename only a complete, closed file: a reader never sees a half-written bag.
  std::error_code ec;
  std::filesystem::rename(w.path, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(w.path, ignored);
    throw std::runtime_error("bag file: cannot rename " + w.path + " to " + path + ": " +
                             ec.message());
  }
}

SavedBag load_bag(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw InputError(path, "", "", std::string("no such file; ") + kHowToMakeOne);
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(path, "", "", std::string("not a file; ") + kHowToMakeOne);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  H5 file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (file < 0)
    throw InputError(path, "", "",
                     std::string("not a saved bag (not an HDF5 file, or unreadable); ") +
                         kHowToMakeOne);
  const Reader r{path, file};

  SavedBag bag;
  bag.rest.vertices = r.points("/film/rest");
  const std::size_t v = bag.rest.vertices.size();
  bag.film_position = r.points("/film/position");
  if (bag.film_position.size() != v)
    r.bad("/film/position has " + std::to_string(bag.film_position.size()) +
          " rows but /film/rest " + std::to_string(v));
  bag.rest.triangles = r.triangles("/film/triangles", v);
  if (v < 3 || bag.rest.triangles.empty()) r.bad("the film has no triangles");
  bag.ball_position = r.points("/balls/position");
  hsize_t n = 0;
  bag.ball_radius = r.doubles("/balls/radius", 0, n);
  if (bag.ball_radius.size() != bag.ball_position.size())
    r.bad("/balls/radius has " + std::to_string(bag.ball_radius.size()) +
          " rows but /balls/position " + std::to_string(bag.ball_position.size()));
  for (double radius : bag.ball_radius)
    if (!(radius > 0)) r.bad("/balls/radius holds a radius that is not positive");

  bag.shape = r.text("shape");
  bag.axis = r.vector("axis");
  bag.side = r.vector("side");
  bag.size = r.vector("size");
  bag.fill_fraction = r.number("fill_fraction");
  bag.film_thickness = r.number("film_thickness");
  return bag;
}

}  // namespace bagdem
