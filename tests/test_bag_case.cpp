// The [bag] section end to end (docs/case-schema.md [bag]; src/case/bag.cpp): filling the bag
// (determinism, no overlaps, balls inside and clear of the film, count / mass / mass_ratio, a bag
// too small refused), what `bagdem check` reports, the settled bag saved and reused (bag.from), the
// film in results.h5 and results.xmf, thread-count determinism of the film's parallel paths, and
// save_state / load_state with a bag.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "bag_support.hpp"
#include "h5_read.hpp"
#include "bagdem/reduce/summary.hpp"
#include "bagdem/parallel.hpp"
#include "bagdem/contact/sphere_triangle.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/bag_file.hpp"
#include "bagdem/mesh/triangle_mesh.hpp"
#include "bagdem/particles.hpp"

using namespace bagdem;
using namespace bagdem::testing;
namespace fs = std::filesystem;

namespace {

// A small bag case: 2 GPa steel balls of 4 mm in an LDPE film (50 um, 200 triangles), tied by two
// strings to the end walls of a box shaken along the bag's axis (1 mm, 30 Hz, phase pi/2 so that the
// cavity's rest position is 1 mm along x, not the origin); `shape` are the [bag] shape keys, `balls`
// the [bag.balls] keys beside material and diameter.
const CaseText::Keys kCapsule = {{"shape", quoted("capsule")}, {"axis", "[1, 0, 0]"}, {"radius", "7 mm"}};
const CaseText::Keys kPillow = {{"shape", quoted("pillow")}, {"axis", "[1, 0, 0]"}, {"aspect", "[2.5, 1.2, 1]"}, {"exponent", 4}};

CaseText bag_case(const CaseText::Keys& shape, const CaseText::Keys& balls = {{"count", 30}}) {
  return bag_scene("0.004 s", 4)
      .interactions("steel-ldpe", 0.3, 0.4)
      .box("steel", vec("-25 mm", "-12 mm", "-12 mm"), vec("25 mm", "12 mm", "12 mm"))
      .harmonic("1 mm", "30 Hz", "[1, 0, 0]")
      .set("cavity.motion", "phase", "1.5707963267948966")
      .set("bag", "triangles", 200)
      .set("bag", shape)
      .set("bag.balls", {{"material", quoted("steel")}, {"diameter", "4 mm"}})
      .set("bag.balls", balls)
      .set("bag.film", {{"material", quoted("ldpe")}, {"thickness", "50 um"}})
      .bag_string("tail", vec("-25 mm", 0, 0), "200 N/m", "0.01 N s/m")
      .bag_string("head", vec("25 mm", 0, 0), "200 N/m", "0.01 N s/m")
      .output("frame_interval", "1 ms");
}

std::vector<Vec3> positions(const Scene& s) {
  std::vector<Vec3> x;
  for (const ParticleInit& p : s.particles) x.push_back(p.x);
  return x;
}

// Distance from p to the nearest film triangle (node positions x) (unit: m).
double film_distance(const TriangleMesh& mesh, const std::vector<Vec3>& x, const Vec3& p) {
  double d2 = 1e300;
  for (const auto& t : mesh.triangles) d2 = std::min(d2, closest_point_on_triangle(p, x[t[0]], x[t[1]], x[t[2]]).distance2);
  return std::sqrt(d2);
}

}  // namespace

// ---- 7. filling ---------------------------------------------------------------------------------------

