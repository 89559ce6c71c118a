// Rigid triangulated (STL) walls against their analytic counterparts.
//
// 1. MeshWallPlane: a sphere (radius 5 mm, 1 m/s normal speed) hitting a plane and the same plane
//    as a triangulated patch (3 mm square of 100 x 100 cells, 30 um: every triangle within 0.8 mm
//    of the foot is within reach, and an 80-degree impact slides across 45 cells) rebounds with the
//    same velocity and spin. Head-on (inside a face, mid-edge on each kind of edge, on vertices with
//    4 and 8 triangles), oblique at 10, 45 and 80 degrees from the normal with mu = 0 and 0.3, with
//    rolling resistance and spin, grazing exactly along a row of edges and along the line of
//    diagonals, and grazing through vertices (dyadic grid and step: the foot lands on a vertex every
//    4 steps). At every step in contact the mesh has exactly one contact (mesh_contact_count).
//    Measured: |dv|/|v| and |dw| R/|v| <= 2e-18, most cases bitwise equal; tolerance 1e-12.
// 2. MeshWallBox: a closed box STL (12 triangles, and 8 x 8 cells a face) vs the analytic box,
//    through load_case, shaken harmonically with 8 balls inside under gravity (30 ms): positions
//    agree to 2e-16 m, cavity force and torque samples to 2e-13 of their peaks, contact counts and
//    energy budgets agree, and the balls' momentum change equals gravity's impulse plus the wall
//    impulse the cavity samples report (so the STL contacts are in the cavity load). And a wall
//    that comes to a ball at rest (candidate lists follow the cavity).
// 3. MeshWallCoarse: triangles much larger than the ball (0.2 m squares of 2 and 8 triangles) hold
//    it as the plane does: the same force during a slow push (1 cm/s), and a ball dropped under
//    gravity rests at the Hertz static overlap for 1500 contact times, in a face, on a diagonal
//    edge and on the vertex where 8 triangles meet.
// 4. MeshWallCase: STL errors through `bagdem check`: exit 2 naming the file (missing file, an
//    edge with 4 triangles, a face turned over).
//
// Materials as in test_oblique_impact.cpp: steel density and Poisson ratio, modulus 2 GPa.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "bagdem/case/load_case.hpp"
#include "bagdem/contact/hertz_theory.hpp"
#include "bagdem/contact/sphere_triangle.hpp"
#include "bagdem/mesh/stl.hpp"
#include "bagdem/motion/motion.hpp"
#include "bagdem/step/simulation.hpp"
#include "mesh_support.hpp"
#include "scene_builder.hpp"
#include "support.hpp"

using namespace bagdem;
using bagdem::testing::box_soup;
using bagdem::testing::CaseText;
using bagdem::testing::steel_scene;
using bagdem::testing::vec;
using bagdem::testing::floor_mesh;
using bagdem::testing::SceneBuilder;
using bagdem::testing::sphere_mass;
using bagdem::testing::TempDir;

