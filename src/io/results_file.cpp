// results.h5 writer (layout and units in results_file.hpp); the XDMF index beside it: xdmf.cpp.
#include "bagdem/io/results_file.hpp"

#include <hdf5.h>
#include <zlib.h>

#include <charconv>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "bagdem/error.hpp"
#include "h5.hpp"

namespace bagdem {

using h5::H5;

namespace {

static_assert(sizeof(int) == 4, "/particles/material is stored as int32");

// The fields of each time-series group besides "time" (s), with their units.
constexpr std::pair<const char*, const char*> kFrameFields[] = {
    {"position", "m"}, {"velocity", "m/s"}, {"angular_velocity", "rad/s"}};
constexpr std::pair<const char*, const char*> kCavityFields[] = {
    {"position", "m"}, {"velocity", "m/s"}, {"force", "N"}, {"torque", "N m"}, {"contents_velocity", "m/s"}};
// A series' name: a field's (name, unit) or an energy term's name.
const char* name_of(const std::pair<const char*, const char*>& field) { return field.first; }
const char* name_of(const char* term) { return term; }

constexpr hsize_t kRowsPerChunk = 1024;  // time, cavity and energy series: 8-24 KiB chunks

// CRC-32 (zlib) of `n` doubles' bytes, continuing `crc`.
std::uint32_t crc_of(std::uint32_t crc, const double* v, std::size_t n) {
  return static_cast<std::uint32_t>(crc32_z(crc, reinterpret_cast<const Bytef*>(v), n * sizeof(double)));
}
template <class T>
std::uint32_t crc_as_doubles(std::uint32_t crc, const T* v, std::size_t n) {
  const std::vector<double> d(v, v + n);
  return crc_of(crc, d.data(), d.size());
}

// Guard of every operation that needs an open file (a template because Impl is private).
template <class Impl>
Impl& open_or_throw(Impl* p) {
  if (!p) throw std::runtime_error("results file is already closed");
  return *p;
}

}  // namespace

struct ResultsFile::Impl {
  std::string path;
  H5 file;  // declared before the datasets so that it is closed last
  hsize_t n = 0;
  SeriesLengths len;
  std::vector<H5> frames, cavity, energy;  // per group: [0] is "time", then the fields in order
  // The bag's film, when the file has one: /film/position, its rows (one per frame once each
  // frame's film is written), node and triangle counts.
  bool film = false;
  H5 film_position;
  // Tables of scalar columns (/structure, /sweep): created with their first row.
  struct Table {
    std::vector<H5> columns;
    hsize_t rows = 0;
  };
  std::map<std::string, Table> tables;
  hsize_t film_rows = 0, film_nodes = 0, film_triangles = 0;
  // What a resume verifies (digest()): the CRC-32 of each appended series' rows so far, by its
  // dataset, and of the datasets written once (/particles/radius, /particles/material,
  // /film/triangles, as doubles, in that order).
  std::unordered_map<hid_t, std::uint32_t> crc;
  std::uint32_t fixed_crc = 0;
  // The series a reopened file holds, as opened (open_series): name, dataset, rows kept.
  struct Opened {
    std::string name;
    hid_t ds;
    hsize_t rows;
  };
  std::vector<Opened> opened;

  h5::Check ok;  // failures throw "results file PATH: what"

  explicit Impl(const std::string& p) : path(p), ok(h5::Check::with_prefix("results file " + p + ": ")) {}

  void flush() { ok(H5Fflush(file, H5F_SCOPE_LOCAL), "cannot flush"); }

  void attribute(hid_t obj, const std::string& name, double value) { h5::write_attribute(obj, name, value, ok); }
  void attribute(hid_t obj, const std::string& name, const std::string& value) { h5::write_attribute(obj, name, value, ok); }
  H5 group(const char* name, bool ordered = false) { return h5::create_group(file, name, ok, ordered); }

