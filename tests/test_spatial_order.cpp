// The stepper's ball order (neighbour/spatial_order.hpp): set-up sorts the balls into slabs across
// the bed's longest side, so two threads' ranges of balls share few pairs; every output stays in the
// scene's order, and the run does not depend on the order the scene lists its balls in.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "bagdem/parallel.hpp"
#include "bagdem/case/load_case.hpp"
#include "bagdem/neighbour/spatial_order.hpp"
#include "bagdem/run/runner.hpp"
#include "bagdem/step/simulation.hpp"
#include "step/stepper.hpp"
#include "case_texts.hpp"
#include "h5_read.hpp"
#include "support.hpp"

using namespace bagdem;
using bagdem::testing::Doubles;
using bagdem::testing::Ints;
using bagdem::testing::open_read;
using bagdem::testing::read_doubles;
using bagdem::testing::read_ints;
using bagdem::testing::TempDir;
namespace fs = std::filesystem;

namespace {

// 700 soft balls of two sizes on an FCC lattice in a long box (60 x 20 mm), shaken along x. The
// lattice fill lists them layer by layer from the bottom.
const std::string kCase = bagdem::testing::CaseText()
                              .simulation("3 ms")
                              .rubber()
                              .interactions(0.6, 0.4)
                              .box("rubber", "[0, 0, 0]", bagdem::testing::vec("60 mm", "20 mm", "60 mm"))
                              .harmonic("1 mm", "30 Hz", "[1, 0, 0]")
                              .balls("small", "rubber", "3.6 mm", 350)
                              .set("particles.small", "fill", bagdem::testing::quoted("lattice"))
                              .balls("large", "rubber", "4 mm", 350)
                              .set("particles.large", "fill", bagdem::testing::quoted("lattice"))
                              .output("frame_interval", "1 ms");

Scene load(const TempDir& tmp) {
  const fs::path dir = tmp.path / "case";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << kCase;
  return load_case(dir.string());
}

// The scene with its balls listed in another order: shuffled[k] = scene.particles[perm[k]].
Scene shuffled(const Scene& scene, std::vector<std::uint32_t>& perm, unsigned seed) {
  perm.resize(scene.particles.size());
  std::iota(perm.begin(), perm.end(), 0u);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(seed));
  Scene s = scene;
  for (std::size_t k = 0; k < perm.size(); ++k) s.particles[k] = scene.particles[perm[k]];
  return s;
}

}  // namespace

// The order is a permutation that keeps the bag's balls, and the balls before and after them, in
// their places, and within each runs along the longest side of that group's bounding box in slabs
// one largest diameter thick.
TEST(SpatialOrder, SortsEachGroupInPlaceAlongItsLongestSide) {
  Scene s;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  // 300 balls in a slab long along y, then 700 (the bag's) long along z, then 200 long along x.
  auto add = [&](std::size_t n, const Vec3& size) {
    for (std::size_t i = 0; i < n; ++i) s.particles.push_back({draw_vec3([&] { return u(rng); }).cwiseProduct(size), Vec3::Zero(), Vec3::Zero(), 1e-3, 0});
  };
  add(300, Vec3(0.02, 0.1, 0.01));
  add(700, Vec3(0.02, 0.01, 0.1));
  add(200, Vec3(0.1, 0.02, 0.01));
  auto bag = std::make_shared<Bag>();
  bag->ball_first = 300;
  bag->balls = 700;
  s.bag = bag;
  const std::vector<std::uint32_t> order = spatial_order(s);
  ASSERT_EQ(order.size(), s.particles.size());
  std::vector<std::uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (std::uint32_t k = 0; k < sorted.size(); ++k) ASSERT_EQ(sorted[k], k) << "not a permutation";
  const struct {
    std::size_t first, last;
    int axis;
  } groups[] = {{0, 300, 1}, {300, 1000, 2}, {1000, 1200, 0}};
  for (const auto& g : groups) {
    double lo = 1e300;
    for (std::size_t i = g.first; i < g.last; ++i) {
      ASSERT_GE(order[i], g.first) << "ball " << i << " left its group";
      ASSERT_LT(order[i], g.last) << "ball " << i << " left its group";
      lo = std::min(lo, s.particles[order[i]].x[g.axis]);
    }
    for (std::size_t i = g.first + 1; i < g.last; ++i) {
      const double a = std::floor((s.particles[order[i - 1]].x[g.axis] - lo) / 2e-3);
      const double b = std::floor((s.particles[order[i]].x[g.axis] - lo) / 2e-3);
      ASSERT_LE(a, b) << "balls " << i - 1 << " and " << i << " of group at " << g.first << ": slabs out of order";
    }
  }
  // Below kSpatialOrderMin balls the scene's order is kept.
  s.particles.resize(kSpatialOrderMin - 1);
  s.bag = nullptr;
  const std::vector<std::uint32_t> small = spatial_order(s);
  for (std::uint32_t k = 0; k < small.size(); ++k) ASSERT_EQ(small[k], k);
}