namespace {

constexpr double kRho = 7800, kE = 2e9, kNu = 0.3, kR = 5e-3;

// ---- 1. plane vs triangulated plane ---------------------------------------------------------------

struct ImpactSpec {
  Vec3 v0;                    // initial velocity (v0.z() < 0)
  Vec3 w0 = Vec3::Zero();     // initial spin
  Vec3 foot = Vec3::Zero();   // where the sphere first touches the floor z = 0 (x, y)
  double e = 0.5, mu = 0, mu_r = 0;
  double phase = 0.37;        // where in a step the contact opens
};

struct Outcome {
  Vec3 v_plane, w_plane, v_mesh, w_mesh;
  double dv_rel = 0;          // |v_mesh - v_plane| / |v_plane| after the impact
  double dw_rel = 0;          // |w_mesh - w_plane| R / |v_plane| (spin as a surface speed)
  double force_rel = 0;       // largest |F_mesh - F_plane| over the contact / largest |F_plane|
  int touching = 0;           // steps with the mesh ball overlapping the floor
  int not_one = 0;            // of those, steps whose mesh contact count was not 1
  std::size_t most = 0;       // largest mesh contact count seen
  int count_when_apart = 0;   // steps apart with a mesh contact anyway
  std::set<std::uint32_t> faces, edges, vertices;  // features the contact visited
};

Scene impact_scene(const ImpactSpec& s, bool mesh, const TriangleMesh& floor, double& dt) {
  // One ball, no wall; built once per interaction (building the pair laws takes ~0.1 s).
  static std::map<std::array<double, 3>, Scene> built;
  const std::array<double, 3> key{s.e, s.mu, s.mu_r};
  if (!built.count(key)) {
    SceneBuilder b;
    b.material("soft steel", kRho, kE, kNu).interaction(s.e, s.mu, s.mu_r).particle(Vec3::Zero(), Vec3::Zero(), kR).dt(1.0);
    built.emplace(key, b.build());
  }
  Scene scene = built.at(key);
  scene.particles[0].v = s.v0;
  scene.particles[0].w = s.w0;
  if (!mesh) {
    scene.walls.push_back({WallKind::Plane, Vec3::Zero(), Vec3::UnitZ(), 0, 0});
    scene.wall_names.push_back("floor");
  }
  // The step of test_oblique_impact.cpp: t_c / 40 at the normal speed, or half the critical step.
  const double m = sphere_mass(kRho, kR), vn = -s.v0.z();
  const PairLaw& law = scene.laws(0, 0);
  const double tc = hertz::contact_time(m, kR, law.E_star, vn);
  const double delta = hertz::max_overlap(m, kR, law.E_star, vn);
  const double S_n = 2 * law.E_star * std::sqrt(kR * delta), S_t = S_n * 4 * law.G_star / law.E_star;
  const double crit = std::min(hertz::critical_step(std::sqrt(S_n / m), 0.5 * law.damping),
                               hertz::critical_step(std::sqrt(3.5 * S_t / m), 0.5 * law.damping));
  dt = std::min(hertz::resolved_step(tc, hertz::damping_parameter(law.damping), 40), 0.5 * crit);
  scene.dt = dt;
  const double lead = (2 + s.phase) * dt;  // the contact opens `lead` after the start
  scene.particles[0].x = Vec3(s.foot.x(), s.foot.y(), kR) - lead * s.v0;
  if (mesh) scene.mesh_walls.push_back({"floor", floor, 0});
  return scene;
}

// Features the kernel's rule keeps for a sphere at x (the same functions as the stepper).
std::vector<MeshHit> contacts_of(const TriangleMesh& m, const Vec3& x, double r) {
  std::vector<MeshHit> hits;
  for (std::uint32_t t = 0; t < m.size(); ++t) {
    const auto& tri = m.triangles[t];
    const TriangleHit h = closest_point_on_triangle(x, m.vertices[tri[0]], m.vertices[tri[1]], m.vertices[tri[2]]);
    if (h.distance2 < r * r) hits.push_back({t, 0, h});
  }
  select_mesh_contacts(m, hits);
  return hits;
}

Outcome plane_vs_mesh(const ImpactSpec& s, const TriangleMesh& floor) {
  double dt = 0;
  const Scene sp = impact_scene(s, false, floor, dt);
  const Scene sm = impact_scene(s, true, floor, dt);
  Simulation a(sp), b(sm);
  const auto &pa = a.particles(), &pb = b.particles();
  Outcome o;
  double f_max = 0, df_max = 0;
  bool in = false, out = false;
  for (int k = 0; k < 100000 && !out; ++k) {
    a.step();
    b.step();
    const bool ta = pa.x[0].z() < kR, tb = pb.x[0].z() < kR;
    const std::size_t count = b.mesh_contact_count();
    if (tb) {
      ++o.touching;
      if (count != 1) ++o.not_one;
      o.most = std::max(o.most, count);
      for (const MeshHit& h : contacts_of(floor, pb.x[0], kR)) {
        const auto kind = static_cast<Feature>(h.key >> 30);
        (kind == Feature::Face ? o.faces : kind == Feature::Edge ? o.edges : o.vertices).insert(h.key);
      }
    } else if (count != 0) {
      ++o.count_when_apart;
    }
    if (ta || tb) {
      f_max = std::max(f_max, pa.f[0].norm());
      df_max = std::max(df_max, (pb.f[0] - pa.f[0]).norm());
    }
    in = in || ta || tb;
    out = in && !ta && !tb;
  }
  EXPECT_TRUE(out) << "the contact never closed";
  a.step();
  b.step();
  o.v_plane = pa.v[0];
  o.w_plane = pa.w[0];
  o.v_mesh = pb.v[0];
  o.w_mesh = pb.w[0];
  const double vs = pa.v[0].norm();
  o.dv_rel = (pb.v[0] - pa.v[0]).norm() / vs;
  o.dw_rel = (pb.w[0] - pa.w[0]).norm() * kR / vs;
  o.force_rel = df_max / f_max;
  return o;
}

// Tolerance of the rebound comparison: the triangulated plane's normal and overlap come from a
// closest point and a square root instead of a dot product, so they may differ from the plane's in
// the last bits. Measured (GCC, -O3): at most 2e-18 relative, most cases bitwise equal; forces
// during the contact within 2e-18 of the peak. 1e-12 leaves room for other compilers and FMA.
constexpr double kRebound = 1e-12;

// The patch: 3 mm square of 100 x 100 cells (30 um; 20000 right triangles), the impact near its
// middle. The ball (radius 5 mm) overlaps the plane by up to 60 um at 1 m/s, so every triangle
// within sqrt(2 R delta) ~ 0.8 mm of the foot is in reach (~2000) and the one-contact-per-feature
// rule has to discard all but one. The contact lasts t_c ~ 0.24 ms: at tan(angle) m/s along the
// plane the foot slides 0.04 mm (10 degrees), 0.24 mm (45) and 1.4 mm (80, 45 cells).
constexpr double kPatch = 3e-3;
constexpr std::size_t kCells = 100;

// Hertz contact time of the impacts here (normal speed 1 m/s).
double contact_time() {
  const Material m{"soft steel", kRho, kE, kNu};
  return hertz::contact_time(sphere_mass(kRho, kR), kR, effective_youngs(m, m), 1.0);
}

void expect_same(const char* what, const Outcome& o) {
  std::printf("  %-34s |dv|/|v| %.1e  |dw|R/|v| %.1e  max|dF|/max|F| %.1e  steps %3d (faces %zu, edges %zu, "
              "vertices %zu)  contacts != 1: %d steps (most %zu)\n",
              what, o.dv_rel, o.dw_rel, o.force_rel, o.touching, o.faces.size(), o.edges.size(), o.vertices.size(),
              o.not_one, o.most);
  EXPECT_LT(o.dv_rel, kRebound) << what << ": v plane " << o.v_plane.transpose() << ", mesh " << o.v_mesh.transpose();
  EXPECT_LT(o.dw_rel, kRebound) << what << ": w plane " << o.w_plane.transpose() << ", mesh " << o.w_mesh.transpose();
  EXPECT_GT(o.touching, 20) << what;
  EXPECT_EQ(o.not_one, 0) << what << ": steps in contact without exactly one mesh contact (most " << o.most << ")";
  EXPECT_EQ(o.count_when_apart, 0) << what << ": mesh contacts while apart";
}

// In-plane unit vector at angle phi (radians) from x.
Vec3 along(double phi) { return Vec3(std::cos(phi), std::sin(phi), 0); }

}  // namespace

