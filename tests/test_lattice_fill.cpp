// The lattice fill (fill = "lattice", src/case/fcc_lattice.hpp): its sites a batch at a time give
// the order of every site of the box enumerated and sorted (lowest first along gravity, ties in the
// lattice's index order), whatever the batches; a box in metres where millimetres were meant fills
// in memory that follows the balls (it used to enumerate every site first: 12.6 GB and
// std::bad_alloc for cases/box-damper with cavity.max = [21, 21, 48]), and a box whose one layer
// alone is too large is refused before filling, naming the key and the units.
#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>
#include <string>
#include <vector>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "case/fcc_lattice.hpp"

using namespace bagdem;

namespace {

// Every site of the box, sorted as the fill takes them: the reference the batches must give.
std::vector<Vec3> every_site_sorted(const Vec3& lo, const Vec3& hi, double spacing, const Vec3& down) {
  struct S {
    double e;
    Vec3 x;
  };
  const double a = spacing * std::numbers::sqrt2;
  const Vec3 o = lo + Vec3::Constant(0.5 * spacing);
  const Vec3 basis[4] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  std::vector<S> all;
  for (double i = 0; o.x() + i * a <= hi.x(); ++i)
    for (double j = 0; o.y() + j * a <= hi.y(); ++j)
      for (double k = 0; o.z() + k * a <= hi.z(); ++k)
        for (const Vec3& b : basis) {
          const Vec3 x = o + a * (Vec3(i, j, k) + b);
          if ((x.array() <= hi.array()).all()) all.push_back({-x.dot(down), x});
        }
  std::stable_sort(all.begin(), all.end(), [](const S& p, const S& q) { return p.e < q.e; });
  std::vector<Vec3> xs;
  for (const S& s : all) xs.push_back(s.x);
  return xs;
}

}  // namespace

TEST(LatticeFill, BatchesGiveTheOrderOfEverySiteSorted) {
  const Vec3 lo(0, 0, 0), hi(0.021, 0.033, 0.048);
  const double spacing = 1.01 * 0.004;
  for (const Vec3& down : {Vec3(0, 0, -1), Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(Vec3(0.3, -0.2, -1).normalized())}) {
    const std::vector<Vec3> want = every_site_sorted(lo, hi, spacing, down);
    ASSERT_GT(want.size(), 500u);
    for (std::size_t wanted : {1u, 100u, 100000u}) {  // batches of 256, 256 and all: many refills, a few, one
      FccLattice lattice(lo, hi, spacing, down, wanted);
      std::vector<Vec3> got;
      for (Vec3 x; lattice.next(x);) got.push_back(x);
      ASSERT_EQ(got.size(), want.size()) << "down " << down.transpose() << ", wanted " << wanted;
      for (std::size_t k = 0; k < got.size(); ++k)
        ASSERT_EQ(got[k], want[k]) << "site " << k << ", down " << down.transpose() << ", wanted " << wanted;
    }
  }
}

// The case: 100 balls of 4 mm in a box of 21 x 21 x 48 m (4.6e11 lattice sites): filled,
// with the units warning; ten times wider, refused before filling.
TEST(LatticeFill, ABoxInMetresWhereMillimetresWereMeantFillsOrIsRefused) {
  const std::string box_damper = std::string(BAGDEM_CASES_DIR) + "/box-damper";
  const Scene s = load_case(box_damper, {"cavity.max=[21, 21, 48]"});
  EXPECT_EQ(s.particles.size(), 100u);
  for (const ParticleInit& p : s.particles) EXPECT_LT(p.x.z(), 0.01) << "the balls fill the lowest layer first";
  ASSERT_FALSE(s.warnings.empty());
  EXPECT_NE(s.warnings.front().find("check the units of the cavity's keys"), std::string::npos) << s.warnings.front();
  try {
    load_case(box_damper, {"cavity.max=[210, 210, 48]"});
    ADD_FAILURE() << "a layer of 5e9 sites was filled";
  } catch (const InputError& e) {
    const std::string m = e.what();
    for (const char* part : {"particles.balls.fill", "sites in one layer", "check the units", "\"20 mm\""})
      EXPECT_NE(m.find(part), std::string::npos) << part << " not in: " << m;
  }
}