// For both shapes: the same seed gives bitwise the same balls and film; another bag.balls.seed gives
// other positions; no two balls overlap (centre distance >= r_i + r_j, exact); every ball is inside
// the film (generalized winding number > 0.5) and clear of it by at least its radius plus the film's
// half thickness (src/case/bag.cpp lattice_sites: r + t/2 + 2% of r); the bag's balls are the last
// N particles and N is the count asked for.
TEST(BagFill, DeterministicInsideAndClear) {
  for (const CaseText::Keys& shape : {kCapsule, kPillow}) {
    SCOPED_TRACE(shape[0].second.toml);
    LoadedCase a(bag_case(shape)), b(bag_case(shape)), other(bag_case(shape), {"bag.balls.seed=99"});
    const Scene& s = a.scene;
    ASSERT_TRUE(s.bag);
    const Bag& bag = *s.bag;
    EXPECT_EQ(bag.balls, 30u);
    EXPECT_EQ(bag.ball_first + bag.balls, s.particles.size());
    EXPECT_TRUE(same_bits(positions(a.scene), positions(b.scene))) << "same seed, different balls";
    EXPECT_TRUE(same_bits(bag.x0, b.scene.bag->x0)) << "same seed, different film";
    EXPECT_TRUE(same_bits(bag.rest.vertices, b.scene.bag->rest.vertices));
    EXPECT_FALSE(same_bits(positions(a.scene), positions(other.scene))) << "bag.balls.seed had no effect";
    const double reach = 0.5 * bag.film.thickness;
    double closest_pair = 1e300, least_clearance = 1e300, least_winding = 1e300;
    for (std::size_t i = bag.ball_first; i < s.particles.size(); ++i) {
      const ParticleInit& p = s.particles[i];
      for (std::size_t j = i + 1; j < s.particles.size(); ++j) {
        const double gap = (p.x - s.particles[j].x).norm() - p.radius - s.particles[j].radius;
        closest_pair = std::min(closest_pair, gap);
        EXPECT_GE(gap, 0.0) << "balls " << i << " and " << j << " overlap";
      }
      const double wn = winding_number(bag.rest, bag.x0, p.x);
      least_winding = std::min(least_winding, wn);
      EXPECT_GT(wn, 0.5) << "ball " << i << " outside the film";
      const double clearance = film_distance(bag.rest, bag.x0, p.x) - p.radius - reach;
      least_clearance = std::min(least_clearance, clearance);
      EXPECT_GE(clearance, 0.0) << "ball " << i << " closer to the film than its radius + t/2";
    }
    std::printf("BagFill: %s: %zu balls, %zu triangles, fill fraction %.3f, outer %.2f x %.2f x %.2f mm; closest pair gap "
                "%.3g m, least film clearance beyond r + t/2 %.3g m, least winding number %.4f\n",
                bag.shape.c_str(), bag.balls, bag.rest.triangles.size(), bag.fill_fraction, 1e3 * bag.size.x(),
                1e3 * bag.size.y(), 1e3 * bag.size.z(), closest_pair, least_clearance, least_winding);
  }
}

// count / mass / mass_ratio + primary_mass: N = round(mass / ball mass) (src/case/bag.cpp
// ball_count). Ball mass m = 7800 x 4/3 pi (2 mm)^3. mass = 23.4 m and 23.6 m give 23 and 24;
// mass_ratio 0.05 with primary_mass = 20.2 m / 0.05 gives 20. Exactly one of the three is allowed.
TEST(BagFill, CountMassAndMassRatio) {
  const double m = sphere_mass(7800, 0.002);
  auto n_for = [&](const CaseText::Keys& balls) {
    LoadedCase c(bag_case(kCapsule, balls));
    return c.scene.bag->balls;
  };
  EXPECT_EQ(n_for({{"count", 17}}), 17u);
  EXPECT_EQ(n_for({{"mass", 23.4 * m}}), 23u);
  EXPECT_EQ(n_for({{"mass", 23.6 * m}}), 24u);
  EXPECT_EQ(n_for({{"mass_ratio", 0.05}, {"primary_mass", 20.2 * m / 0.05}}), 20u);
  EXPECT_THROW(n_for({{"count", 17}, {"mass", 23.4 * m}}), InputError);
  EXPECT_THROW(n_for({}), InputError);
}

// A bag of fixed size (bag.radius and bag.length given) asked for more balls than its lattice holds
// is refused by `bagdem check`: exit code 2 (bad input), the message names bag.balls.count.
// Capsule radius 7 mm, length 20 mm (about 2.6 cm^3): 200 balls of 4 mm (6.7 cm^3) cannot fit.
TEST(BagFill, FixedSizeBagWithTooManyBallsIsRefused) {
  TempDir dir;
  dir.write("case.toml", bag_case(kCapsule, {{"count", 200}}).set("bag", "length", "20 mm"));
  const CmdResult r = run_bagdem({"check", dir.str()}, dir.path);
  std::printf("BagFill: check of an overfull fixed bag: exit %d, stderr: %s", r.code, r.err.c_str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("bag.balls.count"), std::string::npos) << r.err;
}