TEST(MeshWallPlane, HeadOnInAFaceOnAnEdgeAndOnAVertex) {
  // No sliding: the middle 0.6 mm of the patch (20 x 20 cells of 30 um; all in reach) will do.
  const std::size_t cells = 20;
  const TriangleMesh floor = floor_mesh(Vec3::Zero(), kPatch * cells / kCells, kPatch * cells / kCells, cells, cells);
  const std::size_t row = cells + 1;
  // Vertex (i, j) is vertices[j * row + i]; with alternating diagonals, i + j odd has 4 triangles
  // around it, i + j even has 8 (every diagonal of the 4 cells meets there).
  const Vec3 vtx = floor.vertices[13 * row + 12];
  const Vec3 vtx8 = floor.vertices[10 * row + 10];
  const Vec3 xedge = 0.5 * (floor.vertices[13 * row + 11] + floor.vertices[13 * row + 12]);  // along x
  const Vec3 yedge = 0.5 * (floor.vertices[13 * row + 11] + floor.vertices[14 * row + 11]);  // along y
  const Vec3 diag = 0.5 * (floor.vertices[8 * row + 8] + floor.vertices[9 * row + 9]);       // a diagonal
  const struct {
    const char* name;
    Vec3 foot;
  } where[] = {{"head-on, in a face", Vec3(1.234e-6, -2.71e-6, 0)},
               {"head-on, on a vertex (4 triangles)", vtx},
               {"head-on, on a vertex (8 triangles)", vtx8},
               {"head-on, mid x-edge", xedge},
               {"head-on, mid y-edge", yedge},
               {"head-on, mid diagonal", diag}};
  for (const auto& w : where)
    for (double mu : {0.0, 0.3}) {
      ImpactSpec s;
      s.v0 = Vec3(0, 0, -1);
      s.foot = w.foot;
      s.mu = mu;
      const Outcome o = plane_vs_mesh(s, floor);
      expect_same((std::string(w.name) + (mu > 0 ? ", mu 0.3" : ", mu 0")).c_str(), o);
      EXPECT_NEAR(o.v_mesh.z(), 0.5, 0.01) << w.name;  // the requested restitution
    }
}

TEST(MeshWallPlane, ObliqueImpactsWithAndWithoutFriction) {
  const TriangleMesh floor = floor_mesh(Vec3::Zero(), kPatch, kPatch, kCells, kCells);
  // Normal speed 1 m/s, tangential tan(angle) m/s along 20 degrees from x (the path crosses
  // x-edges, y-edges and diagonals); the foot starts 60 um before the middle.
  const Vec3 t = along(20 * std::numbers::pi / 180);
  const double tc = contact_time();
  for (double deg : {10.0, 45.0, 80.0})
    for (double mu : {0.0, 0.3}) {
      ImpactSpec s;
      const double vt = std::tan(deg * std::numbers::pi / 180);
      s.v0 = vt * t - Vec3::UnitZ();
      s.foot = Vec3(0.123e-6, 0.0457e-6, 0) - 0.5 * vt * tc * t;  // the slide centred on the patch
      s.mu = mu;
      const Outcome o = plane_vs_mesh(s, floor);
      char name[64];
      std::snprintf(name, sizeof name, "%2.0f deg, mu %.1f", deg, mu);
      expect_same(name, o);
      // The contact really crosses the triangulation at 45 and 80 degrees.
      if (deg >= 45) {
        EXPECT_GE(o.faces.size(), 3u) << name;
      }
      if (mu == 0) {
        EXPECT_LT(o.w_mesh.norm() * kR, 1e-12) << name;  // no friction, no spin
      } else {
        EXPECT_GT(o.w_mesh.norm() * kR, 1e-3) << name;
      }
    }
}

TEST(MeshWallPlane, RollingResistanceAndSpin) {
  const TriangleMesh floor = floor_mesh(Vec3::Zero(), kPatch, kPatch, kCells, kCells);
  const Vec3 t = along(-35 * std::numbers::pi / 180);
  const Vec3 axis = Vec3::UnitZ().cross(t);
  const double tc = contact_time();
  for (double deg : {45.0, 80.0}) {
    ImpactSpec s;
    const double vt = std::tan(deg * std::numbers::pi / 180);
    s.v0 = vt * t - Vec3::UnitZ();
    s.w0 = -150.0 * axis + Vec3(0, 0, 40);  // backspin and spin about the normal
    s.foot = Vec3(-0.0771e-6, 0.311e-6, 0) - 0.5 * vt * tc * t;
    s.mu = 0.3;
    s.mu_r = 0.05;
    const Outcome o = plane_vs_mesh(s, floor);
    char name[64];
    std::snprintf(name, sizeof name, "%2.0f deg, mu 0.3, mu_r 0.05, spin", deg);
    expect_same(name, o);
  }
}

