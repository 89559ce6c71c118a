// Sphere against triangles (contact/sphere_triangle.hpp): the closest point of a triangle and its
// feature, and the one-contact-per-feature rule on meshes.
//
// References and tolerances:
//   closest_point_on_triangle against an independent reference (projection on the plane when it
//     falls inside, else the nearest of the three clamped segment projections): squared distance
//     to 1e-12 (1 + |p|^2), point to 1e-10, feature and local index equal wherever the reference
//     is not within 1e-9 of a region boundary; and against dense sampling of the triangle
//     (150 x 150 barycentric grid): no sample nearer than the result by more than 1e-12, and the
//     nearest sample within one grid step (longest edge / 150) of the result. All 7 regions hit
//     (at least 100 times each in 20000 random points).
//   triangle_distance2 (four triangles in lanes, no branches): the squared distance above to 1e-12
//     of the scene's size squared, at 1 m and 1 mm, degenerate triangles included (or NaN).
//   Weights: sum 1 to 1e-15, each in [0, 1], reproduce the point to 1e-14; on an edge the
//     opposite weight is exactly 0, at a vertex its weight is exactly 1 and the others 0.
//   select_mesh_contacts: on a flat sheet exactly one contact at the plane distance (to 1e-12)
//     for random centres and centres exactly above vertices and edges; outside a convex box near
//     an edge one Edge contact, near a corner one Vertex contact, at the analytic distance; inside
//     a box corner the three face contacts; around closed meshes no key twice, the nearest hit
//     kept, only face contacts from inside, exactly one from outside. Selection never reallocates.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <vector>

#include "bagdem/contact/sphere_triangle.hpp"
#include "bagdem/mesh/shapes.hpp"
#include "rng.hpp"

using namespace bagdem;
using bagdem::testing::Rng;

