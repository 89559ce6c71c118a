// The bag's film on disk: bag.h5 (save_bag / load_bag), the /film datasets of results.h5 and the
// film grid of the XDMF index. Files are read back with the plain HDF5 C API.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bagdem/error.hpp"
#include "bagdem/io/bag_file.hpp"
#include "bagdem/io/results_file.hpp"
#include "h5_read.hpp"
#include "support.hpp"

using namespace bagdem;
using bagdem::testing::Doubles;
using bagdem::testing::Ints;
using bagdem::testing::open_read;
using bagdem::testing::read_doubles;
using bagdem::testing::read_ints;
using bagdem::testing::TempDir;
using bagdem::testing::unit_of;
namespace fs = std::filesystem;

namespace {

std::string at(const TempDir& dir, const std::string& name) { return (dir.path / name).string(); }

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::size_t count(const std::string& text, const std::string& s) {
  std::size_t n = 0;
  for (std::size_t i = text.find(s); i != std::string::npos; i = text.find(s, i + 1)) ++n;
  return n;
}

// Replaces dataset `name` by a [rows, 3] double dataset of zeros (to damage a saved bag).
void replace_points(const std::string& path, const std::string& name, hsize_t rows) {
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  ASSERT_GE(H5Ldelete(f, name.c_str(), H5P_DEFAULT), 0);
  const hsize_t dims[2] = {rows, 3};
  hid_t space = H5Screate_simple(2, dims, nullptr);
  hid_t ds = H5Dcreate2(f, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT,
                        H5P_DEFAULT);
  ASSERT_GE(ds, 0);
  const std::vector<double> zeros(rows * 3, 0.0);
  if (rows > 0) {
    ASSERT_GE(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, zeros.data()), 0);
  }
  H5Dclose(ds);
  H5Sclose(space);
  H5Fclose(f);
}

// Distinct, non-round values so that any misplaced element shows.
Vec3 node(int frame, int i) {
  return Vec3(0.1 * frame + 1e-3 * i + 1.0 / 3.0, -0.7 * frame + 0.013 * i, 1e-5 * (i + 1) + frame / 7.0);
}
std::vector<Vec3> film_frame(int frame, int nodes) {
  std::vector<Vec3> x;
  for (int i = 0; i < nodes; ++i) x.push_back(node(frame, i));
  return x;
}

// A tetrahedron: 4 nodes, 4 outward triangles.
const std::vector<std::array<std::uint32_t, 3>> kTet{{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};

SavedBag sample_bag() {
  SavedBag b;
  b.rest.vertices = {Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0, 0.1, 0), Vec3(0, 0, 0.1)};
  b.rest.triangles = kTet;
  b.film_position = film_frame(3, 4);
  b.ball_position = {Vec3(0.01, 0.02, 0.03), Vec3(1.0 / 3.0, -2.0 / 7.0, 1e-17)};
  b.ball_radius = {2.5e-3, 2.5e-3 + 1e-12};
  b.shape = "pillow \xc3\xa9";  // UTF-8 survives
  b.axis = Vec3(0, 0, 1);
  b.side = Vec3(1.0 / 3.0, 2.0 / 3.0, -2.0 / 3.0);
  b.size = Vec3(0.12, 0.08, 0.0325);
  b.fill_fraction = 0.4321;
  b.film_thickness = 5e-5;
  return b;
}

const std::vector<double> kRadius{1e-3, 1.5e-3};
const std::vector<int> kMaterial{0, 0};
std::vector<Vec3> balls(int frame) { return {Vec3(frame, 0, 0), Vec3(0, frame, 1)}; }

// results.h5 with 3 frames (times 0, 0.1, 0.2) of two balls and the tetrahedron's film.
// Returns the lengths after two frames (what a checkpoint then would record).
SeriesLengths write_three_frames(const std::string& path) {
  ResultsFile rf(path, kRadius, kMaterial, {"steel"}, 0.01);
  rf.write_film(kTet, 4);
  SeriesLengths two;
  for (int f = 0; f < 3; ++f) {
    rf.append_frame(0.1 * f, balls(f), balls(f), balls(f));
    rf.append_film_frame(film_frame(f, 4));
    if (f == 1) two = rf.lengths();
  }
  return two;
}

// ---- bag.h5 ---------------------------------------------------------------------------------