TEST(MeshWallPlane, GrazingAlongALineOfEdges) {
  // The foot runs exactly along a grid line y = y_j (edges along x), and along the main diagonal
  // (every cell (i, i) has its diagonal there): the contact stays on edges, from one edge to the
  // next, where rounding decides between the triangles on either side.
  const TriangleMesh floor = floor_mesh(Vec3::Zero(), kPatch, kPatch, kCells, kCells);
  const std::size_t row = kCells + 1;
  const Vec3 on_row = floor.vertices[43 * row + 27];   // x = -0.69 mm: the 1.4 mm slide stays on the patch
  const Vec3 on_diag = floor.vertices[27 * row + 27];
  for (double deg : {45.0, 80.0})
    for (double mu : {0.0, 0.3}) {
      const double vt = std::tan(deg * std::numbers::pi / 180);
      {
        ImpactSpec s;
        s.v0 = Vec3(vt, 0, -1);
        s.foot = on_row + Vec3(0.3e-6, 0, 0);
        s.foot.y() = on_row.y();
        s.mu = mu;
        const Outcome o = plane_vs_mesh(s, floor);
        char name[64];
        std::snprintf(name, sizeof name, "along a row, %2.0f deg, mu %.1f", deg, mu);
        expect_same(name, o);
        EXPECT_GE(o.edges.size(), 5u) << name;
      }
      {
        ImpactSpec s;
        s.v0 = Vec3(vt / std::sqrt(2.0), vt / std::sqrt(2.0), -1);
        s.foot = on_diag;  // x == y exactly, and the motion keeps them equal
        s.mu = mu;
        s.phase = 0.61;
        const Outcome o = plane_vs_mesh(s, floor);
        char name[64];
        std::snprintf(name, sizeof name, "along the diagonal, %2.0f deg, mu %.1f", deg, mu);
        expect_same(name, o);
        EXPECT_GE(o.edges.size(), 5u) << name;
      }
    }
}


TEST(MeshWallPlane, GrazingThroughVertices) {
  // A grazing slide whose foot lands exactly on a vertex every 4 steps: a floor of 256 x 256 cells
  // of 2^-15 m (vertex coordinates are exact binary fractions), dt = 2^-18 s (64 steps a contact,
  // below the resolved and critical steps), v = (2, 0, -1) m/s and (2, 2, -1) m/s without friction
  // (the tangential velocity stays exactly 2 m/s; the foot advances 2^-17 m a step). Along a row the
  // contact goes edge -> vertex -> edge; along the main diagonal (every cell (i, i) has its diagonal
  // there) likewise across the diagonals' ends, where 8 triangles meet.
  const double L = std::ldexp(1.0, -7);  // 7.8 mm
  const std::size_t n = 256, row = n + 1;
  const TriangleMesh floor = floor_mesh(Vec3::Zero(), L, L, n, n);
  for (bool diagonal : {false, true}) {
    ImpactSpec s;
    s.v0 = diagonal ? Vec3(2, 2, -1) : Vec3(2, 0, -1);
    s.phase = 1.0;  // (2 + phase) dt v_x = 3 x 2^-17 m: the foot is on a vertex at steps 3, 7, 11, ...
    const std::size_t i0 = 100;  // the slide covers ~0.5 mm, 16 cells
    s.foot = floor.vertices[(diagonal ? i0 : 128) * row + i0];
    double dt = 0;
    Scene sp = impact_scene(s, false, floor, dt), sm = impact_scene(s, true, floor, dt);
    ASSERT_LT(std::ldexp(1.0, -18), dt);
    sp.dt = sm.dt = std::ldexp(1.0, -18);
    const double lead = 3 * sp.dt;
    sp.particles[0].x = sm.particles[0].x = Vec3(s.foot.x(), s.foot.y(), kR) - lead * s.v0;
    Simulation a(sp), b(sm);
    const auto &pa = a.particles(), &pb = b.particles();
    std::set<std::uint32_t> edges, vertices;
    int touching = 0, not_one = 0;
    bool in = false, out = false;
    for (int k = 0; k < 100000 && !out; ++k) {
      a.step();
      b.step();
      const bool t = pb.x[0].z() < kR;
      if (t) {
        ++touching;
        if (b.mesh_contact_count() != 1) ++not_one;
        for (const MeshHit& h : contacts_of(floor, pb.x[0], kR))
          (static_cast<Feature>(h.key >> 30) == Feature::Vertex ? vertices : edges).insert(h.key);
      }
      in = in || t;
      out = in && !t;
    }
    a.step();
    b.step();
    const double dv = (pb.v[0] - pa.v[0]).norm() / pa.v[0].norm();
    std::printf("  %-9s: %d steps in contact, %zu edges and %zu vertices visited, |dv|/|v| %.1e, contacts != 1: %d\n",
                diagonal ? "diagonal" : "row", touching, edges.size(), vertices.size(), dv, not_one);
    EXPECT_LT(dv, kRebound);
    EXPECT_EQ(pb.w[0], pa.w[0]);
    EXPECT_GE(vertices.size(), 10u);  // one vertex every 4 steps
    EXPECT_EQ(not_one, 0);
    EXPECT_EQ(pb.v[0].x(), 2.0);      // no tangential force from any feature
  }
}

// ---- 2. an STL box moves with the cavity ------------------------------------------------------------

