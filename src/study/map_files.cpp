// The effective-field map's files (study/characterize.hpp, write_map): map.csv (through
// reduce/map_table.hpp, which predict and design read it back with), map.json, map.h5.
// Each figure is given by its mean over the starts and the half-width of its 95% interval; the
// columns are documented in docs/characterize.md.
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "../io/h5.hpp"
#include "bagdem/io/atomic_file.hpp"
#include "bagdem/io/json.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/study/characterize.hpp"
#include "bagdem/study/damper_record.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;

namespace {

// [[row of amplitude 0], [row of amplitude 1], ...] of a value per cell (cells Gamma-major).
template <class F>
std::string json_rows(const MapPlan& g, const std::vector<MapCell>& cells, F value) {
  std::string s = "[";
  for (std::size_t i = 0; i < g.axes.gamma.size(); ++i) {
    s += i ? ", [" : "[";
    for (std::size_t j = 0; j < g.axes.frequency.size(); ++j) s += (j ? ", " : "") + json_number_text(value(cells[i * g.axes.frequency.size() + j]), 12);
    s += "]";
  }
  return s + "]";
}


void write_json(const fs::path& path, const MapPlan& g, const std::vector<MapCell>& cells, const std::string& case_dir) {
  std::ostringstream s;
  s.precision(12);
  s << "{\n  \"case\": \"" << json_escape(case_dir) << "\",\n";
  s << "  \"direction\": [" << g.direction.x() << ", " << g.direction.y() << ", " << g.direction.z() << "],\n";
  s << "  \"g\": {\"value\": " << g.axes.g << ", \"unit\": \"m/s^2\"},\n";
  auto list = [](const std::vector<double>& v) {
    std::string t = "[";
    for (std::size_t k = 0; k < v.size(); ++k) t += (k ? ", " : "") + json_number_text(v[k], 12);
    return t + "]";
  };
  s << "  \"gamma\": {\"values\": " << list(g.axes.gamma) << ", \"unit\": \"1\"},\n";
  s << "  \"frequency\": {\"values\": " << list(g.axes.frequency) << ", \"unit\": \"Hz\"},\n";
  s << "  \"amplitude\": {\"values\": " << json_rows(g, cells, [](const MapCell& c) { return c.amplitude; }) << ", \"unit\": \"m\"},\n";
  s << "  \"starts\": " << json_rows(g, cells, [](const MapCell& c) { return double(c.starts); }) << ",\n";
  s << "  \"steady_starts\": " << json_rows(g, cells, [](const MapCell& c) { return double(c.steady); }) << ",\n";
  s << "  \"e_starts\": " << json_rows(g, cells, [](const MapCell& c) { return double(c.e_starts); }) << ",\n";
  s << "  \"e_method\": [";
  for (std::size_t i = 0; i < g.axes.gamma.size(); ++i) {
    s << (i ? ", [" : "[");
    for (std::size_t j = 0; j < g.axes.frequency.size(); ++j) s << (j ? ", " : "") << '"' << json_escape(cells[i * g.axes.frequency.size() + j].e_method) << '"';
    s << "]";
  }
  s << "],\n";
  s << "  \"figures\": {";
  bool first = true;
  for (const MapFigure& f : map_figures()) {
    s << (first ? "\n" : ",\n") << "    \"" << f.name << "\": {\"unit\": \"" << json_escape(f.unit) << "\", \"mean\": "
      << json_rows(g, cells, [&](const MapCell& c) { return (c.*f.field).mean; })
      << ", \"ci95\": " << json_rows(g, cells, [&](const MapCell& c) { return (c.*f.field).ci95; }) << "}";
    first = false;
  }
  s << "\n  }\n}\n";
  write_atomically(path, s.str());
}

void write_h5(const fs::path& path, const MapPlan& g, const std::vector<MapCell>& cells, const std::string& case_dir) {
  const std::string tmp = path.string() + ".part";
  const h5::Check ok = h5::Check::with_prefix("map.h5: ");
  {
    h5::H5 file(ok(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "cannot create " + tmp), H5Fclose);
    h5::write_attribute(file, "case", case_dir, ok);
    h5::write_attribute(file, "direction", g.direction.data(), 3, ok);
    h5::write_attribute(file, "g", g.axes.g, ok);
    const hsize_t na = g.axes.gamma.size(), nf = g.axes.frequency.size();
    h5::write_dataset(file, "gamma", {na}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, g.axes.gamma.data(), "1", ok);
    h5::write_dataset(file, "frequency", {nf}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, g.axes.frequency.data(), "Hz", ok);
    auto grid_of = [&](auto value) {
      std::vector<double> v;
      for (const MapCell& c : cells) v.push_back(value(c));
      return v;
    };
    auto put = [&](hid_t where, const std::string& name, const std::vector<double>& v, const std::string& unit) {
      h5::write_dataset(where, name, {na, nf}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data(), unit, ok);
    };
    put(file, "amplitude", grid_of([](const MapCell& c) { return c.amplitude; }), "m");
    put(file, "starts", grid_of([](const MapCell& c) { return double(c.starts); }), "1");
    put(file, "steady_starts", grid_of([](const MapCell& c) { return double(c.steady); }), "1");
    put(file, "e_starts", grid_of([](const MapCell& c) { return double(c.e_starts); }), "1");
    std::vector<std::string> methods;  // Gamma-major, as the grids' rows
    for (const MapCell& c : cells) methods.push_back(c.e_method);
    h5::write_strings(file, "e_method", methods, ok);
    for (const MapFigure& f : map_figures()) {
      h5::H5 group = h5::create_group(file, f.name, ok, true);
      put(group, "mean", grid_of([&](const MapCell& c) { return (c.*f.field).mean; }), f.unit);
      put(group, "ci95", grid_of([&](const MapCell& c) { return (c.*f.field).ci95; }), f.unit);
    }
    h5::close_file(file, ok, "cannot write " + tmp);
  }
  fs::rename(tmp, path);
}

}  // namespace

void write_map(const std::string& out_dir, const MapPlan& grid, const std::vector<MapCell>& cells, const std::string& case_dir) {
  const fs::path out(out_dir);
  // The map's files, then damper.toml (with map.csv's fingerprint), then the files take their names:
  // a map.csv is never without the record of its damper; stopped between, the record refuses the
  // map.csv there (an earlier one), and characterize run again writes them all.
  write_map_csv(out / "map.csv.new", cells);
  write_json(out / "map.json.new", grid, cells, case_dir);
  write_h5(out / "map.h5.new", grid, cells, case_dir);
  write_damper_record(out / "damper.toml", grid.damper, MapRecord{file_print(out / "map.csv.new"), grid.bands});
  for (const char* name : {"map.csv", "map.json", "map.h5"}) fs::rename(out / (std::string(name) + ".new"), out / name);
}

}  // namespace bagdem::study