TEST(BagFile, RoundTripIsExact) {
  TempDir dir;
  const std::string path = at(dir, "bag.h5");
  const SavedBag b = sample_bag();
  save_bag(path, b);
  EXPECT_TRUE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".part"));
  const SavedBag l = load_bag(path);
  EXPECT_EQ(l.rest.vertices, b.rest.vertices);
  EXPECT_EQ(l.rest.triangles, b.rest.triangles);
  EXPECT_TRUE(l.rest.edge_vertices.empty());  // topology is not built
  EXPECT_EQ(l.film_position, b.film_position);
  EXPECT_EQ(l.ball_position, b.ball_position);
  EXPECT_EQ(l.ball_radius, b.ball_radius);
  EXPECT_EQ(l.shape, b.shape);
  EXPECT_EQ(l.axis, b.axis);
  EXPECT_EQ(l.side, b.side);
  EXPECT_EQ(l.size, b.size);
  EXPECT_EQ(l.fill_fraction, b.fill_fraction);
  EXPECT_EQ(l.film_thickness, b.film_thickness);
}

TEST(BagFile, LayoutAndUnitsAsDocumented) {
  TempDir dir;
  const std::string path = at(dir, "bag.h5");
  save_bag(path, sample_bag());
  hid_t file = open_read(path);
  ASSERT_GE(file, 0);
  EXPECT_EQ(read_doubles(file, "/film/rest").dims, (std::vector<hsize_t>{4, 3}));
  EXPECT_EQ(read_doubles(file, "/film/position").dims, (std::vector<hsize_t>{4, 3}));
  const Ints tri = read_ints(file, "/film/triangles");
  EXPECT_TRUE(tri.int32);
  EXPECT_EQ(tri.dims, (std::vector<hsize_t>{4, 3}));
  EXPECT_EQ(tri.values, (std::vector<std::int32_t>{0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2}));
  EXPECT_EQ(read_doubles(file, "/balls/position").dims, (std::vector<hsize_t>{2, 3}));
  EXPECT_EQ(read_doubles(file, "/balls/radius").dims, (std::vector<hsize_t>{2}));
  for (const char* name : {"/film/rest", "/film/position", "/balls/position", "/balls/radius"})
    EXPECT_EQ(unit_of(file, name), "m") << name;
  for (const char* name : {"shape", "axis", "side", "size", "fill_fraction", "film_thickness",
                           "program_version"})
    EXPECT_GT(H5Aexists(file, name), 0) << name;
  H5Fclose(file);
}

TEST(BagFile, SaveReplacesAnOldFile) {
  TempDir dir;
  const std::string path = at(dir, "bag.h5");
  SavedBag b = sample_bag();
  save_bag(path, b);
  b.fill_fraction = 0.25;
  b.ball_position.pop_back();
  b.ball_radius.pop_back();
  save_bag(path, b);
  const SavedBag l = load_bag(path);
  EXPECT_EQ(l.fill_fraction, 0.25);
  EXPECT_EQ(l.ball_position.size(), 1u);
}

TEST(BagFile, SaveRefusesInconsistentShapes) {
  TempDir dir;
  SavedBag b = sample_bag();
  b.film_position.pop_back();
  EXPECT_THROW(save_bag(at(dir, "a.h5"), b), std::invalid_argument);
  b = sample_bag();
  b.rest.triangles.push_back({0, 1, 4});
  EXPECT_THROW(save_bag(at(dir, "b.h5"), b), std::invalid_argument);
  EXPECT_FALSE(fs::exists(at(dir, "a.h5")));
  EXPECT_FALSE(fs::exists(at(dir, "b.h5.part")));
}

TEST(BagFile, MissingFileIsAnInputErrorNamingIt) {
  TempDir dir;
  const std::string path = at(dir, "no_such_bag.h5");
  try {
    load_bag(path);
    FAIL() << "loading a missing file did not throw";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find("bagdem run"), std::string::npos) << m;  // says how to make one
  }
}