namespace {

// Eight 4 mm balls (2 GPa steel) with speeds up to 0.9 m/s in a 20 x 16 x 16 mm box shaken 1 mm at
// 40 Hz along (1, 0.6, 0.4) (peak acceleration 6.5 g) under gravity; 30 ms. Two balls head into
// opposite corners (three walls at once).
CaseText shaken_head() {
  return steel_scene("30 ms")
      .steel("2 GPa")
      .harmonic("1 mm", "40 Hz", "[1, 0.6, 0.4]")
      .placed("balls", "steel", "4 mm",
              R"([["-6 mm", "-4 mm", "-5 mm"], ["-1 mm", "3 mm", "-4 mm"], ["3 mm", "-3 mm", "-5.5 mm"],
             ["6 mm", "4 mm", "2 mm"], ["-5 mm", "2 mm", "4 mm"], ["1 mm", "-2 mm", "3 mm"],
             ["6.5 mm", "4.5 mm", "-4.5 mm"], ["-6.5 mm", "-4.5 mm", "4.5 mm"]])",
              R"([[0.3, -0.2, 0.1], [-0.4, 0.1, 0.2], [0.1, 0.35, -0.3],
              [-0.2, -0.3, 0.25], [0.45, 0.05, -0.1], [-0.1, -0.4, 0.3],
              [0.5, 0.5, -0.5], [-0.5, -0.5, 0.5]])");
}

struct ShakenRun {
  double max_dx = 0;          // largest |x_stl - x_box| over balls and steps (unit: m)
  double max_dx_early = 0;    // the same over the first half of the run
  double max_dF = 0, max_F = 0;  // cavity force samples: largest difference, largest value (unit: N)
  double max_dT = 0, max_T = 0;  // cavity torque samples (unit: N m)
  double impulse_error = 0;   // |balls' momentum change - gravity impulse - wall impulse| (unit: N s)
  double wall_impulse = 0;    // |wall impulse on the balls| summed over samples (unit: N s)
  double contacts_max = 0;    // most STL contacts at once
  int count_mismatch = 0;     // steps whose contact counts (pairs + walls or triangles) differ
  EnergySample ea, eb;        // energy budgets at the end
  std::uint64_t steps = 0;
};

ShakenRun shaken_box_vs_stl(int cells) {
  TempDir box_dir, stl_dir;
  box_dir.write("case.toml", shaken_head().box("steel", vec("-10 mm", "-8 mm", "-8 mm"), vec("10 mm", "8 mm", "8 mm")));
  // The same box as an STL file in millimetres.
  stl_dir.write("box.stl", bagdem::testing::ascii_stl(box_soup(Vec3(-10, -8, -8), Vec3(10, 8, 8), cells), 1.0, "box"));
  stl_dir.write("case.toml", shaken_head().stl("steel", "box.stl", "1 mm"));
  Scene a = load_case(box_dir.str()), b = load_case(stl_dir.str());
  EXPECT_EQ(b.mesh_walls.size(), 1u);
  EXPECT_TRUE(b.walls.empty());
  EXPECT_EQ(b.mesh_walls.at(0).mesh.size(), 12u * cells * cells);
  EXPECT_TRUE(b.mesh_walls.at(0).mesh.closed());
  EXPECT_NEAR((b.cavity_lo - a.cavity_lo).norm(), 0.0, 1e-15);
  EXPECT_NEAR((b.cavity_hi - a.cavity_hi).norm(), 0.0, 1e-15);
  EXPECT_EQ(a.dt, b.dt);  // the same time step from the same bounds, materials and motion
  b.dt = a.dt;
  Simulation sa(a), sb(b);
  const auto &pa = sa.particles(), &pb = sb.particles();
  const std::size_t n = pb.size();
  double M = 0;
  Vec3 p0(0, 0, 0), f0(0, 0, 0);
  for (std::size_t i = 0; i < n; ++i) {
    M += pb.mass[i];
    p0 += pb.mass[i] * pb.v[i];
    f0 += pb.f[i];
  }
  const Vec3 W0 = f0 - M * b.gravity;  // wall force at the start (0: no ball touches a wall)
  EXPECT_LT(W0.norm(), 1e-12);
  ShakenRun r;
  r.steps = a.total_steps();
  const std::uint64_t every = 25;
  Vec3 J(0, 0, 0);  // impulse of the contents on the cavity, from the samples
  double Jsum = 0;
  for (std::uint64_t k = 1; k <= r.steps; ++k) {
    sa.step();
    sb.step();
    r.contacts_max = std::max(r.contacts_max, static_cast<double>(sb.mesh_contact_count()));
    if (sa.contact_count() != sb.contact_count()) ++r.count_mismatch;
    for (std::size_t i = 0; i < n; ++i) {
      const double d = (pb.x[i] - pa.x[i]).norm();
      r.max_dx = std::max(r.max_dx, d);
      if (2 * k <= r.steps) r.max_dx_early = std::max(r.max_dx_early, d);
    }
    if (k % every == 0 || k == r.steps) {
      const auto ca = sa.take_cavity_sample(), cb = sb.take_cavity_sample();
      const double span = static_cast<double>(k % every == 0 ? every : k % every) * b.dt;
      r.max_dF = std::max(r.max_dF, (cb.force - ca.force).norm());
      r.max_F = std::max(r.max_F, ca.force.norm());
      r.max_dT = std::max(r.max_dT, (cb.torque - ca.torque).norm());
      r.max_T = std::max(r.max_T, ca.torque.norm());
      EXPECT_EQ((cb.position - ca.position).norm(), 0.0);
      J += cb.force * span;
      Jsum += cb.force.norm() * span;
    }
  }
  // Velocity Verlet: m (v_N - v_0) = dt (F_0 / 2 + F_1 + ... + F_{N-1} + F_N / 2); the pair forces
  // cancel, gravity gives N dt M g, the walls dt sum W_k - dt/2 (W_N - W_0), and the cavity samples
  // report -dt sum_{k=1..N} W_k.
  Vec3 p1(0, 0, 0), fN(0, 0, 0);
  for (std::size_t i = 0; i < n; ++i) {
    p1 += pb.mass[i] * pb.v[i];
    fN += pb.f[i];
  }
  const Vec3 WN = fN - M * b.gravity;
  const Vec3 expected = static_cast<double>(r.steps) * b.dt * M * b.gravity - J - 0.5 * b.dt * (WN - W0);
  r.impulse_error = (p1 - p0 - expected).norm();
  r.wall_impulse = Jsum;
  r.ea = sa.energy();
  r.eb = sb.energy();
  return r;
}

}  // namespace