// ---- 8. check report --------------------------------------------------------------------------------

// `bagdem check` on a bag case names the film's resolution (its number of triangles, the same as the
// loaded scene's), the bag's size (outer dimensions in mm as resolved) and each string (name,
// stiffness, anchor).
TEST(BagCheckReport, ReportsFilmResolutionSizeAndStrings) {
  TempDir dir;
  dir.write("case.toml", bag_case(kCapsule));
  const CmdResult r = run_bagdem({"check", dir.str()}, dir.path);
  ASSERT_EQ(r.code, 0) << r.err;
  LoadedCase c(bag_case(kCapsule));
  const Bag& bag = *c.scene.bag;
  std::printf("BagCheckReport: bagdem check prints:\n%s", r.out.c_str());
  std::ostringstream tri;
  tri << "resolution " << bag.rest.triangles.size() << " triangles";
  EXPECT_NE(r.out.find(tri.str()), std::string::npos) << "no '" << tri.str() << "'";
  // "outer L x W x H mm", printed to 4 significant digits: within 0.05% of the resolved size.
  std::smatch m;
  const std::regex outer(R"(outer ([0-9.eE+-]+) x ([0-9.eE+-]+) x ([0-9.eE+-]+) mm)");
  ASSERT_TRUE(std::regex_search(r.out, m, outer)) << "no 'outer L x W x H mm'";
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(std::stod(m[k + 1].str()), 1e3 * bag.size[k], 5e-4 * 1e3 * bag.size[k]) << "extent " << k;
  EXPECT_NE(r.out.find("30 balls"), std::string::npos);
  for (const char* name : {"bag.strings.0", "bag.strings.1"}) EXPECT_NE(r.out.find(name), std::string::npos) << name;
  EXPECT_NE(r.out.find("k 200 N/m"), std::string::npos);
  EXPECT_NE(r.out.find("anchor [-0.025"), std::string::npos);
  EXPECT_NE(r.out.find("anchor [0.025"), std::string::npos);
}

// ---- 9, 10. a run with a settle phase: bag.h5, summary.json, results.h5, results.xmf -------------------

namespace {

// One run of the small bag case with simulation.settle = 10 ms through the binary, shared by the
// tests below.
struct SettledRun {
  TempDir dir;
  fs::path case_dir, out;
  CmdResult result;
  SettledRun() {
    case_dir = dir.path / "first";
    out = dir.path / "first-out";
    fs::create_directories(case_dir);
    std::ofstream(case_dir / "case.toml") << bag_case(kCapsule);
    // settle 10 ms through --set (the template has no settle)
    result = run_bagdem({"run", case_dir.string(), "--out", out.string(), "--quiet", "--threads", "1", "--set",
                         "simulation.settle=0.01"},
                        dir.path);
  }
};

const SettledRun& settled_run() {
  static const SettledRun r;
  return r;
}

}  // namespace

// The run saves the settled bag to <out>/bag.h5 and reports it in summary.json ("bag": packing
// fraction in (0.3, 0.75), the range of a bag of balls from loose to dense random packing).
TEST(BagSettledReuse, RunSavesTheSettledBag) {
  const SettledRun& run = settled_run();
  ASSERT_EQ(run.result.code, 0) << run.result.err;
  EXPECT_TRUE(fs::exists(run.out / "bag.h5"));
  const bagdem::Summary summary = bagdem::read_summary(run.out / "summary.json");
  ASSERT_TRUE(summary.bag);
  const double packing = summary.bag->packing_fraction;
  const std::size_t balls = summary.bag->balls;
  std::printf("BagSettledReuse: summary.json bag entry: balls %zu, packing fraction %.4f\n", balls, packing);
  EXPECT_EQ(balls, 30u);
  EXPECT_GT(packing, 0.3);
  EXPECT_LT(packing, 0.75);
}