namespace {

struct Ref {
  double d2;
  Vec3 point;
  Feature feature;
  int local;
  bool near_boundary;  // within 1e-9 of a region boundary: the feature may round either way
};

// Independent reference: the plane projection when inside, else the best clamped segment.
Ref reference(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 x[3] = {a, b, c};
  const Vec3 n = (b - a).cross(c - a);
  const Vec3 q = p - n * (n.dot(p - a) / n.squaredNorm());
  const double wa = n.dot((b - q).cross(c - q)) / n.squaredNorm();
  const double wb = n.dot((c - q).cross(a - q)) / n.squaredNorm();
  const double wc = 1 - wa - wb;
  if (wa > 0 && wb > 0 && wc > 0) {
    const double m = std::min({wa, wb, wc});
    return {(p - q).squaredNorm(), q, Feature::Face, 0, m < 1e-9};
  }
  Ref best{1e300, Vec3::Zero(), Feature::Face, 0, false};
  for (int k = 0; k < 3; ++k) {
    const Vec3 e = x[(k + 1) % 3] - x[k];
    const double t_raw = (p - x[k]).dot(e) / e.squaredNorm();
    const double t = std::clamp(t_raw, 0.0, 1.0);
    const Vec3 pt = x[k] + t * e;
    const double d2 = (p - pt).squaredNorm();
    if (d2 < best.d2) {
      const bool interior = t_raw > 0 && t_raw < 1;
      best = {d2, pt, interior ? Feature::Edge : Feature::Vertex, interior ? k : (t_raw <= 0 ? k : (k + 1) % 3),
              std::abs(t_raw) < 1e-9 || std::abs(t_raw - 1) < 1e-9};
    }
  }
  best.near_boundary = best.near_boundary || std::min({std::abs(wa), std::abs(wb), std::abs(wc)}) < 1e-9;
  return best;
}

// Random triangle with vertices in [-1, 1]^3 (obtuse and skinny ones included), not degenerate.
std::array<Vec3, 3> random_triangle(Rng& rng) {
  for (;;) {
    std::array<Vec3, 3> t;
    for (auto& v : t) v = draw_vec3([&] { return rng.uniform(-1, 1); });
    if ((t[1] - t[0]).cross(t[2] - t[0]).norm() > 1e-3) return t;
  }
}

// Closest points of every triangle within reach R of p, ascending (what a broad phase hands over).
std::vector<MeshHit> hits_within(const TriangleMesh& m, const Vec3& p, double R) {
  std::vector<MeshHit> hits;
  for (std::uint32_t t = 0; t < m.size(); ++t) {
    const auto& v = m.triangles[t];
    const TriangleHit h = closest_point_on_triangle(p, m.vertices[v[0]], m.vertices[v[1]], m.vertices[v[2]]);
    if (h.distance2 < R * R) hits.push_back({t, 0, h});
  }
  return hits;
}

// Runs the selection and checks what must hold for any mesh: no reallocation, keys as documented,
// no key twice, the nearest hit kept. Returns the kept contacts.
std::vector<MeshHit> select(const TriangleMesh& m, std::vector<MeshHit> hits) {
  const std::vector<MeshHit> all = hits;
  const MeshHit* data = hits.data();
  const std::size_t cap = hits.capacity();
  select_mesh_contacts(m, hits);
  EXPECT_EQ(hits.data(), data);
  EXPECT_EQ(hits.capacity(), cap);
  std::set<std::uint32_t> keys;
  for (const MeshHit& h : hits) {
    EXPECT_TRUE(keys.insert(h.key).second) << "key " << h.key << " twice";
    const auto local = h.hit.local;
    switch (h.hit.feature) {
      case Feature::Face: EXPECT_EQ(h.key, feature_key(Feature::Face, h.triangle)); break;
      case Feature::Edge: EXPECT_EQ(h.key, feature_key(Feature::Edge, m.triangle_edges[h.triangle][local])); break;
      case Feature::Vertex: EXPECT_EQ(h.key, feature_key(Feature::Vertex, m.triangles[h.triangle][local])); break;
    }
  }
  if (!all.empty()) {
    EXPECT_FALSE(hits.empty());
    double nearest_all = 1e300, nearest_kept = 1e300;
    for (const auto& h : all) nearest_all = std::min(nearest_all, h.hit.distance2);
    for (const auto& h : hits) nearest_kept = std::min(nearest_kept, h.hit.distance2);
    // Ties (two triangles finding the same point of a shared edge) may differ in the last bits.
    EXPECT_NEAR(nearest_kept, nearest_all, 1e-12 * nearest_all);
  }
  return hits;
}

// Edges where the surface folds inwards (the far vertex of one triangle above the other's plane).
int concave_edges(const TriangleMesh& m) {
  int n = 0;
  for (std::size_t e = 0; e < m.edge_vertices.size(); ++e) {
    const auto [t1, t2] = m.edge_triangles[e];
    if (t2 == kNoTriangle) continue;
    const auto& a = m.triangles[t1];
    const Vec3 normal = (m.vertices[a[1]] - m.vertices[a[0]]).cross(m.vertices[a[2]] - m.vertices[a[0]]).normalized();
    for (std::uint32_t v : m.triangles[t2])
      if (v != m.edge_vertices[e][0] && v != m.edge_vertices[e][1] && (m.vertices[v] - m.vertices[a[0]]).dot(normal) > 1e-15)
        ++n;
  }
  return n;
}

// Axis-aligned box [lo, hi] with each face cut into k x k squares, two triangles each, outward.
TriangleMesh box_mesh(const Vec3& lo, const Vec3& hi, int k) {
  TriangleMesh m;
  std::map<std::array<int, 3>, std::uint32_t> id;
  auto node = [&](std::array<int, 3> l) {
    auto [it, fresh] = id.emplace(l, static_cast<std::uint32_t>(m.vertices.size()));
    if (fresh) {
      Vec3 x;
      for (int a = 0; a < 3; ++a) x[a] = lo[a] + (hi[a] - lo[a]) * l[a] / k;
      m.vertices.push_back(x);
    }
    return it->second;
  };
  struct Face {
    int a, u, v;
    bool high;
  };
  const Face faces[6] = {{0, 1, 2, true}, {0, 2, 1, false}, {1, 2, 0, true}, {1, 0, 2, false}, {2, 0, 1, true}, {2, 1, 0, false}};
  for (const Face& f : faces)
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j) {
        std::uint32_t q[4];
        const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
        for (int c = 0; c < 4; ++c) {
          std::array<int, 3> l{};
          l[f.a] = f.high ? k : 0;
          l[f.u] = i + di[c];
          l[f.v] = j + dj[c];
          q[c] = node(l);
        }
        m.triangles.push_back({q[0], q[1], q[2]});
        m.triangles.push_back({q[0], q[2], q[3]});
      }
  build_topology(m);
  return m;
}

}  // namespace

