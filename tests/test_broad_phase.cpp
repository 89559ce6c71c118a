// The broad phases return one canonical set (neighbour/broad_phase.hpp): all i < j with
// |x_i - x_j| < r_i + r_j + skin, grouped by i, sorted by j. "brute" is the O(N^2) reference;
// "hash" and "kdtree" must give identical CSR arrays (begin and partner) for any packing, any skin
// and any thread count, and therefore a Simulation run must not depend on the choice at all.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bagdem/motion/motion.hpp"
#include "bagdem/neighbour/broad_phase.hpp"
#include "bagdem/step/simulation.hpp"
#include "rng.hpp"
#include "scene_builder.hpp"

using namespace bagdem;
using bagdem::testing::Rng;
using bagdem::testing::SceneBuilder;

namespace {


struct Packing {
  std::string name;
  std::vector<Vec3> x;
  std::vector<double> r;
};

// Uniform random positions in a box straddling negative coordinates; radii r0 * [1, 3] (diameter
// ratio 3); `density` sets the number of particles per (2 r0)^3, > 1 gives many overlaps.
Packing uniform_packing(std::uint64_t seed, int n, double r0, double density) {
  Rng rng(seed);
  Packing p{"uniform seed " + std::to_string(seed), {}, {}};
  const double side = 2 * r0 * std::cbrt(n / density);
  const Vec3 lo(-0.7 * side, -0.3 * side, -1.2 * side);
  for (int i = 0; i < n; ++i) {
    p.r.push_back(r0 * rng.uniform(1, 3));
    p.x.push_back(lo + side * draw_vec3([&] { return rng.uniform(); }));
  }
  return p;
}

// Dense Gaussian clusters (heavy overlap) at negative and positive coordinates, a sparse halo, and
// isolated particles very far away (|x| ~ 1e3 m, all octants) and in exact coincidence.
Packing clustered_packing(std::uint64_t seed, int n, double r0) {
  Rng rng(seed);
  Packing p{"clustered seed " + std::to_string(seed), {}, {}};
  std::vector<Vec3> centres;
  for (int c = 0; c < 6; ++c) centres.push_back(draw_vec3([&] { return rng.uniform(-1, 1); }) * 40 * r0);
  for (int i = 0; i < n; ++i) {
    const double r = r0 * rng.uniform(1, 3);
    const double u = rng.uniform();
    Vec3 x;
    if (u < 0.8) {
      const Vec3& c = centres[static_cast<std::size_t>(rng.next() % centres.size())];
      x = c + 2.5 * r0 * draw_vec3([&] { return rng.normal(); });
    } else if (u < 0.97) {
      x = draw_vec3([&] { return rng.uniform(-1, 1); }) * 200 * r0;
    } else {
      x = draw_vec3([&] { return rng.uniform(-1, 1); }) * 1e3;
    }
    p.r.push_back(r);
    p.x.push_back(x);
  }
  // A few exact duplicates (distance 0) and a far pair that touches.
  for (int k = 0; k < 5; ++k) {
    p.x.push_back(p.x[static_cast<std::size_t>(k * 97)]);
    p.r.push_back(p.r[static_cast<std::size_t>(k * 97)]);
  }
  p.x.push_back(Vec3(-987.25, 512.5, -1000.0));
  p.r.push_back(r0);
  p.x.push_back(Vec3(-987.25, 512.5, -1000.0) + Vec3(1.5 * r0, 0, 0));
  p.r.push_back(2 * r0);
  return p;
}

// Pairs placed exactly at the cut-off distance, in floating point: x_j = x_i + cut * u, with u a
// random unit vector and cut = r_i + r_j + skin. |x_i - x_j|^2 then lies within a few ulps of
// cut^2 on either side, so every implementation must evaluate the same expression to agree. This
// is what a generator placing particles "in contact" produces.
Packing touching_pairs(std::uint64_t seed, int n_pairs, double r0, double skin) {
  Rng rng(seed);
  Packing p{"touching pairs seed " + std::to_string(seed) + " skin " + std::to_string(skin / r0) + " r0",
            {}, {}};
  for (int k = 0; k < n_pairs; ++k) {
    const double ri = r0 * rng.uniform(1, 3), rj = r0 * rng.uniform(1, 3);
    const Vec3 xi = draw_vec3([&] { return rng.uniform(-1, 1); }) * 30 * r0 * std::cbrt(n_pairs);
    const Vec3 xj = xi + (ri + rj + skin) * rng.unit();
    p.x.push_back(xi);
    p.r.push_back(ri);
    p.x.push_back(xj);
    p.r.push_back(rj);
  }
  return p;
}

// Simple-cubic lattice with spacing exactly 2 r (r a power of two: exact arithmetic): every
// neighbour pair sits exactly at the cut-off for skin 0, so none is a candidate then.
Packing lattice_packing(int m, double r) {
  Packing p{"lattice", {}, {}};
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      for (int k = 0; k < m; ++k) {
        p.x.push_back(Vec3(-8 * r * m + 2 * r * i, 2 * r * j - r * m, 2 * r * k));
        p.r.push_back(r);
      }
  return p;
}

CandidatePairs find(const std::string& kind, const Packing& p, double skin) {
  CandidatePairs out;
  make_broad_phase(kind)->find(p.x, p.r, skin, out);
  return out;
}

// Structural check of a CSR result against the definition (independent of the implementations).
void check_canonical(const CandidatePairs& c, const Packing& p, double skin, const std::string& what) {
  const std::size_t n = p.x.size();
  ASSERT_EQ(c.begin.size(), n + 1) << what;
  ASSERT_EQ(c.begin[0], 0u) << what;
  ASSERT_EQ(c.begin[n], c.partner.size()) << what;
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_LE(c.begin[i], c.begin[i + 1]) << what;
    for (std::uint32_t k = c.begin[i]; k < c.begin[i + 1]; ++k) {
      const std::uint32_t j = c.partner[k];
      ASSERT_GT(j, i) << what;
      ASSERT_LT(j, n) << what;
      if (k > c.begin[i]) {
        ASSERT_LT(c.partner[k - 1], j) << what << ": not sorted / duplicated at i=" << i;
      }
      const double cut = p.r[i] + p.r[j] + skin;
      ASSERT_LT((p.x[i] - p.x[j]).squaredNorm(), cut * cut) << what << ": (" << i << "," << j << ")";
    }
  }
}