TEST(BagFile, NotHdf5IsAnInputError) {
  TempDir dir;
  dir.write("bag.h5", "this is text, not HDF5\n");
  const std::string path = at(dir, "bag.h5");
  try {
    load_bag(path);
    FAIL() << "loading a text file did not throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(BagFile, ResultsFileIsNotABag) {
  TempDir dir;
  const std::string path = at(dir, "results.h5");
  write_three_frames(path);  // has /film/position and /film/triangles, but no /film/rest
  try {
    load_bag(path);
    FAIL() << "loading a results file as a bag did not throw";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find("not a saved bag"), std::string::npos) << m;
    EXPECT_NE(m.find("/film/rest"), std::string::npos) << m;
  }
}

TEST(BagFile, InconsistentFileIsAnInputError) {
  TempDir dir;
  const std::string path = at(dir, "bag.h5");
  save_bag(path, sample_bag());
  replace_points(path, "/film/position", 3);  // the rest shape has 4 vertices
  try {
    load_bag(path);
    FAIL() << "a film with 3 positions for 4 rest vertices was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find("/film/position"), std::string::npos) << m;
  }
  // Triangles index vertex 3, but the rest shape now has only 3 (positions 3 too).
  save_bag(path, sample_bag());
  replace_points(path, "/film/rest", 3);
  replace_points(path, "/film/position", 3);
  try {
    load_bag(path);
    FAIL() << "a triangle index beyond the vertices was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/film/triangles"), std::string::npos) << e.what();
  }
}

// ---- results.h5 /film -----------------------------------------------------------------------

TEST(ResultsFileFilm, FramesReadBackExactly) {
  TempDir dir;
  const std::string path = at(dir, "results.h5");
  write_three_frames(path);
  hid_t file = open_read(path);
  ASSERT_GE(file, 0);
  const Doubles pos = read_doubles(file, "/film/position");
  ASSERT_EQ(pos.dims, (std::vector<hsize_t>{3, 4, 3}));
  for (int f = 0; f < 3; ++f)
    for (int i = 0; i < 4; ++i)
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(pos.values[(f * 4 + i) * 3 + c], node(f, i)[c]) << f << ' ' << i << ' ' << c;
  EXPECT_EQ(read_doubles(file, "/frames/time").dims, std::vector<hsize_t>{3});
  const Ints tri = read_ints(file, "/film/triangles");
  EXPECT_TRUE(tri.int32);
  ASSERT_EQ(tri.dims, (std::vector<hsize_t>{4, 3}));
  for (std::size_t t = 0; t < kTet.size(); ++t)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(tri.values[t * 3 + c], std::int32_t(kTet[t][c]));
  EXPECT_EQ(unit_of(file, "/film/position"), "m");
  EXPECT_EQ(unit_of(file, "/film/triangles"), "1");
  H5Fclose(file);
}

TEST(ResultsFileFilm, ReopenTruncatesTheFilm) {
  TempDir dir;
  const std::string path = at(dir, "results.h5");
  const SeriesLengths two = write_three_frames(path);
  ASSERT_EQ(two.frames, 2u);
  SeriesLengths again;  // after the frame appended on reopening
  {
    ResultsFile rf = ResultsFile::reopen(path, two);
    rf.write_film(kTet, 4);  // the same film: accepted, nothing rewritten
    rf.append_frame(0.15, balls(7), balls(7), balls(7));
    rf.append_film_frame(film_frame(7, 4));
    again = rf.lengths();
  }
  hid_t file = open_read(path);
  ASSERT_GE(file, 0);
  const Doubles pos = read_doubles(file, "/film/position");
  ASSERT_EQ(pos.dims, (std::vector<hsize_t>{3, 4, 3}));
  EXPECT_EQ(pos.values[(1 * 4 + 2) * 3 + 1], node(1, 2)[1]);  // kept from the first run
  EXPECT_EQ(pos.values[(2 * 4 + 3) * 3 + 0], node(7, 3)[0]);  // appended after reopen
  EXPECT_EQ(read_doubles(file, "/frames/time").values, (std::vector<double>{0.0, 0.1, 0.15}));
  H5Fclose(file);

  EXPECT_EQ(again.frames, 3u);
  { ResultsFile rf = ResultsFile::reopen(path, two); }  // the first two frames are still those checkpointed
  file = open_read(path);
  ASSERT_GE(file, 0);
  EXPECT_EQ(read_doubles(file, "/film/position").dims, (std::vector<hsize_t>{2, 4, 3}));
  EXPECT_EQ(read_doubles(file, "/frames/position").dims, (std::vector<hsize_t>{2, 2, 3}));
  EXPECT_EQ(read_ints(file, "/film/triangles").dims, (std::vector<hsize_t>{4, 3}));
  H5Fclose(file);
}

