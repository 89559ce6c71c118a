// Which side of the film a ball is on (step/surface_features.hpp, oriented): judged at the touched
// feature by its angle-weighted pseudonormal (Baerentzen & Aanaes, IEEE TVCG 11(3), 2005). Reference:
// the generalized winding number of the closed surface (mesh/triangle_mesh.hpp, winding_number),
// exact for any point off the surface. On a sphere mesh whose nodes are moved radially at random
// (a closed, star-shaped surface that cannot cut itself, folded sharply between neighbouring nodes,
// as a film is between balls at high acceleration), every point within reach of the surface is
// judged at its nearest hit as the winding number says. The touched triangle's own normal (the rule
// before) misjudges some of the same points: the ones nearly in that triangle's plane beside a
// sharp fold, where a run stopped with "crossed the bag's film" while the ball was inside.
// A film doubled in a pleat (two layers closer than the reach): a ball on the inner side of the near
// layer also reaches the far one, seen from its outer side. The point's side is its nearest hit's
// (find_features): the far layer is no crossing and gives no contact of the law; a centre between
// the layers is a crossing.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "bagdem/mesh/shapes.hpp"
#include "bagdem/mesh/triangle_mesh.hpp"
#include "mesh_support.hpp"
#include "step/surface_features.hpp"

using namespace bagdem;
using namespace bagdem::surface_contacts;

namespace {

struct Judged {
  std::size_t points = 0;         // points within reach of the surface
  std::size_t pseudonormal = 0;   // judged wrong by oriented
  std::size_t face_normal = 0;    // judged wrong by the touched triangle's own normal
};

// Points drawn in the surface's bounding ball, each judged at its nearest hit (the one the theorem
// speaks of) among the contacts select_mesh_contacts keeps.
Judged judge(const TriangleMesh& m, const std::vector<Vec3>& vx, double reach, std::size_t draws, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Judged j;
  for (std::size_t d = 0; d < draws; ++d) {
    const Vec3 x(u(rng), u(rng), u(rng));
    std::vector<MeshHit> hits;
    for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
      const auto& tri = m.triangles[t];
      const TriangleHit h = closest_point_on_triangle(x, vx[tri[0]], vx[tri[1]], vx[tri[2]]);
      if (h.distance2 < reach * reach) hits.push_back({t, 0, h});
    }
    if (hits.empty()) continue;
    select_mesh_contacts(m, hits);
    const MeshHit& nearest = *std::min_element(hits.begin(), hits.end(), [](const MeshHit& a, const MeshHit& b) {
      return a.hit.distance2 < b.hit.distance2;
    });
    const bool inside = winding_number(m, vx, x) > 0.5;
    Vec3 n;
    double overlap;
    // side -1: inside, against the triangles' (outward) normals, as the bag's balls are.
    const bool own_side = oriented(x, vx, m, nearest, -1.0, reach, n, overlap);
    const auto& tri = m.triangles[nearest.triangle];
    const Vec3 face = (vx[tri[1]] - vx[tri[0]]).cross(vx[tri[2]] - vx[tri[0]]);
    const bool face_own_side = -(x - nearest.hit.point).dot(face) >= 0;
    ++j.points;
    j.pseudonormal += own_side != inside;
    j.face_normal += face_own_side != inside;
  }
  return j;
}

}  // namespace

TEST(FilmSide, PseudonormalJudgesEveryPointNearASharplyFoldedClosedFilm) {
  TriangleMesh m = sphere_mesh(Vec3::Zero(), 1.0, 320);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> radius(0.55, 1.0);
  for (Vec3& v : m.vertices) v = radius(rng) * v.normalized();  // star-shaped: it cannot cut itself
  build_topology(m);
  const Judged j = judge(m, m.vertices, 0.25, 40000, 5);
  ASSERT_GT(j.points, 5000u);
  EXPECT_EQ(j.pseudonormal, 0u) << "of " << j.points << " points";
  // The case is exercised: the face normal's rule misjudges some of these points.
  EXPECT_GT(j.face_normal, 0u) << "of " << j.points << " points";
  std::printf("points %zu: misjudged by the pseudonormal %zu, by the touched face's normal %zu\n", j.points, j.pseudonormal,
              j.face_normal);
}

TEST(FilmSide, SmoothClosedFilmAgreesWithTheFaceNormal) {
  // On the undeformed sphere mesh (no sharp fold) both rules judge every point right.
  TriangleMesh m = sphere_mesh(Vec3::Zero(), 0.8, 320);
  const Judged j = judge(m, m.vertices, 0.2, 20000, 3);
  ASSERT_GT(j.points, 3000u);
  EXPECT_EQ(j.pseudonormal, 0u);
  EXPECT_EQ(j.face_normal, 0u);
}

