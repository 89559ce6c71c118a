// The elastic energy of a sphere against a triangulated surface as the stepper computes it: the
// Euler characteristic's sum over the features within reach (step/surface_features.hpp,
// euler_terms), U = sum_faces U_H - sum_interior edges U_H + sum_interior vertices U_H, per unit Hertz
// constant (U_H = delta^(5/2)). References:
//  - a flat triangulation: the plane's energy, U_H(overlap), at any place of the foot (a face, an
//    edge, a vertex where 6 or 8 triangles meet), to rounding;
//  - an open sheet's boundary edge: the edge's own contact (the boundary's edges and vertices are
//    not counted);
//  - across a shallow fold, where the one-contact-per-feature rule lets a hit be born at positive
//    overlap: continuous (every step's change within the Lipschitz bound of the terms), where the
//    sum over the rule's contacts jumps;
//  - the forces the stepper applies (each term's Hertz force along its normal on the ball, its
//    reaction on the feature's nodes by the closest point's weights) are minus the gradient of U,
//    against central finite differences, on a wrinkled film round a 20-mm ball.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "bagdem/mesh/shapes.hpp"
#include "mesh_support.hpp"
#include "step/surface_features.hpp"

using namespace bagdem;
using namespace bagdem::surface_contacts;
using bagdem::testing::floor_mesh;

namespace {

// The closest points of the triangles within reach of x (what find_features collects).
std::vector<MeshHit> hits_of(const TriangleMesh& m, const std::vector<Vec3>& vx, const Vec3& x, double reach) {
  std::vector<MeshHit> hits;
  for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
    const auto& tri = m.triangles[t];
    const TriangleHit h = closest_point_on_triangle(x, vx[tri[0]], vx[tri[1]], vx[tri[2]]);
    if (h.distance2 < reach * reach) hits.push_back({t, 0, h});
  }
  return hits;
}

struct Euler {
  double energy = 0;
  Vec3 force = Vec3::Zero();     // on the sphere
  std::vector<Vec3> node_force;  // on the surface's nodes
  std::size_t terms = 0;
};

Euler euler(const TriangleMesh& m, const std::vector<Vec3>& vx, const Vec3& x, double reach) {
  std::vector<EulerTerm> terms;
  euler_terms(m, vx, x, reach, -1.0, hits_of(m, vx, x, reach), 0, terms);
  Euler e;
  e.node_force.assign(vx.size(), Vec3::Zero());
  e.terms = terms.size();
  PairLaw unit;  // Hertz with a unit constant: (8/15) E* sqrt(R*) = 1 at R* = 1
  unit.E_star = 15.0 / 8.0;
  for (const EulerTerm& t : terms) {
    const auto [u, F] = euler_load(t, unit, 1.0);
    e.energy += u;
    e.force += F;
    for (int a = 0; a < 3; ++a) e.node_force[t.node[a]] -= t.weights[a] * F;
  }
  return e;
}

// The sum over the contacts the one-contact-per-feature rule keeps, each U_H of its own overlap.
double per_contact(const TriangleMesh& m, const Vec3& x, double reach) {
  std::vector<MeshHit> hits = hits_of(m, m.vertices, x, reach);
  select_mesh_contacts(m, hits);
  double u = 0;
  for (const MeshHit& h : hits) u += std::pow(reach - std::sqrt(h.hit.distance2), 2.5);
  return u;
}

}  // namespace

TEST(EulerContact, AFlatTriangulationGivesThePlanesEnergy) {
  // floor_mesh: 8 x 8 cells of 1 mm with alternating diagonals (6 or 8 triangles at a vertex), the
  // sphere (R = 2 mm) above it at heights giving overlaps of 1e-4 to 0.3 of R, feet drawn at random
  // and on every vertex and edge midpoint of the middle cells.
  const TriangleMesh floor = floor_mesh(Vec3::Zero(), 0.008, 0.008, 8, 8);
  const double R = 0.002;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.002, 0.002), depth(-4, std::log10(0.3));
  std::vector<Vec3> feet;
  for (int k = 0; k < 400; ++k) feet.emplace_back(u(rng), u(rng), 0);
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j) {
      feet.emplace_back(0.001 * i, 0.001 * j, 0);
      feet.emplace_back(0.001 * i + 0.0005, 0.001 * j, 0);
      feet.emplace_back(0.001 * i, 0.001 * j + 0.0005, 0);
    }
  double worst = 0;
  std::size_t most = 0;
  for (const Vec3& foot : feet) {
    const double overlap = R * std::pow(10.0, depth(rng));
    const Euler e = euler(floor, floor.vertices, foot + Vec3(0, 0, R - overlap), R);
    worst = std::max(worst, std::abs(e.energy / std::pow(overlap, 2.5) - 1));
    worst = std::max(worst, (e.force - Vec3(0, 0, 2.5 * std::pow(overlap, 1.5))).norm() / (2.5 * std::pow(overlap, 1.5)));
    most = std::max(most, e.terms);
  }
  std::printf("  %zu places: largest relative difference from the plane's energy and force %.2e; most terms left %zu\n",
              feet.size(), worst, most);
  EXPECT_LT(worst, 1e-9);
  EXPECT_EQ(most, 1u);  // the terms of a flat sheet cancel in integers: one is left, the foot's
}