  // Empty double series, extendible along rows shaped `row` ({} for scalars, {3}, {N, 3}).
  H5 series(hid_t group, const char* name, std::vector<hsize_t> row, hsize_t chunk_rows,
            const char* unit) {
    const std::string what = std::string("cannot create dataset ") + name;
    std::vector<hsize_t> dims{0}, maxdims{H5S_UNLIMITED}, chunk{chunk_rows};
    dims.insert(dims.end(), row.begin(), row.end());
    maxdims.insert(maxdims.end(), row.begin(), row.end());
    chunk.insert(chunk.end(), row.begin(), row.end());
    H5 space(ok(H5Screate_simple(int(dims.size()), dims.data(), maxdims.data()), what), H5Sclose);
    H5 dcpl(ok(H5Pcreate(H5P_DATASET_CREATE), what), H5Pclose);
    ok(H5Pset_chunk(dcpl, int(chunk.size()), chunk.data()), what);
    H5 ds(ok(H5Dcreate2(group, name, H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT), what),
          H5Dclose);
    attribute(ds, "unit", unit);
    return ds;
  }

  std::vector<hsize_t> dims(hid_t ds) const { return h5::dims(ds, ok); }

  // Opens `name`, which must hold at least `rows` rows (growing it would invent data), and with
  // `cut` cuts it to them; records it in `opened` with its rows.
  H5 open_rows(const std::string& name, hsize_t rows, bool cut) {
    H5 ds(ok(H5Dopen2(file, name.c_str(), H5P_DEFAULT), "cannot open dataset " + name), H5Dclose);
    std::vector<hsize_t> d = dims(ds);
    if (d.empty() || d[0] < rows)
      ok.fail(name + " has fewer than the " + std::to_string(rows) + " rows to resume from");
    opened.push_back({name, ds, rows});
    if (!cut) return ds;
    d[0] = rows;
    ok(H5Dset_extent(ds, d.data()), "cannot truncate " + name);
    return ds;
  }

  // The data's digest: the CRC-32 of the per-dataset CRCs of the fixed datasets, the frames, the
  // cavity and energy series, the film's frames and /structure, in that order (/sweep is written
  // again on a resume), with their count in the upper 32 bits.
  std::uint64_t digest() const {
    std::vector<std::uint32_t> parts{fixed_crc};
    auto add = [&](hid_t ds) {
      const auto it = crc.find(ds);
      parts.push_back(it == crc.end() ? 0 : it->second);
    };
    for (const auto* g : {&frames, &cavity, &energy})
      for (const H5& ds : *g) add(ds);
    if (film) add(film_position);
    if (const auto t = tables.find("structure"); t != tables.end())
      for (const H5& ds : t->second.columns) add(ds);
    const auto c = static_cast<std::uint32_t>(crc32_z(0, reinterpret_cast<const Bytef*>(parts.data()), parts.size() * sizeof parts[0]));
    return (static_cast<std::uint64_t>(parts.size()) << 32) | c;
  }

  // The CRC of a dataset's first `rows` rows as they stand in the file (doubles).
  std::uint32_t crc_from_file(hid_t ds, const std::string& name, hsize_t rows) {
    std::vector<hsize_t> d = dims(ds);
    d[0] = rows;
    std::size_t n = 1;
    for (hsize_t x : d) n *= x;
    std::vector<double> v(n);
    if (n > 0) {
      const std::vector<hsize_t> start(d.size(), 0);
      H5 file_space(ok(H5Dget_space(ds), "cannot read " + name), H5Sclose);
      ok(H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start.data(), nullptr, d.data(), nullptr), "cannot read " + name);
      H5 mem_space(ok(H5Screate_simple(int(d.size()), d.data(), nullptr), "cannot read " + name), H5Sclose);
      ok(H5Dread(ds, H5T_NATIVE_DOUBLE, mem_space, file_space, H5P_DEFAULT, v.data()), "cannot read " + name);
    }
    return crc_of(0, v.data(), v.size());
  }

  // Opens the series of an existing file to continue it (cut to `lengths` with `cut`): the frames,
  // the cavity and energy series, the film and /structure, in digest()'s order.
  void open_series(const SeriesLengths& lengths, bool cut);
  // The CRC of the datasets written once (/particles/radius, /particles/material, /film/triangles).
  std::uint32_t fixed_crc_from_file();