namespace {

struct Sheet {
  const TriangleMesh* mesh;
};

// other's vertices and triangles added to m, as one mesh (build_topology after).
void append(TriangleMesh& m, const TriangleMesh& other) {
  const auto base = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.insert(m.vertices.end(), other.vertices.begin(), other.vertices.end());
  for (auto t : other.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

// The contacts find_features gives a point at x (reach 1 unless given) against one mesh (every
// triangle a candidate), side -1; crossed: whether it reported a hit beyond the mid-surface;
// closed: the mesh is a closed film (PointView::closed).
std::vector<Found> contacts(const TriangleMesh& m, const Vec3& x, bool& crossed, bool closed = false, double reach = 1.0) {
  std::vector<Sheet> surfaces{{&m}};
  std::vector<MeshCandidates> cand(1);
  cand[0].begin = {0, static_cast<std::uint32_t>(m.triangles.size())};
  for (std::uint32_t t = 0; t < m.triangles.size(); ++t) cand[0].triangle.push_back(t);
  auto view = [&](std::uint32_t) { return PointView{x, &m.vertices, reach, -1.0, closed}; };
  crossed = false;
  auto touched = [&](std::uint32_t, double, double, bool own_side) { crossed = crossed || !own_side; };
  Found found[16];
  std::vector<EulerTerm> terms;
  const std::size_t nf = find_features<16>(surfaces, cand, 0, view, touched, [] {}, found, terms);
  return {found, found + nf};
}

}  // namespace

TEST(FilmSide, AFarLayerOfAPleatIsNeitherACrossingNorAContact) {
  // The near layer at z = 0 with its outer side down (normals -z: the ball above is inside), the
  // far layer 0.05 below it folded back (normals +z: its outer side faces the ball), one mesh.
  using bagdem::testing::floor_mesh;
  const TriangleMesh near = floor_mesh(Vec3(0, 0, 0), 4, 4, 8, 8);
  const TriangleMesh far = rectangle_mesh(Vec3(0, 0, -0.05), 4, 4, 8, 8);
  TriangleMesh m = near;
  append(m, far);
  build_topology(m);
  bool crossed = true;
  const std::vector<Found> above = contacts(m, Vec3(0.31, 0.27, 0.9), crossed);
  EXPECT_FALSE(crossed);
  ASSERT_EQ(above.size(), 1u);  // the near layer's one contact, as against a plane
  EXPECT_NEAR(above[0].n.z(), 1.0, 1e-12);
  EXPECT_NEAR(above[0].overlap, 0.1, 1e-12);
  EXPECT_LT(above[0].hit.triangle, near.triangles.size());
  // The centre between the layers: beyond the near layer's mid-surface, its nearest hit.
  contacts(m, Vec3(0.31, 0.27, -0.02), crossed);
  EXPECT_TRUE(crossed);
}

// A part of the film turned outside in (a 20-mm ball's bag at Gamma 20, crushed against the bore:
// two triangles by an edge, one of them a sliver, faced the ball with their outer sides while the
// ball's winding number was 1; the run stopped with "crossed the bag's film"; docs/verification.md,
// "The bag at the extremes"). Here: a small closed bubble inside the film (the two spheres' meshes
// as one, outward normals), its outer side facing the points between it and the film. Such a point
// is inside the film as a whole (winding number 1) while its nearest hit, on the bubble, is seen
// from its outer side. As a closed film (the bag's, PointView::closed) find_features reports no
// crossing and gives its contacts from the side the point is on (normals from the hit to the
// point); as an open surface it reports a crossing, as before. A point outside the film near it
// (winding number 0) is a crossing either way.
TEST(FilmSide, AFilmTurnedOutsideInIsNoCrossingForAPointInsideIt) {
  TriangleMesh m = sphere_mesh(Vec3::Zero(), 1.0, 320);
  const TriangleMesh bubble = sphere_mesh(Vec3(0.6, 0, 0), 0.2, 80);
  append(m, bubble);
  build_topology(m);
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  std::size_t tried = 0, wrong_normal = 0, crossed_closed = 0, crossed_open = 0;
  for (int k = 0; k < 200; ++k) {
    const Vec3 x = Vec3(0.6, 0, 0) + 0.27 * Vec3(g(rng), g(rng), g(rng)).normalized();  // 0.07 off the bubble
    if (x.norm() > 0.85) continue;  // keep clear of the film's outer sphere
    ASSERT_NEAR(winding_number(m, m.vertices, x), 1.0, 1e-9);
    ++tried;
    bool as_open = false, as_closed = true;
    contacts(m, x, as_open, false, 0.1);
    const std::vector<Found> closed = contacts(m, x, as_closed, true, 0.1);
    crossed_open += as_open, crossed_closed += as_closed;
    ASSERT_FALSE(closed.empty());
    for (const Found& f : closed) wrong_normal += f.n.dot(x - f.hit.hit.point) <= 0;
  }
  ASSERT_GT(tried, 100u);
  EXPECT_EQ(crossed_open, tried);
  EXPECT_EQ(crossed_closed, 0u);
  EXPECT_EQ(wrong_normal, 0u);
  // Outside the film, 0.02 beyond its mid-surface: a crossing, closed or not.
  for (bool closed : {false, true}) {
    bool crossed = false;
    contacts(m, Vec3(0, 0, 1.02), crossed, closed, 0.1);
    EXPECT_TRUE(crossed) << "closed " << closed;
  }
}