// bag.from: a second case starts from the saved bag. Its balls are exactly the saved ones (bag.h5,
// cavity frame) plus the cavity's rest position (1 mm along x here: harmonic motion with phase
// pi/2), bit for bit (the same addition); its film nodes likewise. The path works relative to the
// case directory and absolute. With bag.centre, the balls' centroid is there (+ the cavity's rest
// position) within 1e-12 m. The second case runs (exit 0). A saved bag with balls of another
// diameter is refused (exit 2, naming bag.from).
TEST(BagSettledReuse, BagFromLoadsTheSavedBag) {
  const SettledRun& run = settled_run();
  ASSERT_EQ(run.result.code, 0) << run.result.err;
  const fs::path saved_path = run.out / "bag.h5";
  ASSERT_TRUE(fs::exists(saved_path));
  const SavedBag saved = load_bag(saved_path.string());
  ASSERT_EQ(saved.ball_position.size(), 30u);

  TempDir dir;
  const fs::path second = dir.path / "second";
  fs::create_directories(second);
  fs::copy_file(saved_path, second / "settled.h5");
  const CaseText relative = bag_case(kCapsule).set("bag", "from", quoted("settled.h5"));
  const CaseText absolute = bag_case(kCapsule).set("bag", "from", quoted(saved_path.string()));
  for (const std::string& bag_text : {relative.str(), absolute.str()}) {
    std::ofstream(second / "case.toml") << bag_text;
    const Scene s = load_case(second.string());
    const Vec3 rest = s.motion->at(0.0).position;
    ASSERT_NEAR(rest.x(), 1e-3, 1e-15);
    const Bag& bag = *s.bag;
    ASSERT_EQ(bag.balls, saved.ball_position.size());
    std::size_t differ = 0;
    for (std::size_t k = 0; k < bag.balls; ++k) differ += !(s.particles[bag.ball_first + k].x == saved.ball_position[k] + rest);
    for (std::size_t k = 0; k < bag.x0.size(); ++k) differ += !(bag.x0[k] == saved.film_position[k] + rest);
    EXPECT_EQ(differ, 0u) << (bag_text == relative.str() ? "relative" : "absolute") << " bag.from";
    EXPECT_EQ(bag.x0.size(), saved.film_position.size());
  }
  // With bag.centre.
  std::ofstream(second / "case.toml") << CaseText(relative).set("bag", "centre", vec("2 mm", "-1 mm", "-3 mm"));
  {
    const Scene s = load_case(second.string());
    const Bag& bag = *s.bag;
    Vec3 c(0, 0, 0);
    for (std::size_t k = 0; k < bag.balls; ++k) c += s.particles[bag.ball_first + k].x;
    c /= static_cast<double>(bag.balls);
    const Vec3 expected = Vec3(2e-3, -1e-3, -3e-3) + s.motion->at(0.0).position;
    std::printf("BagSettledReuse: bag.from with centre: balls' centroid (%.6g, %.6g, %.6g) m, expected (%.6g, %.6g, %.6g)\n",
                c.x(), c.y(), c.z(), expected.x(), expected.y(), expected.z());
    EXPECT_LT((c - expected).norm(), 1e-12);
  }
  // The scene's record (what a resume compares) names the bag's file as the case does, relative to
  // it, so the case given by another path, or moved, resumes.
  std::ofstream(second / "case.toml") << relative;
  fs::copy(second, dir.path / "moved");
  const std::vector<std::string> record = scene_record(load_case(second.string()));
  EXPECT_EQ(scene_difference(record, scene_record(load_case((second / ".." / "second").string()))), "");
  EXPECT_EQ(scene_difference(record, scene_record(load_case((dir.path / "moved").string()))), "");
  EXPECT_TRUE(std::any_of(record.begin(), record.end(), [](const std::string& l) { return l.find("(from settled.h5)") != std::string::npos; }));
  // It runs.
  const CmdResult r = run_bagdem({"run", second.string(), "--out", (dir.path / "second-out").string(), "--quiet", "--threads",
                                  "1", "--set", "simulation.duration=0.001"},
                                 dir.path);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir.path / "second-out" / "summary.json"));
  // Balls of another diameter: refused.
  std::ofstream(second / "case.toml") << relative;
  const CmdResult wrong = run_bagdem({"check", second.string(), "--set", "bag.balls.diameter=\"3 mm\""}, dir.path);
  std::printf("BagSettledReuse: bag.from with 3 mm balls: exit %d, %s", wrong.code, wrong.err.c_str());
  EXPECT_EQ(wrong.code, 2);
  EXPECT_NE(wrong.err.find("bag.from"), std::string::npos) << wrong.err;
}