// ------------------------------------------------------------------------------------------------
// closest_point_on_triangle

TEST(SphereTriangle, ClosestPointMatchesReference) {
  Rng rng(11);
  std::map<std::pair<int, int>, int> regions;
  int compared = 0;
  for (int i = 0; i < 20000; ++i) {
    const auto t = random_triangle(rng);
    const Vec3 p = draw_vec3([&] { return rng.uniform(-2, 2); });
    const TriangleHit h = closest_point_on_triangle(p, t[0], t[1], t[2]);
    const Ref r = reference(p, t[0], t[1], t[2]);
    ASSERT_NEAR(h.distance2, r.d2, 1e-12 * (1 + p.squaredNorm())) << "point " << i;
    ASSERT_LT((h.point - r.point).norm(), 1e-10) << "point " << i;
    ASSERT_NEAR(h.distance2, (p - h.point).squaredNorm(), 1e-15 * (1 + p.squaredNorm()));
    ++regions[{static_cast<int>(h.feature), h.local}];
    if (!r.near_boundary) {
      ++compared;
      ASSERT_EQ(h.feature, r.feature) << "point " << i;
      ASSERT_EQ(h.local, r.local) << "point " << i;
    }
  }
  std::printf("  regions hit (feature, local: count):");
  for (const auto& [k, n] : regions) std::printf(" (%d,%d: %d)", k.first, k.second, n);
  std::printf("; features compared in %d of 20000\n", compared);
  EXPECT_EQ(regions.size(), 7u);
  for (const auto& [k, n] : regions) EXPECT_GE(n, 100);
}

TEST(SphereTriangle, ClosestPointNotBeatenBySampling) {
  Rng rng(12);
  const int N = 150;
  for (int i = 0; i < 150; ++i) {
    const auto t = random_triangle(rng);
    const Vec3 p = draw_vec3([&] { return rng.uniform(-2, 2); });
    const TriangleHit h = closest_point_on_triangle(p, t[0], t[1], t[2]);
    double best = 1e300;
    for (int u = 0; u <= N; ++u)
      for (int v = 0; u + v <= N; ++v) {
        const Vec3 s = t[0] + (t[1] - t[0]) * (double(u) / N) + (t[2] - t[0]) * (double(v) / N);
        best = std::min(best, (p - s).squaredNorm());
      }
    const double longest = std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()});
    ASSERT_GE(best, h.distance2 - 1e-12) << "a sample is nearer, point " << i;
    ASSERT_LE(std::sqrt(best) - std::sqrt(h.distance2), longest / N) << "point " << i;
  }
}

TEST(SphereTriangle, WeightsAndFeatures) {
  Rng rng(13);
  for (int i = 0; i < 20000; ++i) {
    const auto t = random_triangle(rng);
    const Vec3 p = draw_vec3([&] { return rng.uniform(-2, 2); });
    const TriangleHit h = closest_point_on_triangle(p, t[0], t[1], t[2]);
    const Vec3& w = h.weights;
    ASSERT_NEAR(w.sum(), 1.0, 1e-15);
    for (int k = 0; k < 3; ++k) {
      ASSERT_GE(w[k], 0.0);
      ASSERT_LE(w[k], 1.0);
    }
    ASSERT_LT((w[0] * t[0] + w[1] * t[1] + w[2] * t[2] - h.point).norm(), 1e-14);
    switch (h.feature) {
      case Feature::Vertex:
        ASSERT_EQ(w[h.local], 1.0);
        ASSERT_EQ(w[(h.local + 1) % 3], 0.0);
        ASSERT_EQ(w[(h.local + 2) % 3], 0.0);
        ASSERT_EQ(h.point, t[h.local]);
        break;
      case Feature::Edge:
        ASSERT_LT(h.local, 3);
        ASSERT_EQ(w[(h.local + 2) % 3], 0.0);
        break;
      case Feature::Face:
        ASSERT_EQ(h.local, 0);
        break;
    }
  }
}