  // Grows a series to row + 1 rows and writes row `row` (doubles, row-major).
  void append_row(hid_t ds, hsize_t row, const double* data) {
    const std::string what = "cannot append to a dataset";
    std::vector<hsize_t> d = dims(ds);
    d[0] = row + 1;
    std::size_t n = 1;
    for (std::size_t k = 1; k < d.size(); ++k) n *= d[k];
    crc[ds] = crc_of(crc[ds], data, n);
    ok(H5Dset_extent(ds, d.data()), what);
    std::vector<hsize_t> start(d.size(), 0), count = d;
    start[0] = row;
    count[0] = 1;
    H5 file_space(ok(H5Dget_space(ds), what), H5Sclose);
    ok(H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start.data(), nullptr, count.data(),
                           nullptr),
       what);
    H5 mem_space(ok(H5Screate_simple(int(count.size()), count.data(), nullptr), what), H5Sclose);
    ok(H5Dwrite(ds, H5T_NATIVE_DOUBLE, mem_space, file_space, H5P_DEFAULT, data), what);
  }
};

ResultsFile::ResultsFile(Impl* impl) : impl_(impl) {}

ResultsFile::ResultsFile(const std::string& path, const std::vector<double>& radius,
                         const std::vector<int>& material,
                         const std::vector<std::string>& materials, double cavity_interval) {
  if (radius.empty() || material.size() != radius.size())
    throw std::invalid_argument("results file " + path +
                                ": need one radius and one material per particle, at least one");
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // failures become exceptions, not stderr dumps
  auto p = std::make_unique<Impl>(path);
  p->n = radius.size();
  p->file = H5(
      p->ok(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "cannot create file"),
      H5Fclose);
  p->attribute(p->file, "program_version", std::string(BAGDEM_VERSION));

  H5 particles = p->group("particles");
  h5::write_dataset(particles, "radius", {p->n}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, radius.data(), "m", p->ok);
  H5 mat = h5::write_dataset(particles, "material", {p->n}, H5T_STD_I32LE, H5T_NATIVE_INT, material.data(), "1", p->ok);
  std::string names;
  for (const std::string& m : materials) names += (names.empty() ? "" : ",") + m;
  p->attribute(mat, "materials", names);
  p->fixed_crc = crc_as_doubles(crc_of(0, radius.data(), radius.size()), material.data(), material.size());

  H5 frames = p->group("frames");  // one frame per chunk: frames are written and read whole
  p->frames.push_back(p->series(frames, "time", {}, kRowsPerChunk, "s"));
  for (auto [name, unit] : kFrameFields)
    p->frames.push_back(p->series(frames, name, {p->n, 3}, 1, unit));

  H5 cavity = p->group("cavity");
  p->attribute(cavity, "interval", cavity_interval);  // s
  p->cavity.push_back(p->series(cavity, "time", {}, kRowsPerChunk, "s"));
  for (auto [name, unit] : kCavityFields)
    p->cavity.push_back(p->series(cavity, name, {3}, kRowsPerChunk, unit));

  H5 energy = p->group("energy");
  p->energy.push_back(p->series(energy, "time", {}, kRowsPerChunk, "s"));
  for (const char* name : kEnergyTerms) p->energy.push_back(p->series(energy, name, {}, kRowsPerChunk, "J"));

  p->flush();
  impl_ = p.release();
}

void ResultsFile::Impl::open_series(const SeriesLengths& lengths, bool cut) {
  // group/time, then group/<field> for each field, all with `rows` rows.
  auto open = [&](std::vector<H5>& out, const std::string& group, const auto& fields, std::size_t rows) {
    out.push_back(open_rows(group + "/time", rows, cut));
    for (const auto& field : fields) out.push_back(open_rows(group + "/" + name_of(field), rows, cut));
  };
  open(frames, "/frames", kFrameFields, lengths.frames);
  open(cavity, "/cavity", kCavityFields, lengths.cavity);
  open(energy, "/energy", kEnergyTerms, lengths.energy);
  n = dims(frames[1]).at(1);  // /frames/position is [F, N, 3]
  if (ok(H5Lexists(file, "film", H5P_DEFAULT), "cannot look for /film") > 0) {
    film_position = open_rows("/film/position", lengths.frames, cut);
    film_nodes = dims(film_position).at(1);  // [F, V, 3]
    H5 triangles(ok(H5Dopen2(file, "/film/triangles", H5P_DEFAULT), "cannot open dataset /film/triangles"), H5Dclose);
    film_triangles = dims(triangles).at(0);  // [T, 3]
    film_rows = lengths.frames;
    film = true;
  }
  // Tables: /structure follows the time series (the checkpoint's rows).
  if (ok(H5Lexists(file, "structure", H5P_DEFAULT), "cannot look for /structure") > 0) {
    H5 g(ok(H5Gopen2(file, "/structure", H5P_DEFAULT), "cannot open /structure"), H5Gclose);
    H5G_info_t info;
    ok(H5Gget_info(g, &info), "cannot read /structure");
    Table& t = tables["structure"];
    for (hsize_t k = 0; k < info.nlinks; ++k) {
      char name[256];
      ok(H5Lget_name_by_idx(g, ".", H5_INDEX_CRT_ORDER, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT), "cannot list /structure");
      t.columns.push_back(open_rows(std::string("/structure/") + name, lengths.structure, cut));
    }
    t.rows = lengths.structure;
  }
}

