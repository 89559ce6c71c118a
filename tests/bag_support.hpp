// Helpers of the bag suites (test_bag_physics.cpp, test_bag_case.cpp): a case written to a
// temporary directory and loaded (the Scene is kept alive beside it: a Simulation holds a reference
// to its Scene), the bag's mass and centre of mass (balls and film nodes), and the energy-balance
// error exactly as the run loop reports it (src/run/runner.cpp, balance_error).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "bagdem/case/load_case.hpp"
#include "bagdem/step/simulation.hpp"
#include "case_texts.hpp"
#include "support.hpp"

namespace bagdem::testing {

// The start of the bag suites' cases: [simulation] with `duration`, gravity down and `seed`, their
// materials (steel softened to 2 GPa for balls and walls, the LDPE film) and the default
// interaction (e 0.5, mu 0.3).
inline CaseText bag_scene(const Value& duration, int seed) {
  return CaseText().simulation(duration).set("simulation", "seed", seed).steel_and_film().interactions(0.5, 0.3);
}

// case.toml written into a fresh temporary directory, then loaded with `overrides` (--set syntax).
struct LoadedCase {
  TempDir dir;
  Scene scene;
  explicit LoadedCase(const std::string& toml, const std::vector<std::string>& overrides = {}) {
    dir.write("case.toml", toml);
    scene = load_case(dir.str(), overrides);
  }
};

// Mass of the bag's balls plus its film nodes (unit: kg).
inline double bag_mass(const Simulation& sim) {
  const Bag& bag = *sim.scene().bag;
  double m = 0;
  for (std::size_t i = bag.ball_first; i < bag.ball_first + bag.balls; ++i) m += sim.particles().mass[i];
  for (double mk : sim.film().mass) m += mk;
  return m;
}

// Mass-weighted centre of mass (position and velocity) of the bag's balls and film nodes.
struct Com {
  Vec3 x = Vec3::Zero(), v = Vec3::Zero();
};
inline Com bag_com(const Simulation& sim) {
  const Bag& bag = *sim.scene().bag;
  Com c;
  double m = 0;
  const Particles& p = sim.particles();
  for (std::size_t i = bag.ball_first; i < bag.ball_first + bag.balls; ++i) {
    c.x += p.mass[i] * p.x[i];
    c.v += p.mass[i] * p.v[i];
    m += p.mass[i];
  }
  const FilmNodes& f = sim.film();
  for (std::size_t k = 0; k < f.size(); ++k) {
    c.x += f.mass[k] * f.x[k];
    c.v += f.mass[k] * f.v[k];
    m += f.mass[k];
  }
  c.x /= m;
  c.v /= m;
  return c;
}

// The energy-balance error of the run loop (src/run/runner.cpp, balance_error): the residual of
// W_cavity + W_gravity = (K + U) - (K0 + U0) + D, relative to the largest of |W_cavity| + |W_gravity|,
// D, K + U and K0 + U0.
struct Balance {
  double residual = 0, scale = 0;
  double relative() const { return std::abs(residual) / scale; }
};
inline Balance energy_balance(const EnergySample& e, double stored0) {
  Balance b;
  const double in = e.work_cavity + e.work_gravity;
  const double diss = e.dissipated();
  b.residual = in - (e.kinetic + e.elastic - stored0) - diss;
  b.scale = std::max({std::abs(e.work_cavity) + std::abs(e.work_gravity), diss, e.kinetic + e.elastic, stored0, 1e-300});
  return b;
}

// Bitwise comparison of two position arrays.
inline bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0);
}

// Edges of the film crossing one of its triangles (not sharing a vertex): the film passing through
// itself (nothing keeps it from that without bag.film.self_contact). Moller-Trumbore segment test
// (J. Graphics Tools 2(1), 1997).
inline std::size_t film_self_intersections(const TriangleMesh& mesh, const std::vector<Vec3>& x) {
  auto crosses = [](const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 e1 = b - a, e2 = c - a, d = p1 - p0, h = d.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-300) return false;
    const Vec3 s = p0 - a;
    const double u = s.dot(h) / det;
    if (u < 0 || u > 1) return false;
    const Vec3 q = s.cross(e1);
    const double v = d.dot(q) / det;
    if (v < 0 || u + v > 1) return false;
    const double t = e2.dot(q) / det;
    return t > 0 && t < 1;
  };
  std::size_t n = 0;
  for (const auto& e : mesh.edge_vertices)
    for (const auto& tri : mesh.triangles) {
      if (tri[0] == e[0] || tri[1] == e[0] || tri[2] == e[0] || tri[0] == e[1] || tri[1] == e[1] || tri[2] == e[1]) continue;
      n += crosses(x[e[0]], x[e[1]], x[tri[0]], x[tri[1]], x[tri[2]]);
    }
  return n;
}

}  // namespace bagdem::testing