// results.h5 of a bag run: /film/triangles [T, 3] int32 (the film's triangles, T as in check) and
// /film/position [F, V, 3] with F = the number of particle frames (/frames/time) and V the film's
// nodes; results.xmf has a film grid of triangles reading /film/triangles and /film/position.
TEST(BagResults, FilmInResultsAndXdmf) {
  const SettledRun& run = settled_run();
  ASSERT_EQ(run.result.code, 0) << run.result.err;
  LoadedCase c(bag_case(kCapsule), {"simulation.settle=0.01"});
  const Bag& bag = *c.scene.bag;
  const std::string h5 = (run.out / "results.h5").string();
  const hid_t f = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const Ints tri = read_ints(f, "/film/triangles");
  const Doubles pos = read_doubles(f, "/film/position");
  const auto tri_dims = tri.dims, pos_dims = pos.dims, time_dims = read_doubles(f, "/frames/time").dims,
             frame_dims = read_doubles(f, "/frames/position").dims;
  const std::vector<std::int32_t>& triangles = tri.values;
  const std::vector<double>& film = pos.values;
  const bool int32 = tri.int32;
  H5Fclose(f);
  ASSERT_EQ(tri_dims.size(), 2u);
  ASSERT_EQ(pos_dims.size(), 3u);
  ASSERT_EQ(time_dims.size(), 1u);
  std::printf("BagResults: /film/triangles [%llu, %llu], /film/position [%llu, %llu, %llu], /frames/time [%llu]\n",
              static_cast<unsigned long long>(tri_dims[0]), static_cast<unsigned long long>(tri_dims[1]),
              static_cast<unsigned long long>(pos_dims[0]), static_cast<unsigned long long>(pos_dims[1]),
              static_cast<unsigned long long>(pos_dims[2]), static_cast<unsigned long long>(time_dims[0]));
  EXPECT_TRUE(int32);
  EXPECT_EQ(tri_dims[0], bag.rest.triangles.size());
  EXPECT_EQ(tri_dims[1], 3u);
  EXPECT_EQ(pos_dims[0], time_dims[0]) << "one film frame per particle frame";
  EXPECT_GE(time_dims[0], 14u);  // frames every 1 ms over 14 ms, plus the first
  EXPECT_EQ(pos_dims[1], bag.x0.size());
  EXPECT_EQ(pos_dims[2], 3u);
  EXPECT_EQ(frame_dims.at(0), time_dims[0]);
  // The triangles are the film's, node indices in range.
  ASSERT_EQ(triangles.size(), 3 * bag.rest.triangles.size());
  std::size_t differ = 0;
  for (std::size_t t = 0; t < bag.rest.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) differ += triangles[3 * t + k] != static_cast<std::int32_t>(bag.rest.triangles[t][k]);
  EXPECT_EQ(differ, 0u);
  // The first film frame is the film at t = 0.
  ASSERT_GE(film.size(), 3 * bag.x0.size());
  double first = 0;
  for (std::size_t k = 0; k < bag.x0.size(); ++k)
    first = std::max(first, (Vec3(film[3 * k], film[3 * k + 1], film[3 * k + 2]) - bag.x0[k]).norm());
  EXPECT_EQ(first, 0.0);
  const std::string xmf = slurp(run.out / "results.xmf");
  EXPECT_NE(xmf.find("<Grid Name=\"film\""), std::string::npos);
  EXPECT_NE(xmf.find("TopologyType=\"Triangle\" NumberOfElements=\"" + std::to_string(bag.rest.triangles.size()) + "\""),
            std::string::npos);
  EXPECT_NE(xmf.find(":/film/triangles"), std::string::npos);
  EXPECT_NE(xmf.find(":/film/position"), std::string::npos);
}

// ---- 11. threads -------------------------------------------------------------------------------------