std::uint32_t ResultsFile::Impl::fixed_crc_from_file() {
  std::uint32_t c = 0;
  for (const char* fixed : {"/particles/radius", "/particles/material", "/film/triangles"}) {
    if (std::string(fixed) == "/film/triangles" && !film) continue;
    H5 ds(ok(H5Dopen2(file, fixed, H5P_DEFAULT), std::string("cannot open dataset ") + fixed), H5Dclose);
    const std::vector<double> v = h5::read_doubles(ds, fixed, ok);
    c = crc_of(c, v.data(), v.size());
  }
  return c;
}

ResultsFile ResultsFile::reopen(const std::string& path, const SeriesLengths& lengths) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  // 1. Read-only, the rows to continue from must be those the checkpoint recorded: a file that is
  // refused is left exactly as it was.
  std::map<std::string, std::uint32_t> kept;
  std::uint32_t fixed = 0;
  {
    auto v = std::make_unique<Impl>(path);
    v->file = H5(v->ok(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "cannot open file"), H5Fclose);
    v->open_series(lengths, false);
    for (const Impl::Opened& o : v->opened) kept[o.name] = v->crc[o.ds] = v->crc_from_file(o.ds, o.name, o.rows);
    fixed = v->fixed_crc = v->fixed_crc_from_file();
    if (v->digest() != lengths.digest)
      throw InputError(path, "", "",
                       "its data differ from those the checkpoint recorded (the file was changed or damaged since the run was "
                       "interrupted): it cannot be continued, and is left as it is; run again without --resume");
  }
  // 2. Continue: every series cut to the checkpoint's rows, with the CRCs of those rows.
  auto p = std::make_unique<Impl>(path);
  p->file = H5(p->ok(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), "cannot open file"), H5Fclose);
  p->len = lengths;
  p->open_series(lengths, true);
  for (const Impl::Opened& o : p->opened) p->crc[o.ds] = kept.at(o.name);
  p->fixed_crc = fixed;
  // Any other table (/sweep) goes: its writer writes it again, from the rows it restored.
  H5G_info_t root;
  p->ok(H5Gget_info(p->file, &root), "cannot read /");
  std::vector<std::string> others;
  for (hsize_t k = 0; k < root.nlinks; ++k) {
    char name[256];
    p->ok(H5Lget_name_by_idx(p->file, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT), "cannot list /");
    const std::string n = name;
    if (n != "particles" && n != "frames" && n != "cavity" && n != "energy" && n != "film" && n != "structure") others.push_back(n);
  }
  for (const std::string& n : others) p->ok(H5Ldelete(p->file, n.c_str(), H5P_DEFAULT), "cannot remove /" + n);
  p->flush();
  return ResultsFile(p.release());
}

ResultsFile::ResultsFile(ResultsFile&& o) noexcept : impl_(std::exchange(o.impl_, nullptr)) {}

ResultsFile& ResultsFile::operator=(ResultsFile&& o) noexcept {
  ResultsFile old(std::move(o));  // takes o's file; gets this one's and closes it on leaving
  std::swap(impl_, old.impl_);
  return *this;
}

ResultsFile::~ResultsFile() {
  try {
    close();
  } catch (...) {  // a failed last flush cannot be reported from a destructor
  }
}

