// results.h5 written by ResultsFile, read back with the plain HDF5 C API, and the XDMF index.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bagdem/error.hpp"
#include "bagdem/io/results_file.hpp"
#include "bagdem/energy.hpp"
#include "h5_read.hpp"

using namespace bagdem;
using bagdem::testing::Doubles;
using bagdem::testing::open_read;
using bagdem::testing::read_doubles;
using bagdem::testing::read_string_attribute;
using bagdem::testing::unit_of;
namespace fs = std::filesystem;

namespace {

// A fresh directory under the system temp dir, removed with everything in it.
struct TempDir {
  fs::path path;
  TempDir() {
    std::random_device rd;
    path = fs::temp_directory_path() / ("bagdem_results_" + std::to_string(rd()));
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

double read_double_attribute(hid_t obj, const std::string& name) {
  double v = -1;
  hid_t attr = H5Aopen(obj, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(attr, 0) << name;
  if (attr < 0) return v;
  EXPECT_GE(H5Aread(attr, H5T_NATIVE_DOUBLE, &v), 0);
  H5Aclose(attr);
  return v;
}

// Distinct, non-round values so that any misplaced element shows.
Vec3 v3(int frame, int i, int kind) {
  return Vec3(1.1 * frame + 0.01 * i + kind, -2.3 * frame + 0.1 * i,
              1e-3 * (frame + i) + kind / 7.0);
}
std::vector<Vec3> field(int frame, int kind) {
  return {v3(frame, 0, kind), v3(frame, 1, kind), v3(frame, 2, kind)};
}
EnergySample energy(int k) {
  return {0.5 + k, 1.0 / (k + 3), 2.0 * k, -0.25 * k, 0.1 * k, 0.2 * k, 0.3 * k + 1e-9, 0.7 * k};
}
const std::vector<double> kRadius{1e-3, 1.5e-3, 2.25e-3};
const std::vector<int> kMaterial{0, 1, 0};

}  // namespace

TEST(ResultsFileWrite, ValuesReadBackExactly) {
  TempDir dir;
  const std::string path = dir / "results.h5";
  {
    ResultsFile rf(path, kRadius, kMaterial, {"glass", "steel"}, 0.005);
    for (int f = 0; f < 2; ++f) rf.append_frame(0.1 * f, field(f, 0), field(f, 1), field(f, 2));
    for (int s = 0; s < 5; ++s)
      rf.append_cavity(0.005 * (s + 1), v3(s, 10, 0), v3(s, 11, 1), v3(s, 12, 2), v3(s, 13, 3), v3(s, 14, 4));
    for (int k = 0; k < 4; ++k) rf.append_energy(0.02 * k, energy(k).terms());
    const SeriesLengths len = rf.lengths();
    EXPECT_EQ(len.frames, 2u);
    EXPECT_EQ(len.cavity, 5u);
    EXPECT_EQ(len.energy, 4u);
  }  // destructor closes

  hid_t file = open_read(path);
  ASSERT_GE(file, 0);
  const Doubles radius = read_doubles(file, "/particles/radius");
  EXPECT_EQ(radius.values, kRadius);
  {
    hid_t ds = H5Dopen2(file, "/particles/material", H5P_DEFAULT);
    ASSERT_GE(ds, 0);
    hid_t type = H5Dget_type(ds);
    EXPECT_EQ(H5Tget_class(type), H5T_INTEGER);
    EXPECT_EQ(H5Tget_size(type), 4u);
    H5Tclose(type);
    std::vector<int> material(3, -1);
    EXPECT_GE(H5Dread(ds, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, material.data()), 0);
    EXPECT_EQ(material, kMaterial);
    EXPECT_EQ(read_string_attribute(ds, "materials"), "glass,steel");
    H5Dclose(ds);
  }

  EXPECT_EQ(read_doubles(file, "/frames/time").values, (std::vector<double>{0.0, 0.1}));
  const char* frame_sets[] = {"/frames/position", "/frames/velocity", "/frames/angular_velocity"};
  for (int kind = 0; kind < 3; ++kind) {
    const Doubles d = read_doubles(file, frame_sets[kind]);
    ASSERT_EQ(d.dims, (std::vector<hsize_t>{2, 3, 3})) << frame_sets[kind];
    for (int f = 0; f < 2; ++f)
      for (int i = 0; i < 3; ++i)
        for (int c = 0; c < 3; ++c)
          EXPECT_EQ(d.values[(f * 3 + i) * 3 + c], v3(f, i, kind)[c])
              << frame_sets[kind] << " f=" << f << " i=" << i << " c=" << c;
  }

  const Doubles ctime = read_doubles(file, "/cavity/time");
  ASSERT_EQ(ctime.dims, std::vector<hsize_t>{5});
  for (int s = 0; s < 5; ++s) EXPECT_EQ(ctime.values[s], 0.005 * (s + 1));
  const char* cavity_sets[] = {"/cavity/position", "/cavity/velocity", "/cavity/force",
                               "/cavity/torque", "/cavity/contents_velocity"};
  for (int kind = 0; kind < 5; ++kind) {
    const Doubles d = read_doubles(file, cavity_sets[kind]);
    ASSERT_EQ(d.dims, (std::vector<hsize_t>{5, 3})) << cavity_sets[kind];
    for (int s = 0; s < 5; ++s)
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(d.values[s * 3 + c], v3(s, 10 + kind, kind)[c])
            << cavity_sets[kind] << " s=" << s;
  }
  {
    hid_t g = H5Gopen2(file, "/cavity", H5P_DEFAULT);
    EXPECT_EQ(read_double_attribute(g, "interval"), 0.005);
    H5Gclose(g);
  }

  const Doubles etime = read_doubles(file, "/energy/time");
  ASSERT_EQ(etime.dims, std::vector<hsize_t>{4});
  for (int k = 0; k < 4; ++k) EXPECT_EQ(etime.values[k], 0.02 * k);
  const std::pair<const char*, double EnergySample::*> fields[] = {
      {"kinetic", &EnergySample::kinetic},
      {"elastic", &EnergySample::elastic},
      {"work_cavity", &EnergySample::work_cavity},
      {"work_gravity", &EnergySample::work_gravity},
      {"dissipated_normal", &EnergySample::dissipated_normal},
      {"dissipated_tangential", &EnergySample::dissipated_tangential},
      {"dissipated_rolling", &EnergySample::dissipated_rolling},
      {"dissipated_damping", &EnergySample::dissipated_damping}};
  for (const auto& [name, member] : fields) {
    const Doubles d = read_doubles(file, std::string("/energy/") + name);
    ASSERT_EQ(d.dims, std::vector<hsize_t>{4}) << name;
    for (int k = 0; k < 4; ++k) EXPECT_EQ(d.values[k], energy(k).*member) << name << " k=" << k;
  }

  EXPECT_EQ(read_string_attribute(file, "program_version"), BAGDEM_VERSION);
  H5Fclose(file);
}

TEST(ResultsFileWrite, SeriesAreChunkedExtendibleDoubles) {
  TempDir dir;
  const std::string path = dir / "results.h5";
  ResultsFile(path, kRadius, kMaterial, {"glass", "steel"}, 0.01).close();
  hid_t file = open_read(path);
  ASSERT_GE(file, 0);
  for (const char* name :
       {"/frames/time", "/frames/position", "/cavity/force", "/energy/kinetic"}) {
    hid_t ds = H5Dopen2(file, name, H5P_DEFAULT);
    ASSERT_GE(ds, 0) << name;
    hid_t space = H5Dget_space(ds), dcpl = H5Dget_create_plist(ds), type = H5Dget_type(ds);
    hsize_t dims[3], maxdims[3], chunk[3];
    const int rank = H5Sget_simple_extent_dims(space, dims, maxdims);
    EXPECT_EQ(dims[0], 0u) << name;
    EXPECT_EQ(maxdims[0], H5S_UNLIMITED) << name;
    EXPECT_EQ(H5Pget_layout(dcpl), H5D_CHUNKED) << name;
    EXPECT_EQ(H5Pget_chunk(dcpl, 3, chunk), rank) << name;
    if (rank == 3) {
      EXPECT_EQ(chunk[0], 1u) << "one frame per chunk";
    }
    EXPECT_TRUE(H5Tequal(type, H5T_IEEE_F64LE) > 0) << name;
    H5Tclose(type);
    H5Pclose(dcpl);
    H5Sclose(space);
    H5Dclose(ds);
  }
  H5Fclose(file);
}

TEST(ResultsFileWrite, EveryDatasetHasItsUnit) {
  TempDir dir;
  const std::string path = dir / "results.h5";
  ResultsFile(path, kRadius, kMaterial, {"glass"}, 0.01).close();
  hid_t file = open_read(path);
  ASSERT_GE(file, 0);
  const std::pair<const char*, const char*> expected[] = {{"/particles/radius", "m"},
                                                          {"/particles/material", "1"},
                                                          {"/frames/time", "s"},
                                                          {"/frames/position", "m"},
                                                          {"/frames/velocity", "m/s"},
                                                          {"/frames/angular_velocity", "rad/s"},
                                                          {"/cavity/time", "s"},
                                                          {"/cavity/position", "m"},
                                                          {"/cavity/velocity", "m/s"},
                                                          {"/cavity/force", "N"},
                                                          {"/cavity/torque", "N m"},
                                                          {"/cavity/contents_velocity", "m/s"},
                                                          {"/energy/time", "s"},
                                                          {"/energy/kinetic", "J"},
                                                          {"/energy/elastic", "J"},
                                                          {"/energy/work_cavity", "J"},
                                                          {"/energy/work_gravity", "J"},
                                                          {"/energy/dissipated_normal", "J"},
                                                          {"/energy/dissipated_tangential", "J"},
                                                          {"/energy/dissipated_rolling", "J"},
                                                          {"/energy/dissipated_damping", "J"}};
  for (const auto& [name, unit] : expected) EXPECT_EQ(unit_of(file, name), unit) << name;
  H5Fclose(file);
}

// The process dies without closing: the frame, and the cavity rows before it, are on disk.
TEST(ResultsFileDeathTest, KilledRunLeavesTheLastFrame) {
  TempDir dir;
  const std::string path = dir / "results.h5";
  EXPECT_EXIT(
      {
        ResultsFile rf(path, kRadius, kMaterial, {"glass"}, 0.01);
        rf.append_cavity(0.01, v3(0, 10, 0), v3(0, 11, 1), v3(0, 12, 2), v3(0, 13, 3), v3(0, 14, 4));
        rf.append_frame(0.5, field(0, 0), field(0, 1), field(0, 2));
        std::raise(SIGKILL);
      },
      ::testing::KilledBySignal(SIGKILL), "");
  hid_t file = open_read(path);
  ASSERT_GE(file, 0);
  EXPECT_EQ(read_doubles(file, "/frames/time").values, std::vector<double>{0.5});
  EXPECT_EQ(read_doubles(file, "/frames/angular_velocity").dims, (std::vector<hsize_t>{1, 3, 3}));
  EXPECT_EQ(read_doubles(file, "/cavity/time").values, std::vector<double>{0.01});
  H5Fclose(file);
}

TEST(ResultsFileReopen, TruncatesToLengthsAndContinues) {
  TempDir dir;
  const std::string path = dir / "results.h5";
  SeriesLengths checkpoint;  // 1 frame, 2 cavity samples, 3 energy rows, as a checkpoint records them
  {
    ResultsFile rf(path, kRadius, kMaterial, {"glass", "steel"}, 0.005);
    auto cavity = [&](int s) { rf.append_cavity(0.005 * (s + 1), v3(s, 10, 0), v3(s, 11, 1), v3(s, 12, 2), v3(s, 13, 3), v3(s, 14, 4)); };
    rf.append_frame(0, field(0, 0), field(0, 1), field(0, 2));
    for (int s = 0; s < 2; ++s) cavity(s);
    for (int k = 0; k < 3; ++k) rf.append_energy(0.02 * k, energy(k).terms());
    checkpoint = rf.lengths();
    for (int f = 1; f < 3; ++f) rf.append_frame(0.1 * f, field(f, 0), field(f, 1), field(f, 2));
    for (int s = 2; s < 5; ++s) cavity(s);
    for (int k = 3; k < 5; ++k) rf.append_energy(0.02 * k, energy(k).terms());
  }
  {
    ResultsFile rf = ResultsFile::reopen(path, checkpoint);
    EXPECT_EQ(rf.lengths().frames, 1u);
    EXPECT_EQ(rf.lengths().cavity, 2u);
    EXPECT_EQ(rf.lengths().energy, 3u);
    rf.append_cavity(42.0, v3(7, 20, 0), v3(7, 21, 1), v3(7, 22, 2), v3(7, 23, 3), v3(7, 24, 4));
    EXPECT_EQ(rf.lengths().cavity, 3u);
    rf.close();
    rf.close();  // idempotent
  }
  hid_t file = open_read(path);
  ASSERT_GE(file, 0);
  EXPECT_EQ(read_doubles(file, "/frames/time").dims, std::vector<hsize_t>{1});
  EXPECT_EQ(read_doubles(file, "/frames/velocity").dims, (std::vector<hsize_t>{1, 3, 3}));
  EXPECT_EQ(read_doubles(file, "/energy/dissipated_rolling").dims, std::vector<hsize_t>{3});
  EXPECT_EQ(read_doubles(file, "/cavity/time").values, (std::vector<double>{0.005, 0.01, 42.0}));
  const Doubles force = read_doubles(file, "/cavity/force");
  ASSERT_EQ(force.dims, (std::vector<hsize_t>{3, 3}));
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(force.values[1 * 3 + c], v3(1, 12, 2)[c]);  // kept from the first run
    EXPECT_EQ(force.values[2 * 3 + c], v3(7, 22, 2)[c]);  // appended after reopen
  }
  H5Fclose(file);
}

// A resume continues only from the data its checkpoint recorded: a value changed in the rows kept
// (a damaged or edited file) is refused, naming the file; the same lengths with the data intact
// are accepted.
TEST(ResultsFileReopen, RefusesDataThatDifferFromTheCheckpoints) {
  TempDir dir;
  const std::string path = dir / "results.h5";
  SeriesLengths checkpoint;
  {
    ResultsFile rf(path, kRadius, kMaterial, {"glass"}, 0.005);
    for (int f = 0; f < 2; ++f) rf.append_frame(0.1 * f, field(f, 0), field(f, 1), field(f, 2));
    rf.append_cavity(0.005, v3(0, 10, 0), v3(0, 11, 1), v3(0, 12, 2), v3(0, 13, 3), v3(0, 14, 4));
    rf.append_table_row("structure", {{"time", "s"}, {"displacement", "m"}}, {0.005, 1e-6});
    checkpoint = rf.lengths();
    rf.append_frame(0.2, field(2, 0), field(2, 1), field(2, 2));  // after the checkpoint: cut on reopening
  }
  { ResultsFile rf = ResultsFile::reopen(path, checkpoint); }
  for (const char* dataset : {"/frames/velocity", "/cavity/force", "/structure/displacement", "/particles/radius"}) {
    const std::string copy = dir / "copy.h5";
    std::filesystem::copy_file(path, copy, std::filesystem::copy_options::overwrite_existing);
    {  // one value of the rows kept changed in place
      const hid_t f = H5Fopen(copy.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
      const hid_t ds = H5Dopen2(f, dataset, H5P_DEFAULT);
      ASSERT_GE(ds, 0) << dataset;
      std::vector<double> v = read_doubles(f, dataset).values;
      v[0] += 1e-9;
      ASSERT_GE(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
      H5Dclose(ds);
      H5Fclose(f);
    }
    try {
      ResultsFile::reopen(copy, checkpoint);
      ADD_FAILURE() << dataset << " changed, yet the file was reopened";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(copy), std::string::npos) << m;
      EXPECT_NE(m.find("differ from those the checkpoint recorded"), std::string::npos) << m;
    }
  }
}

TEST(ResultsFileReopen, RefusesToGrowASeries) {
  TempDir dir;
  const std::string path = dir / "results.h5";
  ResultsFile(path, kRadius, kMaterial, {"glass"}, 0.01).close();
  EXPECT_THROW(ResultsFile::reopen(path, {0, 1, 0}), std::runtime_error);
}

TEST(ResultsFileErrors, MessageNamesThePath) {
  TempDir dir;
  const std::string path = dir / "no_such_dir/results.h5";
  try {
    ResultsFile::reopen(path, {});
    FAIL() << "reopen of a missing file did not throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_THROW(ResultsFile(path, kRadius, kMaterial, {"glass"}, 0.01), std::runtime_error);
}

TEST(ResultsFileAttributes, SetAttributeOverwrites) {
  TempDir dir;
  const std::string path = dir / "results.h5";
  SeriesLengths lengths;
  {
    ResultsFile rf(path, kRadius, kMaterial, {"glass"}, 0.01);
    lengths = rf.lengths();
    rf.set_attribute("status", "running");
    rf.set_attribute("settle_end", 0.25);
    rf.set_attribute("status", std::string("failed: ") + std::string(70000, 'x'));  // > 64 KiB
    rf.set_attribute("status", "complete");
    rf.set_attribute("settle_end", 0.5);
    rf.set_attribute("settle_end", "string now");  // the type may change too
  }
  hid_t file = open_read(path);
  ASSERT_GE(file, 0);
  EXPECT_EQ(read_string_attribute(file, "status"), "complete");
  EXPECT_EQ(read_string_attribute(file, "settle_end"), "string now");
  H5Fclose(file);

  ResultsFile rf = ResultsFile::reopen(path, lengths);
  rf.set_attribute("settle_end", 0.75);
  rf.close();
  file = open_read(path);
  ASSERT_GE(file, 0);
  EXPECT_EQ(read_double_attribute(file, "settle_end"), 0.75);
  H5Fclose(file);
}

TEST(ResultsFileMove, MoveTransfersOwnership) {
  TempDir dir;
  ResultsFile a(dir / "a.h5", kRadius, kMaterial, {"glass"}, 0.01);
  a.append_energy(0.0, energy(0).terms());
  ResultsFile b(std::move(a));
  EXPECT_EQ(a.lengths().energy, 0u);  // NOLINT(bugprone-use-after-move): moved-from is empty
  EXPECT_EQ(b.lengths().energy, 1u);
  ResultsFile c(dir / "c.h5", kRadius, kMaterial, {"glass"}, 0.01);
  c = std::move(b);  // closes c.h5, takes a.h5
  c.append_energy(1.0, energy(1).terms());
  c.close();
  hid_t file = open_read(dir / "a.h5");
  ASSERT_GE(file, 0);
  EXPECT_EQ(read_doubles(file, "/energy/time").values, (std::vector<double>{0.0, 1.0}));
  H5Fclose(file);
}

TEST(ResultsFileXdmf, TemporalCollectionOfHyperslabs) {
  TempDir dir;
  const std::string xmf = dir / "results.xmf";
  write_xdmf(xmf, "results.h5", 5, {0.0, 0.1, 0.25});  // N = 5, F = 3
  EXPECT_FALSE(fs::exists(xmf + ".part"));
  std::ifstream in(xmf);
  ASSERT_TRUE(in.good());
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  auto count = [&](const std::string& s) {
    std::size_t n = 0;
    for (std::size_t at = text.find(s); at != std::string::npos; at = text.find(s, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("<Grid "), 4u);  // the collection and one per frame
  EXPECT_EQ(count("CollectionType=\"Temporal\""), 1u);
  EXPECT_EQ(count("TopologyType=\"Polyvertex\" NumberOfElements=\"5\""), 3u);
  EXPECT_EQ(count("<Time Value=\"0.25\"/>"), 1u);
  EXPECT_EQ(count("ItemType=\"HyperSlab\""), 9u);  // position, velocity, angular_velocity × 3
  EXPECT_EQ(count(">2 0 0 1 1 1 1 5 3</DataItem>"), 3u);  // start f 0 0, stride 1 1 1, count 1 N 3
  EXPECT_EQ(count("HyperSlab\" Dimensions=\"1 5 3\""), 9u);  // the selected frame
  EXPECT_EQ(count("Dimensions=\"3 5 3\""), 9u);              // the [F N 3] dataset
  EXPECT_EQ(count("results.h5:/frames/position"), 3u);
  EXPECT_EQ(count("results.h5:/frames/angular_velocity"), 3u);
  EXPECT_EQ(
      count("NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">results.h5:/particles/material"),
      3u);
  EXPECT_EQ(count("results.h5:/particles/radius"), 3u);
}