TEST(ResultsFileFilm, NoFilmNoGroup) {
  TempDir dir;
  const std::string path = at(dir, "results.h5");
  SeriesLengths one;
  {
    ResultsFile rf(path, kRadius, kMaterial, {"steel"}, 0.01);
    rf.append_frame(0.0, balls(0), balls(0), balls(0));
    EXPECT_THROW(rf.append_film_frame(film_frame(0, 4)), std::logic_error);
    EXPECT_THROW(rf.write_film(kTet, 4), std::logic_error);  // too late: a frame has no film
    one = rf.lengths();
  }
  { ResultsFile rf = ResultsFile::reopen(path, one); }  // no /film to truncate
  hid_t file = open_read(path);
  ASSERT_GE(file, 0);
  EXPECT_EQ(H5Lexists(file, "film", H5P_DEFAULT), 0);
  H5Fclose(file);
}

TEST(ResultsFileFilm, MisuseThrows) {
  TempDir dir;
  ResultsFile rf(at(dir, "results.h5"), kRadius, kMaterial, {"steel"}, 0.01);
  EXPECT_THROW(rf.write_film({{0, 1, 4}}, 4), std::invalid_argument);  // node 4 of 4
  rf.write_film(kTet, 4);
  EXPECT_THROW(rf.write_film(kTet, 5), std::invalid_argument);  // another film
  EXPECT_THROW(rf.append_film_frame(film_frame(0, 4)), std::logic_error);  // no frame yet
  rf.append_frame(0.0, balls(0), balls(0), balls(0));
  EXPECT_THROW(rf.append_film_frame(film_frame(0, 3)), std::invalid_argument);  // 3 nodes of 4
  EXPECT_THROW(rf.append_frame(0.1, balls(1), balls(1), balls(1)), std::logic_error);  // no film
  rf.append_film_frame(film_frame(0, 4));
  EXPECT_THROW(rf.append_film_frame(film_frame(0, 4)), std::logic_error);  // twice
  EXPECT_EQ(rf.lengths().frames, 1u);
}

// ---- XDMF -----------------------------------------------------------------------------------

TEST(ResultsXdmfFilm, TriangleGridPerFrame) {
  TempDir dir;
  const std::string xmf = at(dir, "results.xmf");
  write_xdmf(xmf, "results.h5", 5, {0.0, 0.1, 0.25}, 7, 10);  // N = 5, V = 7, T = 10, F = 3
  const std::string text = read_text(xmf);
  EXPECT_EQ(count(text, "<Grid "), 10u);  // the temporal collection, and per frame 3 grids
  EXPECT_EQ(count(text, "CollectionType=\"Temporal\""), 1u);
  EXPECT_EQ(count(text, "CollectionType=\"Spatial\""), 3u);
  EXPECT_EQ(count(text, "<Time "), 3u);  // one per time step
  EXPECT_EQ(count(text, "<Time Value=\"0.25\"/>"), 1u);
  EXPECT_EQ(count(text, "<Grid Name=\"particles\" GridType=\"Uniform\">"), 3u);
  EXPECT_EQ(count(text, "<Grid Name=\"film\" GridType=\"Uniform\">"), 3u);
  EXPECT_EQ(count(text, "TopologyType=\"Polyvertex\" NumberOfElements=\"5\""), 3u);
  EXPECT_EQ(count(text, "TopologyType=\"Triangle\" NumberOfElements=\"10\""), 3u);
  EXPECT_EQ(count(text, "Dimensions=\"10 3\" NumberType=\"Int\" Precision=\"4\" "
                        "Format=\"HDF\">results.h5:/film/triangles</DataItem>"),
            3u);
  EXPECT_EQ(count(text, "results.h5:/film/position"), 3u);
  EXPECT_EQ(count(text, "HyperSlab\" Dimensions=\"1 7 3\""), 3u);  // the film at one frame
  EXPECT_EQ(count(text, ">2 0 0 1 1 1 1 7 3</DataItem>"), 1u);    // frame 2 of [3 7 3]
  EXPECT_EQ(count(text, "Dimensions=\"3 7 3\""), 3u);
  EXPECT_EQ(count(text, ">0 0 1 1 10 3</DataItem>"), 3u);  // all the triangles, as a hyperslab
  EXPECT_EQ(count(text, "ItemType=\"HyperSlab\""), 15u);  // 3 particle fields + film's 2, 3 frames
  EXPECT_EQ(count(text, "results.h5:/frames/position"), 3u);
  EXPECT_EQ(count(text, "results.h5:/particles/radius"), 3u);
  // Every grid element that opens is closed.
  EXPECT_EQ(count(text, "<Grid "), count(text, "</Grid>"));
}