TEST(SphereTriangle, DegenerateTriangleStaysFinite) {
  // Collinear and coincident corners (a film element crushed flat): the result is the nearest
  // point of the segment they span.
  Rng rng(14);
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(2, 0, 0);
  for (int i = 0; i < 1000; ++i) {
    const double pz = rng.uniform(-1, 1), py = rng.uniform(-1, 1), px = rng.uniform(-1, 3);  // draw_vec3's order
    const Vec3 p(px, py, pz);
    for (const auto& tri : {std::array<Vec3, 3>{a, b, c}, std::array<Vec3, 3>{b, c, a}, std::array<Vec3, 3>{a, a, a}}) {
      const TriangleHit h = closest_point_on_triangle(p, tri[0], tri[1], tri[2]);
      ASSERT_TRUE(h.point.allFinite() && h.weights.allFinite() && std::isfinite(h.distance2));
      const double lo = std::min({tri[0].x(), tri[1].x(), tri[2].x()}), hi = std::max({tri[0].x(), tri[1].x(), tri[2].x()});
      const Vec3 expect(std::clamp(p.x(), lo, hi), 0, 0);
      ASSERT_NEAR(h.distance2, (p - expect).squaredNorm(), 1e-12);
    }
  }
}

TEST(SphereTriangle, DistanceInLanesMatchesTheClosestPoint) {
  // triangle_distance2 passes over the candidates beyond reach before the exact test: it must give
  // closest_point_on_triangle's squared distance to rounding (here 1e-12 of the scene's size
  // squared, at a metre and at a film's millimetres), and never more for a degenerate triangle.
  Rng rng(15);
  for (const double scale : {1.0, 1e-3}) {
    for (int i = 0; i < 5000; ++i) {
      std::array<Vec3, 3> t[kLanes];
      Vec3 p = draw_vec3([&] { return rng.uniform(-2, 2); }) * scale;
      for (auto& tri : t) {
        tri = random_triangle(rng);
        for (Vec3& v : tri) v *= scale;
      }
      if (i % 50 == 0) t[i / 50 % kLanes] = {t[0][0], t[0][1], 0.5 * (t[0][0] + t[0][1])};  // collinear
      auto corner = [&](int k) {
        const double* at[kLanes] = {t[0][k].data(), t[1][k].data(), t[2][k].data(), t[3][k].data()};
        return gather3(at);
      };
      const Lanes3 x{splat<Lanes>(p.x()), splat<Lanes>(p.y()), splat<Lanes>(p.z())};
      const Lanes d2 = triangle_distance2(x, corner(0), corner(1), corner(2));
      for (int l = 0; l < kLanes; ++l) {
        const double exact = closest_point_on_triangle(p, t[l][0], t[l][1], t[l][2]).distance2;
        const double tol = 1e-12 * (p.squaredNorm() + scale * scale);
        if (std::isnan(d2[l])) continue;  // a degenerate triangle: never passed over
        ASSERT_NEAR(d2[l], exact, tol) << "scale " << scale << ", point " << i << ", lane " << l;
      }
    }
  }
}

// ------------------------------------------------------------------------------------------------
// select_mesh_contacts