// What the order is for: with two threads the pair stage cuts the balls into two index ranges, and
// the pairs across the cut need records. Listed in random order (as a bed file may be), about half
// the pairs would cross; sorted, the cut runs across the box's long side: the pairs of one slab face.
TEST(SpatialOrder, TwoRangesShareFewPairs) {
  TempDir tmp;
  std::vector<std::uint32_t> perm;
  const Scene s = shuffled(load(tmp), perm, 11);
  const int before = omp_get_max_threads();
  omp_set_num_threads(2);
  Stepper sim(s);  // the stepper itself: the test reads its threads' ranges
  sim.set_parallel_balls(kParallelMin);  // two ranges on this small scene
  sim.step();
  omp_set_num_threads(before);
  const PairState& ps = sim.pair_state();
  ASSERT_EQ(ps.ranges, 2u) << "the scene must be large enough for two ranges";
  const double crossing = static_cast<double>(ps.cross.size()) / static_cast<double>(ps.pairs.size());
  std::printf("[spatial order] %zu balls, %zu candidate pairs, %zu across the two ranges (%.1f%%)\n", s.particles.size(),
              ps.pairs.size(), ps.cross.size(), 100 * crossing);
  EXPECT_GT(ps.cross.size(), 0u);
  // 700 balls in about 15 slabs of 4 mm: one slab face holds about 1/15 of the pairs.
  EXPECT_LT(crossing, 0.1);
}

// A run's results.h5 lists the balls in the scene's order, and listing them in another order
// changes nothing else: the stepper's order follows from the positions alone, so every other
// series is bitwise the same.
TEST(SpatialOrder, ResultsAreInTheScenesOrderWhateverItIs) {
  TempDir tmp;
  const Scene a = load(tmp);
  std::vector<std::uint32_t> perm;
  const Scene b = shuffled(a, perm, 5);
  {
    const Simulation sim(a);
    std::vector<std::uint32_t> identity(a.particles.size());
    std::iota(identity.begin(), identity.end(), 0u);
    ASSERT_NE(sim.input_index(), identity) << "the test needs a scene the stepper reorders";
  }
  auto run = [&](const Scene& s, const char* name) {
    const RunReport r = run_scene(s, bagdem::testing::quiet_run(tmp.path / name, 2));
    EXPECT_TRUE(r.complete) << r.message;
    return open_read((tmp.path / name / "results.h5").string());
  };
  const hid_t fa = run(a, "a"), fb = run(b, "b");
  const std::size_t n = a.particles.size();

  const Doubles radius_a = read_doubles(fa, "/particles/radius"), radius_b = read_doubles(fb, "/particles/radius");
  ASSERT_EQ(radius_a.values.size(), n);
  ASSERT_EQ(radius_b.values.size(), n);
  for (std::size_t k = 0; k < n; ++k) {
    ASSERT_EQ(radius_a.values[k], a.particles[k].radius) << "ball " << k;
    ASSERT_EQ(radius_b.values[k], a.particles[perm[k]].radius) << "ball " << k;
  }
  for (const char* name : {"/frames/position", "/frames/velocity", "/frames/angular_velocity"}) {
    const Doubles va = read_doubles(fa, name), vb = read_doubles(fb, name);
    ASSERT_EQ(va.dims.size(), 3u) << name;
    ASSERT_EQ(va.dims, vb.dims) << name;
    const std::size_t frames = va.dims[0];
    ASSERT_GE(frames, 3u) << name;
    ASSERT_EQ(va.dims[1], n) << name;
    for (std::size_t f = 0; f < frames; ++f)
      for (std::size_t k = 0; k < n; ++k)
        for (std::size_t c = 0; c < 3; ++c)
          ASSERT_EQ(vb.values[(f * n + k) * 3 + c], va.values[(f * n + perm[k]) * 3 + c])
              << name << ", frame " << f << ", ball " << k << " of the shuffled scene";
  }
  // The first frame is the scene's initial state, ball for ball.
  const Doubles x = read_doubles(fa, "/frames/position");
  for (std::size_t k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) ASSERT_EQ(x.values[k * 3 + static_cast<std::size_t>(c)], a.particles[k].x[c]) << "ball " << k;
  for (const char* name : {"/cavity/force", "/energy/kinetic", "/energy/dissipated_normal"}) {
    const Doubles va = read_doubles(fa, name), vb = read_doubles(fb, name);
    ASSERT_FALSE(va.values.empty()) << name;
    EXPECT_EQ(va.values, vb.values) << name;
  }
  H5Fclose(fa);
  H5Fclose(fb);
}

// A checkpoint holds the balls in the stepper's order, each with its index in the case. A run of
// the same case takes it and goes on bit for bit; the same balls listed in another order, or placed
// elsewhere (mirrored across the box), give another order, and the checkpoint is refused with a
// message, not misread.
TEST(SpatialOrder, CheckpointsFollowTheStepperOrder) {
  TempDir tmp;
  const Scene a = load(tmp);
  Simulation sa(a);
  for (int k = 0; k < 20; ++k) sa.step();
  const std::vector<char> image = sa.save_state();

  Simulation same(a);
  ASSERT_NO_THROW(same.load_state(image));
  EXPECT_EQ(same.save_state(), image);

  std::vector<std::uint32_t> perm;
  Scene mirrored = a;
  for (ParticleInit& q : mirrored.particles) q.x.x() = a.cavity_hi.x() - q.x.x();
  for (const Scene& other : {shuffled(a, perm, 9), mirrored}) {
    Simulation s(other);
    try {
      s.load_state(image);
      ADD_FAILURE() << "a checkpoint of another ball order was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("another order"), std::string::npos) << e.what();
    }
  }
}