TEST(EulerContact, AnOpenSheetsBoundaryEdgeIsAContact) {
  // A sphere overhanging the edge y = -4 mm of the open floor, its centre 0.5 mm beyond it: the
  // contact is the edge's, overlap R - |x - q|.
  const TriangleMesh floor = floor_mesh(Vec3::Zero(), 0.008, 0.008, 8, 8);
  const double R = 0.002;
  const Vec3 x(0.00037, -0.0045, 0.0019);
  const double d = std::hypot(0.0005, 0.0019);
  const Euler e = euler(floor, floor.vertices, x, R);
  EXPECT_NEAR(e.energy, std::pow(R - d, 2.5), 1e-9 * std::pow(R - d, 2.5));
}

TEST(EulerContact, ContinuousAcrossAShallowFoldWhereTheContactsCountJumps) {
  // Two triangles folded into a valley along the y axis (each face 0.57 degrees off flat), a sphere
  // of R = 0.1 pressed 1% and 5e-4 of R into it, moved across the fold in 2e4 steps of h = 1e-6.
  // Bound of one step's change: each of the at most 3 terms (2 faces, the edge) changes its overlap
  // by at most h, so |dU| <= 3 x 2.5 delta_max^(3/2) h. The sum over the rule's contacts breaks it
  // where the second face's hit is born at positive overlap.
  TriangleMesh m;
  const double lift = 0.01;
  m.vertices = {Vec3(0, -1, 0), Vec3(0, 1, 0), Vec3(-1, 0, lift), Vec3(1, 0, lift)};
  m.triangles = {{0, 2, 1}, {0, 1, 3}};  // normals towards -z: away from the sphere's side (+z)
  build_topology(m);
  const double R = 0.1, h = 1e-6;
  for (double pressed : {0.01, 5e-4}) {
    const double z = R - pressed * R, bound = 3 * 2.5 * std::pow(1.1 * pressed * R, 1.5) * h;
    double prev = euler(m, m.vertices, Vec3(-0.01, 0.1, z), R).energy, prev_count = per_contact(m, Vec3(-0.01, 0.1, z), R);
    double worst = 0, worst_count = 0, lowest = HUGE_VAL;
    for (int k = 1; k <= 20000; ++k) {
      const Vec3 x(-0.01 + k * h, 0.1, z);
      const double e = euler(m, m.vertices, x, R).energy, c = per_contact(m, x, R);
      worst = std::max(worst, std::abs(e - prev));
      worst_count = std::max(worst_count, std::abs(c - prev_count));
      lowest = std::min(lowest, e / std::pow(pressed * R, 2.5));
      prev = e, prev_count = c;
    }
    std::printf("  overlap %.0e R: largest change in a step %.3e (bound %.3e), the rule's contacts' %.3e; least U / U_H(pressed) %.3f\n",
                pressed, worst, bound, worst_count, lowest);
    EXPECT_LE(worst, bound);
    EXPECT_GT(worst_count, 2 * bound);  // the scene has a birth at positive overlap
    EXPECT_GT(lowest, 0.9);
  }
}

TEST(EulerContact, TheStepperForcesAreTheGradientOfTheEnergy) {
  // A 20-mm ball pressed into a coarse sphere of film (80 triangles of radius 10.6 mm, each node
  // moved at random by up to 0.4 mm), 200 places whose terms keep their features over the
  // differences' steps; tolerance 1e-6 of the largest force.
  TriangleMesh film = sphere_mesh(Vec3::Zero(), 0.0106, 80);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (Vec3& v : film.vertices) v += 0.0004 * Vec3(u(rng), u(rng), u(rng));
  build_topology(film);
  const double R = 0.01, step = 1e-10;
  double worst = 0;
  int places = 0, tries = 0;
  std::size_t most = 0;
  while (places < 200 && ++tries < 20000) {
    const Vec3 dir = Vec3(u(rng), u(rng), u(rng)).normalized();
    const Vec3 x = (0.0004 + 0.0005 * std::abs(u(rng))) * dir;
    const Euler e0 = euler(film, film.vertices, x, R);
    if (e0.terms < 2) continue;
    double scale = e0.force.norm();
    for (const Vec3& f : e0.node_force) scale = std::max(scale, f.norm());
    double err = 0;
    bool same = true;
    auto compare = [&](const Euler& p, const Euler& m, double force) {
      same = same && p.terms == e0.terms && m.terms == e0.terms;
      err = std::max(err, std::abs(-(p.energy - m.energy) / (2 * step) - force) / scale);
    };
    for (int c = 0; c < 3 && same; ++c) {
      Vec3 xp = x, xm = x;
      xp[c] += step, xm[c] -= step;
      compare(euler(film, film.vertices, xp, R), euler(film, film.vertices, xm, R), e0.force[c]);
    }
    for (std::size_t k = 0; k < film.vertices.size() && same; ++k) {
      if (e0.node_force[k].squaredNorm() == 0) continue;
      for (int c = 0; c < 3; ++c) {
        std::vector<Vec3> p = film.vertices, m = film.vertices;
        p[k][c] += step, m[k][c] -= step;
        compare(euler(film, p, x, R), euler(film, m, x, R), e0.node_force[k][c]);
      }
    }
    if (!same) continue;
    ++places;
    most = std::max(most, e0.terms);
    worst = std::max(worst, err);
  }
  std::printf("  %d places (up to %zu terms): largest difference %.2e of the largest force\n", places, most, worst);
  EXPECT_EQ(places, 200);
  EXPECT_LT(worst, 1e-6);
}