TEST(SphereTriangle, FlatSheetHasOneContact) {
  const Vec3 c(0.05, -0.02, 0.3);
  const TriangleMesh m = rectangle_mesh(c, 1.0, 1.0, 10, 10);  // cells 0.1, alternating diagonals
  const double R = 0.1;
  Rng rng(21);
  std::vector<Vec3> feet;  // foot points on the sheet
  for (int i = 0; i < 3000; ++i) {
    const double y = rng.uniform(-0.3, 0.3), x = rng.uniform(-0.3, 0.3);  // draw_vec3's order
    feet.push_back(c + Vec3(x, y, 0));
  }
  // Exactly above interior vertices, edge midpoints (axis-parallel and diagonal) and random points
  // on edges.
  for (std::size_t e = 0; e < m.edge_vertices.size(); ++e) {
    const Vec3 &a = m.vertices[m.edge_vertices[e][0]], &b = m.vertices[m.edge_vertices[e][1]];
    if (((a + b) / 2 - c).cwiseAbs().maxCoeff() > 0.35) continue;
    feet.push_back(a);
    feet.push_back(0.5 * (a + b));
    feet.push_back(a + rng.uniform() * (b - a));
  }
  std::map<int, int> features;
  std::size_t most_hits = 0;
  for (const Vec3& foot : feet) {
    const double h = rng.uniform(0.001, 0.099);
    const Vec3 p = foot + Vec3(0, 0, h);
    const std::vector<MeshHit> hits = hits_within(m, p, R);
    most_hits = std::max(most_hits, hits.size());
    const std::vector<MeshHit> kept = select(m, hits);
    ASSERT_EQ(kept.size(), 1u) << "centre " << p.transpose() << ", " << hits.size() << " hits";
    ASSERT_NEAR(std::sqrt(kept[0].hit.distance2), h, 1e-12);
    ++features[static_cast<int>(kept[0].hit.feature)];
  }
  // The documented example: before the agreement condition, 5 contacts survived here.
  const TriangleMesh m0 = rectangle_mesh(Vec3(0, 0, 0), 1, 1, 10, 10);
  const Vec3 p0(0.2468, -0.0895, 0.0117);
  const auto hits0 = hits_within(m0, p0, 0.1);
  const auto kept0 = select(m0, hits0);
  ASSERT_EQ(kept0.size(), 1u);
  EXPECT_EQ(kept0[0].hit.feature, Feature::Face);
  EXPECT_NEAR(std::sqrt(kept0[0].hit.distance2), 0.0117, 1e-15);
  std::printf("  %zu centres, up to %zu hits each; the one contact: %d face, %d edge, %d vertex\n", feet.size(),
              most_hits, features[0], features[1], features[2]);
  EXPECT_GT(features[1], 0);
  EXPECT_GT(features[2], 0);
}

TEST(SphereTriangle, ConvexEdgeAndCornerOfABox) {
  const TriangleMesh m = box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), 4);
  Rng rng(22);
  const double R = 0.08, gap = 0.05;
  for (int i = 0; i < 500; ++i) {
    // Outside the edge x = y = 1 (in its normal wedge), away from the corners.
    const double phi = rng.uniform(0.02, 1.55);
    const double z = i % 10 == 0 ? 0.25 * (1 + i % 3) : rng.uniform(0.1, 0.9);  // also at mesh vertices
    const Vec3 p(1 + gap * std::cos(phi), 1 + gap * std::sin(phi), z);
    const auto kept = select(m, hits_within(m, p, R));
    ASSERT_EQ(kept.size(), 1u) << p.transpose();
    EXPECT_NEAR(std::sqrt(kept[0].hit.distance2), gap, 1e-12);
    EXPECT_EQ(kept[0].hit.feature, i % 10 == 0 ? Feature::Vertex : Feature::Edge) << p.transpose();
    // Outside the corner (1, 1, 1), in its normal cone.
    const Vec3 d = draw_vec3([&] { return rng.uniform(0.05, 1); }).normalized();
    const auto corner = select(m, hits_within(m, Vec3(1, 1, 1) + gap * d, R));
    ASSERT_EQ(corner.size(), 1u);
    EXPECT_EQ(corner[0].hit.feature, Feature::Vertex);
    EXPECT_NEAR(std::sqrt(corner[0].hit.distance2), gap, 1e-12);
  }
}

