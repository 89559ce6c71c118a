// The contents' clearance in the cavity (run/clearance.hpp).
#include "bagdem/run/clearance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bagdem/particles.hpp"
#include "bagdem/step/simulation.hpp"

namespace bagdem {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Distance from c along the unit direction u to a wall (in the cavity frame), +inf if the ray
// does not meet it.
double ray_to_wall(const Wall& w, const Vec3& c, const Vec3& u) {
  const double inf = std::numeric_limits<double>::infinity();
  if (w.kind == WallKind::Plane) {
    const double s = (c - w.point).dot(w.direction), approach = -u.dot(w.direction);
    return approach > 1e-12 ? std::max(0.0, s / approach) : inf;
  }
  // Inside a bore: |q + t u_perp| = R, the positive root.
  const Vec3 a = w.direction, d = c - w.point;
  const Vec3 q = d - d.dot(a) * a, up = u - u.dot(a) * a;
  const double A = up.squaredNorm(), B = q.dot(up), C = q.squaredNorm() - w.radius * w.radius;
  if (A < 1e-24) return inf;
  const double disc = B * B - A * C;
  return disc < 0 ? inf : std::max(0.0, (-B + std::sqrt(disc)) / A);
}

}  // namespace

ContentsGaps contents_gaps(const Scene& scene, const Simulation& sim, const Vec3& e) {
  if (!scene.mesh_walls.empty() || scene.walls.empty()) return {kNaN, kNaN};
  const Particles& p = sim.particles();
  const FilmNodes& film = sim.film();
  const Vec3 shift = sim.cavity().position;  // walls are in the cavity frame
  Vec3 m = Vec3::Zero();
  double mass = 0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t i = 0; i < p.size(); ++i) {
    m += p.mass[i] * p.x[i], mass += p.mass[i];
    lo = std::min(lo, p.x[i].dot(e) - p.radius[i]), hi = std::max(hi, p.x[i].dot(e) + p.radius[i]);
  }
  for (std::size_t k = 0; k < film.size(); ++k) {
    m += film.mass[k] * film.x[k], mass += film.mass[k];
    lo = std::min(lo, film.x[k].dot(e)), hi = std::max(hi, film.x[k].dot(e));
  }
  if (!(mass > 0)) return {kNaN, kNaN};
  const Vec3 c = m / mass - shift;
  double plus = std::numeric_limits<double>::infinity(), minus = plus;
  for (const Wall& w : scene.walls) plus = std::min(plus, ray_to_wall(w, c, e)), minus = std::min(minus, ray_to_wall(w, c, -e));
  if (!std::isfinite(plus + minus)) return {kNaN, kNaN};
  const double ce = (m / mass).dot(e);
  return {std::max(0.0, plus - (hi - ce)), std::max(0.0, minus - (ce - lo))};
}

double contents_clearance(const Scene& scene, const Simulation& sim, const Vec3& e) {
  const ContentsGaps g = contents_gaps(scene, sim, e);
  return g.plus + g.minus;
}

}  // namespace bagdem