// Reports the first difference between two results.
std::string first_difference(const CandidatePairs& a, const CandidatePairs& b, const Packing& p, double skin) {
  const std::size_t n = p.x.size();
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<std::uint32_t> pa(a.partner.begin() + a.begin[i], a.partner.begin() + a.begin[i + 1]);
    std::vector<std::uint32_t> pb(b.partner.begin() + b.begin[i], b.partner.begin() + b.begin[i + 1]);
    if (pa == pb) continue;
    for (std::uint32_t j = static_cast<std::uint32_t>(i) + 1; j < n; ++j) {
      const bool in_a = std::find(pa.begin(), pa.end(), j) != pa.end();
      const bool in_b = std::find(pb.begin(), pb.end(), j) != pb.end();
      if (in_a == in_b) continue;
      const double cut = p.r[i] + p.r[j] + skin;
      char buf[256];
      std::snprintf(buf, sizeof buf, "pair (%zu,%u) in first: %d, in second: %d; |dx|^2 - cut^2 = %.3e, cut^2 = %.17g",
                    i, j, in_a, in_b, (p.x[i] - p.x[j]).squaredNorm() - cut * cut, cut * cut);
      return buf;
    }
    return "row " + std::to_string(i) + " differs in order only";
  }
  return "begin arrays differ";
}

void expect_all_kinds_agree(const Packing& p, double skin, std::size_t* pairs_out = nullptr) {
  const std::string what = p.name + ", " + std::to_string(p.x.size()) + " particles, skin " + std::to_string(skin);
  const CandidatePairs ref = find("brute", p, skin);
  check_canonical(ref, p, skin, what + " [brute]");
  if (pairs_out) *pairs_out = ref.size();
  for (const char* kind : {"hash", "kdtree"}) {
    const CandidatePairs c = find(kind, p, skin);
    EXPECT_EQ(c.begin, ref.begin) << what << " [" << kind << " vs brute]: " << first_difference(ref, c, p, skin);
    EXPECT_EQ(c.partner, ref.partner) << what << " [" << kind << " vs brute]";
  }
}

// Runs a body with k OpenMP threads, restoring the previous setting.
template <class F>
void with_threads(int k, F&& f) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(k);
  f();
  omp_set_num_threads(before);
}

}  // namespace

// Reference: brute-force O(N^2) list (and the definition, check_canonical). Tolerance: exact
// equality of begin and partner arrays. 3 seeds x {sparse, dense} uniform packings of 2500-3000
// particles with diameter ratio 3, skins 0, 0.3 r0 and 2 r0; 1 and 2 threads (the broad phases
// go parallel above 2000 particles).
TEST(BroadPhase, UniformPolydisperseAllKindsIdentical) {
  const double r0 = 1e-3;
  for (int threads : {1, 2}) {
    with_threads(threads, [&] {
      for (std::uint64_t seed : {1u, 2u, 3u}) {
        for (double density : {0.05, 1.5}) {
          const Packing p = uniform_packing(seed, density < 1 ? 2500 : 3000, r0, density);
          for (double skin : {0.0, 0.3 * r0, 2.0 * r0}) {
            std::size_t np = 0;
            expect_all_kinds_agree(p, skin, &np);
            if (density > 1) {
              EXPECT_GT(np, p.x.size()) << "dense packing should have many pairs";
            }
          }
        }
      }
    });
  }
}

TEST(BroadPhase, ClusteredAndFarApartAllKindsIdentical) {
  const double r0 = 2e-3;
  for (int threads : {1, 2}) {
    with_threads(threads, [&] {
      for (std::uint64_t seed : {11u, 12u, 13u}) {
        const Packing p = clustered_packing(seed, 3000, r0);
        for (double skin : {0.0, 0.5 * r0}) {
          std::size_t np = 0;
          expect_all_kinds_agree(p, skin, &np);
          EXPECT_GT(np, 3000u);
        }
      }
    });
  }
}