TEST(SphereTriangle, ConcaveCornerKeepsTheFaceContacts) {
  const TriangleMesh m = box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), 4);
  Rng rng(23);
  for (int i = 0; i < 300; ++i) {
    // Inside near the corner at the origin: touches the three faces through it.
    const Vec3 p = draw_vec3([&] { return rng.uniform(0.02, 0.09); });
    const auto kept = select(m, hits_within(m, p, 0.1));
    ASSERT_EQ(kept.size(), 3u) << p.transpose();
    std::vector<double> d;
    for (const auto& h : kept) d.push_back(std::sqrt(h.hit.distance2));
    std::sort(d.begin(), d.end());
    std::vector<double> expect = {p.x(), p.y(), p.z()};
    std::sort(expect.begin(), expect.end());
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(d[k], expect[k], 1e-12);
    // Inside along the edge x = y = 0: the two faces through it.
    const double qz = rng.uniform(0.2, 0.8), qy = rng.uniform(0.02, 0.09), qx = rng.uniform(0.02, 0.09);  // draw_vec3's order
    const Vec3 q(qx, qy, qz);
    const auto two = select(m, hits_within(m, q, 0.1));
    ASSERT_EQ(two.size(), 2u) << q.transpose();
  }
}

TEST(SphereTriangle, ClosedMeshesFromOutsideAndInside) {
  Rng rng(24);
  const TriangleMesh box = box_mesh(Vec3(-0.05, -0.05, -0.05), Vec3(0.05, 0.05, 0.05), 5);
  const TriangleMesh ball = sphere_mesh(Vec3(0, 0, 0), 0.05, 500);
  // The remeshed pillow is not exactly convex (its Delaunay flips pick diagonals by angle): from
  // outside, a sphere over a slightly concave edge rightly touches both faces there. Only the
  // general rules are checked on it.
  const TriangleMesh pill = pillow_mesh(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.1, 0.1, 0.1), 4, 500);
  ASSERT_EQ(concave_edges(box), 0);
  ASSERT_EQ(concave_edges(ball), 0);
  const int pill_concave = concave_edges(pill);
  int outside = 0, inside = 0, inside_multi = 0, pill_multi = 0;
  for (const TriangleMesh* m : {&box, &ball, &pill}) {
    for (int i = 0; i < 1500; ++i) {
      const double R = rng.uniform(0.005, 0.03);
      const Vec3 p = rng.unit() * rng.uniform(0.0, 0.09);
      const auto hits = hits_within(*m, p, R);
      if (hits.empty()) continue;
      const auto kept = select(*m, hits);  // no key twice, nearest kept, keys right
      if (m == &pill) {
        pill_multi += kept.size() > 1;
        continue;
      }
      if (winding_number(*m, m->vertices, p) < 0.5) {
        // Outside a convex surface a small sphere has one nearest feature.
        ++outside;
        ASSERT_EQ(kept.size(), 1u) << p.transpose() << " R " << R;
      } else {
        // Inside, every edge and vertex is concave: only faces carry contacts.
        ++inside;
        inside_multi += kept.size() > 1;
        for (const auto& h : kept) ASSERT_EQ(h.hit.feature, Feature::Face) << p.transpose() << " R " << R;
      }
    }
  }
  std::printf("  box and sphere: %d spheres outside (one contact each), %d inside (%d with several face contacts)\n",
              outside, inside, inside_multi);
  std::printf("  pillow (%d of %zu edges concave): %d spheres with several contacts\n", pill_concave,
              pill.edge_vertices.size(), pill_multi);
  EXPECT_GT(outside, 300);
  EXPECT_GT(inside, 300);
  EXPECT_GT(inside_multi, 30);
}

// ---- joined patches (blend_patch) ------------------------------------------------------------------