namespace {

struct Snapshot {
  std::vector<Vec3> x, v, film_x, film_v;
  EnergySample e;
};

Snapshot run_threads(const Scene& s, int threads, std::uint64_t steps) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  Simulation sim(s);
  sim.set_parallel_balls(kParallelMin);  // the parallel ball stages on this small scene
  for (std::uint64_t k = 0; k < steps; ++k) sim.step();
  omp_set_num_threads(before);
  return {sim.particles().x, sim.particles().v, sim.film().x, sim.film().v, sim.energy()};
}

void expect_same(const Snapshot& a, const Snapshot& b) {
  EXPECT_TRUE(same_bits(a.x, b.x)) << "ball positions differ";
  EXPECT_TRUE(same_bits(a.v, b.v)) << "ball velocities differ";
  EXPECT_TRUE(same_bits(a.film_x, b.film_x)) << "film positions differ";
  EXPECT_TRUE(same_bits(a.film_v, b.film_v)) << "film velocities differ";
  EXPECT_EQ(std::memcmp(&a.e, &b.e, sizeof a.e), 0) << "energy() differs";
}

}  // namespace

// One and two OpenMP threads give bitwise the same balls and film (src/step/stage.hpp, Determinism). The
// film's parallel loops engage above kParallelMin = 512 nodes: bag.triangles = 1200 (~600 nodes),
// 40 balls, the box shaken (strings, friction, film damping), 3000 steps.
TEST(BagDeterminism, FilmParallelPathsMatchOneThread) {
  LoadedCase c(bag_case(kCapsule, {{"count", 40}}), {"bag.triangles=1200"});
  ASSERT_GT(c.scene.bag->x0.size(), kParallelMin);
  const Snapshot one = run_threads(c.scene, 1, 3000), two = run_threads(c.scene, 2, 3000);
  std::printf("BagDeterminism: film %zu nodes, %zu balls, 3000 steps of %.3g s\n", one.film_x.size(), one.x.size(), c.scene.dt);
  expect_same(one, two);
  EXPECT_FALSE(same_bits(one.film_x, c.scene.bag->x0)) << "the film did not move";
}

// The same with the balls' parallel paths: 600 balls (above 512) in a coarse film, 1000 steps.
TEST(BagDeterminism, BallParallelPathsMatchOneThread) {
  LoadedCase c(bag_case(kCapsule, {{"count", 600}}).set("bag", "radius", "15 mm"),
               {"cavity.min=[-0.06, -0.02, -0.02]", "cavity.max=[0.06, 0.02, 0.02]", "bag.strings.0.anchor=[-0.06, 0, 0]",
                "bag.strings.1.anchor=[0.06, 0, 0]", "bag.triangles=300"});
  ASSERT_GT(c.scene.bag->balls, kParallelMin);
  const Snapshot one = run_threads(c.scene, 1, 1000), two = run_threads(c.scene, 2, 1000);
  std::printf("BagDeterminism: %zu balls, film %zu nodes, 1000 steps of %.3g s\n", one.x.size(), one.film_x.size(), c.scene.dt);
  expect_same(one, two);
}

// ---- 12. restart -------------------------------------------------------------------------------------