// Reference: brute force. Tolerance: exact equality. Pairs at the cut-off to within a few ulps:
// the implementations must not disagree on the strict inequality |dx|^2 < cut^2.
// Known failure (engine, src/neighbour/kdtree.cpp): the k-d tree tests nanoflann's own squared
// distance (L2_Simple_Adaptor, sum of diff*diff, FMA-contracted under -march=native) instead of
// the (x_i - x_j).squaredNorm() that brute and hash use; ~0.2% of exact-contact pairs round the
// other way, in both directions. Fix: recompute d2 = (x[i] - x[j]).squaredNorm() for the hits
// (and pad the search radius by a few ulps).
TEST(BroadPhase, PairsAtTheCutoffAllKindsIdentical) {
  const double r0 = 1e-3;
  for (double skin : {0.0, 0.2 * r0}) {
    for (std::uint64_t seed : {21u, 22u}) {
      const Packing p = touching_pairs(seed, 1500, r0, skin);
      std::size_t np = 0;
      expect_all_kinds_agree(p, skin, &np);
      EXPECT_GT(np, 0u);  // some of the exact-contact pairs round inside
      std::printf("[broad-phase] %s: %zu of 1500 pairs at the cut-off are candidates\n", p.name.c_str(), np);
    }
  }
  const double rl = std::ldexp(1.0, -11);          // ~0.49 mm, a power of two: exact arithmetic
  const Packing lat = lattice_packing(14, rl);      // 2744 particles
  std::size_t np = 1;
  expect_all_kinds_agree(lat, 0.0, &np);
  EXPECT_EQ(np, 0u);  // exactly touching is not a candidate at skin 0
  expect_all_kinds_agree(lat, std::ldexp(1.0, -14), &np);
  EXPECT_EQ(np, 3u * 14 * 14 * 13);  // the six lattice neighbours, each pair once
}

namespace {

// 392 polydisperse frictional balls (r 1-3 mm, diameter ratio 3, E = 5e7 Pa) on a jittered
// lattice in a box with negative coordinates, shaken obliquely, gravity on, 500 steps of 1e-5 s.
// Below 512 particles every loop runs serially, and the run uses one thread anyway: this test is
// about the broad phase, not about threads (and stays fast on a loaded machine).
Scene shaken_bed(const std::string& kind) {
  SceneBuilder b;
  b.material("glass", 2500, 5e7, 0.3).interaction(0.6, 0.4, 0.05);
  const Vec3 lo(-0.03, -0.05, -0.02), hi(0.018, -0.002, 0.06);
  b.box(lo, hi).gravity(Vec3(0.5, 0, -9.81)).dt(1e-5).duration(5e-3).broad_phase(kind);
  b.motion(make_harmonic_motion(0.001, 30.0, Vec3(1, 0, 2), 0.3));
  Rng rng(99);
  const double a = 0.0061;  // lattice spacing > 2 r_max
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 7; ++j)
      for (int k = 0; k < 8; ++k) {
        const double r = rng.uniform(0.001, 0.003);
        const Vec3 x = lo + Vec3(0.0035 + a * i, 0.0035 + a * j, 0.0035 + a * k) +
                       draw_vec3([&] { return rng.uniform(-1, 1); }) * 0.00004;
        const Vec3 v = draw_vec3([&] { return rng.uniform(-1, 1); });
        b.particle(x, v, r);
      }
  return b.build();
}

}  // namespace

// Reference: the same run with "kdtree". Tolerance: bitwise equality of positions, velocities and
// of the whole checkpoint image (histories included), since both must see the same pair lists.
TEST(BroadPhase, SimulationHashAndKdtreeBitwiseIdentical) {
  const Scene sh = shaken_bed("hash"), sk = shaken_bed("kdtree");
  const int before = omp_get_max_threads();
  omp_set_num_threads(1);
  Simulation a(sh), b(sk);
  std::size_t max_contacts = 0;
  for (std::uint64_t k = 0; k < sh.total_steps(); ++k) {
    a.step();
    b.step();
    if (k % 50 == 0) max_contacts = std::max(max_contacts, a.contact_count());
  }
  omp_set_num_threads(before);
  std::printf("[broad-phase] shaken bed: %zu particles, %zu candidate pairs, %llu builds, up to %zu contacts\n",
              a.particles().size(), a.pair_list().pairs,
              static_cast<unsigned long long>(a.neighbour_builds()), max_contacts);
  EXPECT_GT(max_contacts, 20u);  // measured 28
  EXPECT_GT(a.neighbour_builds(), 1u);
  ASSERT_EQ(a.particles().size(), b.particles().size());
  const std::size_t bytes = a.particles().size() * sizeof(Vec3);
  EXPECT_EQ(0, std::memcmp(a.particles().x.data(), b.particles().x.data(), bytes)) << "positions differ";
  EXPECT_EQ(0, std::memcmp(a.particles().v.data(), b.particles().v.data(), bytes)) << "velocities differ";
  EXPECT_TRUE(a.save_state() == b.save_state()) << "checkpoint images differ";
}