TEST(MeshWallBox, StlBoxShakenLikeTheAnalyticBox) {
  for (int cells : {1, 8}) {
    const ShakenRun r = shaken_box_vs_stl(cells);
    std::printf("  %4d triangles, %llu steps: max |dx| %.1e m (first half %.1e m), cavity force max %.3g N, "
                "max |dF| %.1e N, torque max %.3g N m, max |dT| %.1e N m; most STL contacts %g\n"
                "       impulse balance error %.1e N s of %.3g N s wall impulse\n",
                12 * cells * cells, static_cast<unsigned long long>(r.steps), r.max_dx, r.max_dx_early, r.max_F,
                r.max_dF, r.max_T, r.max_dT, r.contacts_max, r.impulse_error, r.wall_impulse);
    EXPECT_LT(r.max_dx, 1e-12) << cells;  // rounding only, on a 20 mm box
    EXPECT_LT(r.max_dF, 1e-9 * r.max_F) << cells;
    EXPECT_LT(r.max_dT, 1e-9 * r.max_T) << cells;
    EXPECT_GT(r.max_F, 1.0) << cells;     // the STL walls load the cavity
    EXPECT_GE(r.contacts_max, 2) << cells;  // balls in corners / against two walls at once
    EXPECT_LT(r.impulse_error, 1e-9 * r.wall_impulse) << cells;
    EXPECT_EQ(r.count_mismatch, 0) << cells;
    // The energy budget sees the STL walls as it sees the box's planes.
    std::printf("       work of the cavity %.6e J (box) %.6e J (STL); dissipated %.6e J / %.6e J\n", r.ea.work_cavity,
                r.eb.work_cavity, r.ea.dissipated(), r.eb.dissipated());
    EXPECT_GT(std::abs(r.ea.work_cavity), 1e-6) << cells;
    EXPECT_NEAR(r.eb.work_cavity, r.ea.work_cavity, 1e-9 * std::abs(r.ea.work_cavity)) << cells;
    EXPECT_NEAR(r.eb.dissipated_normal, r.ea.dissipated_normal, 1e-9 * r.ea.dissipated()) << cells;
    EXPECT_NEAR(r.eb.dissipated_tangential, r.ea.dissipated_tangential, 1e-9 * r.ea.dissipated()) << cells;
    EXPECT_NEAR(r.eb.elastic, r.ea.elastic, 1e-9 * r.ea.dissipated()) << cells;
  }
}

TEST(MeshWallBox, WallComesToABallAtRest) {
  // No gravity, one ball at rest 3 mm from the +x wall of the box; the box moves 4 mm along -x
  // (20 Hz): the wall must find the ball though the ball never moved (the STL candidate lists
  // follow the cavity's motion), and push it as the analytic wall does.
  TempDir dir;
  dir.write("box.stl", bagdem::testing::ascii_stl(box_soup(Vec3(-10, -8, -8), Vec3(10, 8, 8), 1), 1.0, "box"));
  const double mm = 1e-3;
  auto scene = [&](bool stl) {
    SceneBuilder b;
    b.material("soft steel", kRho, kE, kNu).interaction(0.5, 0.3);
    if (stl) b.bounds(Vec3(-10, -8, -8) * mm, Vec3(10, 8, 8) * mm);
    else b.box(Vec3(-10, -8, -8) * mm, Vec3(10, 8, 8) * mm);
    b.particle(Vec3(5 * mm, 1 * mm, -2 * mm), Vec3::Zero(), 2 * mm)
        .motion(make_harmonic_motion(4 * mm, 20, Vec3(-1, 0, 0), 0))
        .dt(2e-6)
        .duration(0.03);
    Scene s = b.build();
    s.cavity_reference = Vec3::Zero();
    if (stl) s.mesh_walls.push_back({"box.stl", read_stl((dir.path / "box.stl").string(), mm), 0});
    return s;
  };
  const Scene sa = scene(false), sb = scene(true);
  Simulation a(sa), b(sb);
  double dx = 0, vmax = 0;
  for (std::uint64_t k = 0; k < sa.total_steps(); ++k) {
    a.step();
    b.step();
    dx = std::max(dx, (b.particles().x[0] - a.particles().x[0]).norm());
    vmax = std::max(vmax, b.particles().v[0].norm());
  }
  std::printf("  ball hit by the moving wall: top speed %.3f m/s, max |x_stl - x_box| %.1e m\n", vmax, dx);
  EXPECT_GT(vmax, 0.3);  // it was hit (wall speed up to 0.5 m/s)
  EXPECT_LT(dx, 1e-12);
}

// ---- 3. triangles much larger than the ball --------------------------------------------------------

namespace {

// A 0.2 m square floor at z = 0 from 2 x 2 cells (8 triangles, legs 0.1 m: 20 ball radii; the
// centre vertex has all 8 around it) or 1 x 1 (2 triangles).
Scene coarse_scene(bool mesh, std::size_t cells, const Vec3& x, const Vec3& v, const Vec3& g, double dt, double e) {
  SceneBuilder b;
  b.material("soft steel", kRho, kE, kNu).interaction(e, 0.3);
  if (!mesh) b.plane(Vec3::Zero(), Vec3::UnitZ());
  b.particle(x, v, kR).gravity(g).dt(dt);
  Scene s = b.build();
  if (mesh) s.mesh_walls.push_back({"coarse floor", floor_mesh(Vec3::Zero(), 0.2, 0.2, cells, cells), 0});
  return s;
}

}  // namespace