TEST(ResultsXdmfFilm, WithoutFilmUnchanged) {
  TempDir dir;
  const std::string a = at(dir, "a.xmf"), b = at(dir, "b.xmf");
  write_xdmf(a, "results.h5", 2, {0.5});
  write_xdmf(b, "results.h5", 2, {0.5}, 0, 0);
  const std::string text = read_text(a);
  EXPECT_EQ(read_text(b), text);
  const std::string expected =
      "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n"
      "    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n"
      "      <Grid Name=\"frame 0\" GridType=\"Uniform\">\n"
      "        <Time Value=\"0.5\"/>\n"
      "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"2\"/>\n"
      "        <Geometry GeometryType=\"XYZ\">\n"
      "          <DataItem ItemType=\"HyperSlab\" Dimensions=\"1 2 3\">\n"
      "            <DataItem Dimensions=\"3 3\" Format=\"XML\">0 0 0 1 1 1 1 2 3</DataItem>\n"
      "            <DataItem Dimensions=\"1 2 3\" NumberType=\"Float\" Precision=\"8\" "
      "Format=\"HDF\">results.h5:/frames/position</DataItem>\n"
      "          </DataItem>\n"
      "        </Geometry>\n"
      "        <Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Node\">\n"
      "          <DataItem ItemType=\"HyperSlab\" Dimensions=\"1 2 3\">\n"
      "            <DataItem Dimensions=\"3 3\" Format=\"XML\">0 0 0 1 1 1 1 2 3</DataItem>\n"
      "            <DataItem Dimensions=\"1 2 3\" NumberType=\"Float\" Precision=\"8\" "
      "Format=\"HDF\">results.h5:/frames/velocity</DataItem>\n"
      "          </DataItem>\n"
      "        </Attribute>\n"
      "        <Attribute Name=\"angular_velocity\" AttributeType=\"Vector\" Center=\"Node\">\n"
      "          <DataItem ItemType=\"HyperSlab\" Dimensions=\"1 2 3\">\n"
      "            <DataItem Dimensions=\"3 3\" Format=\"XML\">0 0 0 1 1 1 1 2 3</DataItem>\n"
      "            <DataItem Dimensions=\"1 2 3\" NumberType=\"Float\" Precision=\"8\" "
      "Format=\"HDF\">results.h5:/frames/angular_velocity</DataItem>\n"
      "          </DataItem>\n"
      "        </Attribute>\n"
      "        <Attribute Name=\"radius\" AttributeType=\"Scalar\" Center=\"Node\">\n"
      "          <DataItem Dimensions=\"2\" NumberType=\"Float\" Precision=\"8\" "
      "Format=\"HDF\">results.h5:/particles/radius</DataItem>\n"
      "        </Attribute>\n"
      "        <Attribute Name=\"material\" AttributeType=\"Scalar\" Center=\"Node\">\n"
      "          <DataItem Dimensions=\"2\" NumberType=\"Int\" Precision=\"4\" "
      "Format=\"HDF\">results.h5:/particles/material</DataItem>\n"
      "        </Attribute>\n"
      "      </Grid>\n"
      "    </Grid>\n  </Domain>\n</Xdmf>\n";
  EXPECT_EQ(text, expected);
  EXPECT_EQ(count(text, "film"), 0u);
  EXPECT_EQ(count(text, "Spatial"), 0u);
}

TEST(ResultsXdmfFilm, FilmNeedsNodesAndTriangles) {
  TempDir dir;
  EXPECT_THROW(write_xdmf(at(dir, "r.xmf"), "results.h5", 2, {0.0}, 4, 0), std::invalid_argument);
}

}  // namespace