void ResultsFile::set_attribute(const std::string& name, const std::string& value) {
  Impl& p = open_or_throw(impl_);
  p.attribute(H5(p.ok(H5Gopen2(p.file, "/", H5P_DEFAULT), "cannot open /"), H5Gclose), name, value);
}

void ResultsFile::set_attribute(const std::string& name, double value) {
  Impl& p = open_or_throw(impl_);
  p.attribute(H5(p.ok(H5Gopen2(p.file, "/", H5P_DEFAULT), "cannot open /"), H5Gclose), name, value);
}

void ResultsFile::append_frame(double t, const std::vector<Vec3>& position,
                               const std::vector<Vec3>& velocity,
                               const std::vector<Vec3>& angular_velocity) {
  Impl& p = open_or_throw(impl_);
  if (p.film && p.film_rows != p.len.frames)
    throw std::logic_error("results file " + p.path +
                           ": the previous frame has no film (append_film_frame)");
  const std::vector<Vec3>* fields[] = {&position, &velocity, &angular_velocity};  // kFrameFields
  for (const std::vector<Vec3>* v : fields)
    if (v->size() != p.n)
      throw std::invalid_argument("results file " + p.path + ": a frame has " +
                                  std::to_string(v->size()) + " particles, the file " +
                                  std::to_string(p.n));
  std::vector<double> row(3 * p.n);
  for (std::size_t k = 0; k < 3; ++k) {
    for (std::size_t i = 0; i < p.n; ++i)
      for (int c = 0; c < 3; ++c) row[3 * i + c] = (*fields[k])[i][c];
    p.append_row(p.frames[1 + k], p.len.frames, row.data());
  }
  p.append_row(p.frames[0], p.len.frames, &t);  // last: a frame is complete once it has a time
  ++p.len.frames;
  p.flush();  // a killed run keeps every frame written so far
}

void ResultsFile::write_film(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                             std::size_t nodes) {
  Impl& p = open_or_throw(impl_);
  const std::string where = "results file " + p.path + ": ";
  if (nodes == 0 || triangles.empty())
    throw std::invalid_argument(where + "a film needs at least one node and one triangle");
  if (nodes > std::size_t(std::numeric_limits<std::int32_t>::max()))
    throw std::invalid_argument(where + "a film of " + std::to_string(nodes) +
                                " nodes does not fit int32 indices");
  std::vector<std::int32_t> flat(3 * triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      if (triangles[t][c] >= nodes)
        throw std::invalid_argument(where + "film triangle " + std::to_string(t) + " has node " +
                                    std::to_string(triangles[t][c]) + ", the film " +
                                    std::to_string(nodes) + " nodes");
      flat[3 * t + c] = std::int32_t(triangles[t][c]);
    }

  if (p.film) {  // reopened (or a second call): it must be the film already in the file
    std::vector<std::int32_t> stored;
    if (p.film_nodes == nodes && p.film_triangles == triangles.size()) {
      H5 ds(p.ok(H5Dopen2(p.file, "/film/triangles", H5P_DEFAULT),
                 "cannot open dataset /film/triangles"),
            H5Dclose);
      stored.resize(flat.size());
      p.ok(H5Dread(ds, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, stored.data()),
           "cannot read /film/triangles");
    }
    if (stored != flat)
      throw std::invalid_argument(where + "the film (" + std::to_string(nodes) + " nodes, " +
                                  std::to_string(triangles.size()) +
                                  " triangles) is not the one in the file (" +
                                  std::to_string(p.film_nodes) + " nodes, " +
                                  std::to_string(p.film_triangles) + " triangles)");
    return;
  }
  if (p.len.frames > 0)
    throw std::logic_error(where + "write_film must come before the first frame");

  H5 group = p.group("film");
  h5::write_dataset(group, "triangles", {triangles.size(), 3}, H5T_STD_I32LE, H5T_NATIVE_INT32, flat.data(), "1", p.ok);
  p.film_position = p.series(group, "position", {hsize_t(nodes), 3}, 1, "m");  // a frame a chunk
  p.film_nodes = nodes;
  p.film_triangles = triangles.size();
  p.film_rows = 0;
  p.film = true;
  p.fixed_crc = crc_as_doubles(p.fixed_crc, flat.data(), flat.size());
  p.flush();
}