TEST(MeshWallCoarse, SlowPushInTheMiddleOfALargeTriangle) {
  // 1 cm/s head-on, no gravity, no damping (e = 1), in the middle of one of 2 triangles (0.2 m
  // square): the force at every step is the plane's, and the deepest overlap Hertz's (a contact
  // found from the triangle's nodes only, 0.1 m away, would never close and the ball would pass
  // through).
  const double v = 0.01;
  const Material m{"soft steel", kRho, kE, kNu};
  const double tc = hertz::contact_time(sphere_mass(kRho, kR), kR, effective_youngs(m, m), v);
  const double dt = tc / 40;
  const Vec3 x0(0.031, -0.047, kR + 2.3 * v * dt);
  const Scene sp = coarse_scene(false, 1, x0, Vec3(0, 0, -v), Vec3::Zero(), dt, 1.0);
  const Scene sm = coarse_scene(true, 1, x0, Vec3(0, 0, -v), Vec3::Zero(), dt, 1.0);
  Simulation a(sp), b(sm);
  double f_max = 0, df_max = 0, z_min = 1;
  int touching = 0;
  for (int k = 0; k < 200; ++k) {
    a.step();
    b.step();
    f_max = std::max(f_max, a.particles().f[0].norm());
    df_max = std::max(df_max, (b.particles().f[0] - a.particles().f[0]).norm());
    z_min = std::min(z_min, b.particles().x[0].z());
    if (b.particles().x[0].z() < kR) {
      ++touching;
      EXPECT_EQ(b.mesh_contact_count(), 1u) << k;
    }
  }
  const double delta = hertz::max_overlap(sphere_mass(kRho, kR), kR, effective_youngs(m, m), v);
  std::printf("  slow push: peak force %.4g N, max |dF| %.1e N, deepest overlap %.4g um (Hertz %.4g um), %d steps "
              "in contact, rebound %.4g m/s (plane %.4g m/s)\n",
              f_max, df_max, (kR - z_min) * 1e6, delta * 1e6, touching, b.particles().v[0].z(), a.particles().v[0].z());
  EXPECT_GT(f_max, 0.1);
  EXPECT_LT(df_max, 1e-12 * f_max);
  EXPECT_NEAR(kR - z_min, delta, 0.01 * delta);
  EXPECT_NEAR(b.particles().v[0].z(), v, 0.01 * v);  // rebounded elastically
}

TEST(MeshWallCoarse, BallRestsOnLargeTrianglesIndefinitely) {
  // Dropped from 0.1 mm under gravity onto a face, the diagonal edge and the centre vertex of a
  // 2 x 2-cell, 0.2 m floor (8 triangles; e = 0.5): it bounces, settles and rests at the Hertz
  // static overlap, with exactly one contact, for 1500 contact times (60 000 steps, 0.62 s), as on
  // the plane.
  const Vec3 g(0, 0, -9.81);
  const Material m{"soft steel", kRho, kE, kNu};
  const double mass = sphere_mass(kRho, kR), E_star = effective_youngs(m, m);
  const double v_drop = std::sqrt(2 * 9.81 * 1e-4);
  const double dt = hertz::contact_time(mass, kR, E_star, v_drop) / 40;
  const double delta_s = hertz::static_overlap(mass * 9.81, kR, E_star);
  const TriangleMesh floor = floor_mesh(Vec3::Zero(), 0.2, 0.2, 2, 2);
  const struct {
    const char* name;
    Vec3 at;
  } where[] = {{"in a face", Vec3(0.0371, -0.0613, 0)},
               {"on a diagonal", Vec3(0.0371, 0.0371, 0)},  // cell (1, 1): diagonal y = x
               {"on the centre vertex", Vec3(0, 0, 0)}};
  for (const auto& w : where) {
    const Vec3 x0 = w.at + Vec3(0, 0, kR + 1e-4);
    const Scene sp = coarse_scene(false, 2, x0, Vec3::Zero(), g, dt, 0.5);
    const Scene sm = coarse_scene(true, 2, x0, Vec3::Zero(), g, dt, 0.5);
    Simulation a(sp), b(sm);
    const int steps = 60000;
    double z_min = 1, last_overlap = 0, dz_max = 0;
    int wrong = 0;
    for (int k = 0; k < steps; ++k) {
      a.step();
      b.step();
      const double z = b.particles().x[0].z();
      z_min = std::min(z_min, z);
      dz_max = std::max(dz_max, std::abs(z - a.particles().x[0].z()));
      if (z < kR && b.mesh_contact_count() != 1) ++wrong;
    }
    last_overlap = kR - b.particles().x[0].z();
    std::printf("  %-22s %d steps (%.1f ms): deepest %.4g um, final overlap %.5g um (Hertz static %.5g um), "
                "max |z - z_plane| %.1e m, steps without exactly one contact %d\n",
                w.name, steps, steps * dt * 1e3, (kR - z_min) * 1e6, last_overlap * 1e6, delta_s * 1e6, dz_max,
                wrong);
    EXPECT_GT(z_min, kR - 10 * delta_s) << w.name;             // never sinks in
    EXPECT_NEAR(last_overlap, delta_s, 0.01 * delta_s) << w.name;  // at rest on one contact
    EXPECT_LT(dz_max, 1e-12) << w.name;
    EXPECT_EQ(wrong, 0) << w.name;
    EXPECT_LT(b.particles().v[0].norm(), 1e-4) << w.name;
  }
}