// A sphere of radius R at x against two planes through the origin tilted by +-a about the y axis
// (a valley: normals 2a apart): the planes' overlaps R - n_i . x, deepest first.
struct Valley {
  double R, a;
  std::array<Vec3, 2> n() const { return {Vec3(-std::sin(a), 0, std::cos(a)), Vec3(std::sin(a), 0, std::cos(a))}; }
  PatchBlend at(const Vec3& x) const {
    auto nn = n();
    double d[2] = {R - nn[0].dot(x), R - nn[1].dot(x)};
    if (d[1] > d[0]) std::swap(d[0], d[1]), std::swap(nn[0], nn[1]);
    return blend_patch(nn.data(), d, 2);
  }
};

TEST(PatchBlend, ForceIsTheGradientOfTheJoinedOverlap) {
  // Reference: central differences of the joined overlap (step 1e-10 m, overlaps ~1e-5 m); the
  // force direction scale x n must be -grad(delta) to 1e-6 and c_i = d delta / d delta_i to 1e-6,
  // at points across the valley floor (the deepest hit changes sides at x = 0).
  const Valley v{5e-3, 13.0 * M_PI / 180};
  const double h = 1e-10;
  double worst_grad = 0, worst_c = 0;
  for (double x = -2e-5; x <= 2e-5; x += 1.7e-6) {
    const Vec3 p(x, 0.3e-3, v.R - 1e-5);
    const PatchBlend b = v.at(p);
    Vec3 grad;
    for (int k = 0; k < 3; ++k) {
      Vec3 e = Vec3::Zero();
      e[k] = h;
      grad[k] = (v.at(p + e).overlap - v.at(p - e).overlap) / (2 * h);
    }
    worst_grad = std::max(worst_grad, (grad + b.scale * b.n).norm() / grad.norm());
    // c_0 by moving the deepest plane alone: delta_0 + eps.
    auto nn = v.n();
    double d[2] = {v.R - nn[0].dot(p), v.R - nn[1].dot(p)};
    if (d[1] > d[0]) std::swap(d[0], d[1]), std::swap(nn[0], nn[1]);
    double dp[2] = {d[0] + h, d[1]}, dm[2] = {d[0] - h, d[1]};
    const double c0 = (blend_patch(nn.data(), dp, 2).overlap - blend_patch(nn.data(), dm, 2).overlap) / (2 * h);
    worst_c = std::max(worst_c, std::abs(c0 - b.c[0]));
  }
  std::printf("PatchBlend: |grad delta + scale n| / |grad delta| at most %.2e, |c_0 - d delta/d delta_0| at most %.2e\n",
              worst_grad, worst_c);
  EXPECT_LT(worst_grad, 1e-6);
  EXPECT_LT(worst_c, 1e-6);
}

TEST(PatchBlend, EqualHitsAndAFaintOne) {
  // Two equally deep hits: delta = 2^(1/8) delta_i, c_i = 2^(-7/8), shares 1/2; a hit at 1/10 of
  // the deepest: delta within 1e-8 of the deepest, c_1 = 1e-7 (p = 8), the normal the deepest's.
  const Vec3 n[2] = {Vec3(-0.2, 0, 1).normalized(), Vec3(0.2, 0, 1).normalized()};
  const double equal[2] = {1e-5, 1e-5}, faint[2] = {1e-5, 1e-6};
  const PatchBlend a = blend_patch(n, equal, 2), b = blend_patch(n, faint, 2);
  EXPECT_NEAR(a.overlap, std::pow(2.0, 0.125) * 1e-5, 1e-18);
  EXPECT_NEAR(a.c[0], std::pow(2.0, -0.875), 1e-14);
  EXPECT_NEAR(a.share[1], 0.5, 1e-14);
  EXPECT_NEAR((a.n - Vec3::UnitZ()).norm(), 0, 1e-14);
  EXPECT_NEAR(b.overlap, 1e-5, 1e-13);
  EXPECT_NEAR(b.c[1], 1e-7, 1e-12);
  EXPECT_LT((b.n - n[0]).norm(), 1e-6);
}