// save_state() mid-run and load_state() into a new Simulation, then continue: bitwise the same
// balls, film nodes, energy() and state image as the uninterrupted run. The small bag case (strings,
// friction histories, film damping, ball-film contacts), the bag placed 0.1 mm above the floor:
// the box shaken from the start; stepped until the balls touch the film (4 contacts) and 1000 steps
// more, saved, then 2000 steps.
TEST(BagRestart, SaveLoadStateIsBitwise) {
  LoadedCase c(bag_case(kCapsule), {"simulation.duration=0.03", "bag.centre=[0, 0, -0.0049]", "bag.film.bending_interval=\"auto\""});
  const Scene& s = c.scene;
  Simulation whole(s);
  // Until at least 4 ball-film contacts are closed, then 1000 steps more; then 2000 steps on.
  std::uint64_t n1 = 0;
  while (whole.mesh_contact_count() < 4 && n1 < s.total_steps() / 2) whole.step(), ++n1;
  for (int k = 0; k < 1000; ++k) whole.step(), ++n1;
  // Saved between two beats of the bending's slower clock (docs/bag.md, "Time step"), which the
  // resumed run takes up from the step count.
  if (s.bag->bending_interval > 1 && n1 % static_cast<std::uint64_t>(s.bag->bending_interval) == 0) whole.step(), ++n1;
  EXPECT_GT(s.bag->bending_interval, 1);
  const std::uint64_t n2 = 2000;
  ASSERT_LE(n1 + n2, s.total_steps());
  const std::vector<char> image = whole.save_state();
  const std::size_t contacts = whole.mesh_contact_count();
  for (std::uint64_t k = 0; k < n2; ++k) whole.step();

  Simulation resumed(s);
  resumed.load_state(image);
  EXPECT_EQ(resumed.steps_done(), n1);
  EXPECT_EQ(resumed.mesh_contact_count(), contacts);
  for (std::uint64_t k = 0; k < n2; ++k) resumed.step();
  std::printf("BagRestart: state image %zu bytes at step %llu (%zu ball-film contacts), %llu more steps\n", image.size(),
              static_cast<unsigned long long>(n1), contacts, static_cast<unsigned long long>(n2));
  EXPECT_GT(contacts, 0u) << "the restart should carry ball-film contact histories";
  const Snapshot a{whole.particles().x, whole.particles().v, whole.film().x, whole.film().v, whole.energy()};
  const Snapshot b{resumed.particles().x, resumed.particles().v, resumed.film().x, resumed.film().v, resumed.energy()};
  expect_same(a, b);
  EXPECT_TRUE(whole.save_state() == resumed.save_state()) << "the state images differ";
}

// A bag pulled tight (bag.film.shrink, docs/bag.md "Tight bags"): the film is made where the FCC
// lattice holds the balls and its unstretched size is 0.9 of that, so it closes on them as they
// settle. The small capsule's 30 balls, settled 20 ms without and with it: the packing fraction
// (summary.json) rises from the lattice's by more than 0.1, past the unstretched film's fill (the
// film wrinkles and sags below its unstretched volume under the balls' weight) and below random
// close packing; the energy budget closes throughout (the run stops otherwise: the film's stretch
// at the start is stored energy, released as it closes).
TEST(BagTight, AShrunkFilmPacksItsBallsCloser) {
  TempDir dir;
  fs::create_directories(dir.path / "case");
  std::ofstream(dir.path / "case" / "case.toml") << bag_case(kCapsule);
  const Scene tight = load_case((dir.path / "case").string(), {"bag.film.shrink=0.9"});
  const Scene loose = load_case((dir.path / "case").string());
  EXPECT_EQ(tight.particles.size(), loose.particles.size());
  EXPECT_NEAR(tight.bag->fill_fraction, loose.bag->fill_fraction / (0.9 * 0.9 * 0.9), 1e-12);
  double packing[2];
  for (int k = 0; k < 2; ++k) {
    const fs::path out = dir.path / (k ? "tight" : "loose");
    std::vector<std::string> args = {"run", (dir.path / "case").string(), "--out", out.string(), "--quiet", "--threads", "1",
                                     "--set", "simulation.settle=0.02"};
    if (k) args.insert(args.end(), {"--set", "bag.film.shrink=0.9"});
    const CmdResult r = run_bagdem(args, dir.path);
    ASSERT_EQ(r.code, 0) << r.err;
    packing[k] = bagdem::read_summary(out / "summary.json").bag->packing_fraction;
  }
  std::printf("BagTight: fill of the unstretched film %.3f (lattice's bag %.3f); settled packing %.3f loose, %.3f tight\n",
              tight.bag->fill_fraction, loose.bag->fill_fraction, packing[0], packing[1]);
  EXPECT_GT(packing[1], packing[0] + 0.1);
  EXPECT_GT(packing[1], tight.bag->fill_fraction);  // a film wrinkles freely: it may sag below its unstretched volume
  EXPECT_LT(packing[1], 0.64);                      // and not past random close packing
  // A film that could only close on its balls by crushing them is refused (every run stopped at its
  // first steps), naming the least value allowed.
  try {
    load_case((dir.path / "case").string(), {"bag.film.shrink=0.7"});
    ADD_FAILURE() << "a shrink past close packing was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("above random close packing (0.64)"), std::string::npos) << e.what();
  }
}