TEST(MeshWallCoarse, BallInAValleyKeepsItsEnergy) {
  // A frictionless, undamped (e = 1) ball dropped 10 um onto the floor of a valley of two faces 26
  // degrees apart (each 13 degrees off flat: the Euler sum's two faces and their edge): it rattles in
  // the valley for 3e5 steps (t_c / 40). Its energy, kinetic + contact - work of gravity, is
  // conserved but for velocity Verlet's bounded error. Reference: the drop's energy m g h;
  // tolerance: the largest change 2% of it. Measured 0.27%; keeping only the deeper face, the ball
  // flipped between the faces and its energy wandered by 5.7%.
  const Vec3 g(0, 0, -9.81);
  const Material m{"soft steel", kRho, kE, kNu};
  const double mass = sphere_mass(kRho, kR), E_star = effective_youngs(m, m), drop = 1e-5;
  const double dt = hertz::contact_time(mass, kR, E_star, std::sqrt(2 * 9.81 * drop)) / 40;
  const double a = 13.0 * M_PI / 180, L = 0.05;
  TriangleMesh valley;  // normals away from the ball (below), as a cavity's
  valley.vertices = {Vec3(0, -L, 0), Vec3(0, L, 0), Vec3(-L, 0, L * std::tan(a)), Vec3(L, 0, L * std::tan(a))};
  valley.triangles = {{0, 2, 1}, {0, 1, 3}};
  build_topology(valley);
  SceneBuilder b;
  b.material("soft steel", kRho, kE, kNu).interaction(1.0, 0.0);
  // Touching both faces first at 0.3 um off the floor line: the deeper face changes sides.
  b.particle(Vec3(3e-7, 0, kR / std::cos(a) + drop), Vec3::Zero(), kR).gravity(g).dt(dt);
  Scene scene = b.build();
  scene.mesh_walls.push_back({"valley", valley, 0});
  Simulation sim(scene);
  auto energy = [&] {
    const EnergySample e = sim.energy();
    return e.kinetic + e.elastic - e.work_gravity;
  };
  const double E0 = energy(), scale = mass * 9.81 * drop;
  double worst = 0;
  for (int k = 0; k < 300000; ++k) {
    sim.step();
    worst = std::max(worst, std::abs(energy() - E0));
  }
  std::printf("  ball in a valley: largest energy change %.2e J = %.2f%% of m g h (%.2e J), final height above the floor line %.3g um\n",
              worst, 100 * worst / scale, scale, (sim.particles().x[0].z() - kR / std::cos(a)) * 1e6);
  EXPECT_LT(worst, 0.02 * scale);
}

// ---- 4. STL errors through the case ----------------------------------------------------------------

namespace {

// `bagdem check` on a case whose STL file is `stl` (none when empty): exit code and all output.
bagdem::testing::CmdResult check_stl_case(const TempDir& dir, const std::string& name, const std::string& stl) {
  dir.write("case.toml", bagdem::testing::stl_case(name));
  if (!stl.empty()) dir.write(name, stl);
  return bagdem::testing::run_bagdem({"check", dir.str()}, dir.path);
}

}  // namespace

TEST(MeshWallCase, GoodStlBoxPassesCheck) {
  TempDir dir;
  const auto r = check_stl_case(dir, "box.stl", bagdem::testing::ascii_stl(box_soup(Vec3(-10, -8, -8), Vec3(10, 8, 8), 2)));
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("box.stl"), std::string::npos) << r.out;
}

TEST(MeshWallCase, MissingStlFileIsNamed) {
  TempDir dir;
  const auto r = check_stl_case(dir, "no_such_box.stl", "");
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_NE((r.out + r.err).find("no_such_box.stl"), std::string::npos) << r.out << r.err;
  EXPECT_NE((r.out + r.err).find("cannot open"), std::string::npos) << r.out << r.err;
}

TEST(MeshWallCase, NonManifoldStlIsNamed) {
  // (a) A fin: two extra facets on an edge of the box (4 triangles on one edge).
  {
    TempDir dir;
    auto soup = box_soup(Vec3(-10, -8, -8), Vec3(10, 8, 8), 1);
    soup.push_back({Vec3(-10, -8, -8), Vec3(10, -8, -8), Vec3(0, -20, 0)});
    soup.push_back({Vec3(10, -8, -8), Vec3(-10, -8, -8), Vec3(0, -20, 5)});
    const auto r = check_stl_case(dir, "finned_box.stl", bagdem::testing::ascii_stl(soup));
    EXPECT_EQ(r.code, 2) << r.out << r.err;
    EXPECT_NE((r.out + r.err).find("finned_box.stl"), std::string::npos) << r.out << r.err;
    EXPECT_NE((r.out + r.err).find("manifold"), std::string::npos) << r.out << r.err;
  }
  // (b) One face turned over: the orientation is inconsistent across its edges.
  {
    TempDir dir;
    auto soup = box_soup(Vec3(-10, -8, -8), Vec3(10, 8, 8), 1);
    std::swap(soup[0][1], soup[0][2]);
    std::swap(soup[1][1], soup[1][2]);
    const auto r = check_stl_case(dir, "twisted_box.stl", bagdem::testing::ascii_stl(soup));
    EXPECT_EQ(r.code, 2) << r.out << r.err;
    EXPECT_NE((r.out + r.err).find("twisted_box.stl"), std::string::npos) << r.out << r.err;
    EXPECT_NE((r.out + r.err).find("manifold"), std::string::npos) << r.out << r.err;
  }
}