void ResultsFile::append_film_frame(const std::vector<Vec3>& position) {
  Impl& p = open_or_throw(impl_);
  const std::string where = "results file " + p.path + ": ";
  if (!p.film) throw std::logic_error(where + "append_film_frame before write_film");
  if (position.size() != p.film_nodes)
    throw std::invalid_argument(where + "a film frame has " + std::to_string(position.size()) +
                                " nodes, the film " + std::to_string(p.film_nodes));
  if (p.film_rows + 1 != p.len.frames)
    throw std::logic_error(where + "a film frame must follow its frame (append_frame)");
  std::vector<double> row(3 * position.size());
  for (std::size_t i = 0; i < position.size(); ++i)
    for (int c = 0; c < 3; ++c) row[3 * i + c] = position[i][c];
  p.append_row(p.film_position, p.film_rows, row.data());
  ++p.film_rows;
  p.flush();
}

void ResultsFile::append_cavity(double t, const Vec3& position, const Vec3& velocity,
                                const Vec3& mean_force, const Vec3& mean_torque, const Vec3& contents_velocity) {
  Impl& p = open_or_throw(impl_);
  const Vec3* fields[] = {&position, &velocity, &mean_force, &mean_torque, &contents_velocity};  // kCavityFields
  static_assert(std::size(fields) == std::size(kCavityFields));
  p.append_row(p.cavity[0], p.len.cavity, &t);
  for (std::size_t k = 0; k < std::size(fields); ++k)
    p.append_row(p.cavity[1 + k], p.len.cavity, fields[k]->data());
  ++p.len.cavity;  // no flush (frequent): the next frame, flush() or close() does it
}

void ResultsFile::append_energy(double t, const std::array<double, kEnergyTerms.size()>& terms) {
  Impl& p = open_or_throw(impl_);
  p.append_row(p.energy[0], p.len.energy, &t);
  for (std::size_t k = 0; k < terms.size(); ++k) p.append_row(p.energy[1 + k], p.len.energy, &terms[k]);
  ++p.len.energy;  // no flush, as for the cavity
}

void ResultsFile::append_table_row(const std::string& group, const std::vector<TableColumn>& columns,
                                   const std::vector<double>& values) {
  Impl& p = open_or_throw(impl_);
  if (values.size() != columns.size())
    throw std::invalid_argument("results file " + p.path + ": a row of /" + group + " has " +
                                std::to_string(values.size()) + " values for " + std::to_string(columns.size()) + " columns");
  Impl::Table& t = p.tables[group];
  if (t.columns.empty()) {
    // Creation order is kept, so that a reopened file lists the columns in the same order.
    H5 g = p.group(group.c_str(), true);
    for (const TableColumn& c : columns) t.columns.push_back(p.series(g, c.name, {}, kRowsPerChunk, c.unit));
  }
  if (t.columns.size() != columns.size())
    throw std::invalid_argument("results file " + p.path + ": /" + group + " has " + std::to_string(t.columns.size()) + " columns");
  for (std::size_t k = 0; k < columns.size(); ++k) p.append_row(t.columns[k], t.rows, &values[k]);
  ++t.rows;
  if (group == "structure") p.len.structure = t.rows;
}

std::vector<double> ResultsFile::read_series(const std::string& dataset) const {
  Impl& p = open_or_throw(impl_);
  H5 ds(p.ok(H5Dopen2(p.file, dataset.c_str(), H5P_DEFAULT), "cannot open dataset " + dataset), H5Dclose);
  return h5::read_doubles(ds, dataset, p.ok);
}

SeriesLengths ResultsFile::lengths() const {
  if (!impl_) return {};
  SeriesLengths l = impl_->len;
  l.digest = impl_->digest();
  return l;
}

void ResultsFile::flush() { if (impl_) impl_->flush(); }

void ResultsFile::seal() {
  for (const auto& [ds, c] : open_or_throw(impl_).crc) impl_->attribute(ds, "crc32", static_cast<double>(c));
}

void ResultsFile::close() {
  if (!impl_) return;
  std::unique_ptr<Impl> p(std::exchange(impl_, nullptr));
  p->flush();  // the handles close as p goes, even if this throws
}

}  // namespace bagdem
