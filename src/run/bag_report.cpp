// Bag measurements and the saved-bag state (run/bag_report.hpp).
#include "bagdem/run/bag_report.hpp"

#include <algorithm>
#include <numbers>

namespace bagdem {

BagReport measure_bag(const Scene& scene, const Simulation& sim) {
  BagReport r;
  if (!scene.bag) return r;
  const Bag& bag = *scene.bag;
  const std::vector<Vec3>& x = sim.film().x;
  // The film's mid-surface encloses its inner half: take off half the thickness over the area.
  r.inner_volume = enclosed_volume(bag.rest, x) - 0.5 * bag.film.thickness * surface_area(bag.rest, x);
  double balls = 0;
  const Particles& p = sim.particles();
  for (std::size_t i = bag.ball_first; i < bag.ball_first + bag.balls; ++i) {
    balls += 4.0 / 3.0 * std::numbers::pi * p.radius[i] * p.radius[i] * p.radius[i];
    r.centre += p.x[i];
  }
  r.centre /= static_cast<double>(bag.balls);
  r.packing_fraction = balls / r.inner_volume;
  const Vec3 axes[3] = {bag.axis, bag.side, bag.axis.cross(bag.side)};
  for (int k = 0; k < 3; ++k) {
    double lo = 1e300, hi = -1e300;
    for (const Vec3& v : x) lo = std::min(lo, v.dot(axes[k])), hi = std::max(hi, v.dot(axes[k]));
    r.outer[k] = hi - lo + bag.film.thickness;
  }
  return r;
}

SavedBag saved_bag(const Scene& scene, const Simulation& sim) {
  SavedBag s;
  const Bag& bag = *scene.bag;
  const Vec3 c = sim.cavity().position;
  s.rest.triangles = bag.rest.triangles;
  for (const Vec3& v : bag.rest.vertices) s.rest.vertices.push_back(v - c);
  for (const Vec3& v : sim.film().x) s.film_position.push_back(v - c);
  // In the scene's order (the stepper sorts the bag's balls among themselves).
  const std::vector<Vec3> x = sim.in_scene_order(sim.particles().x);
  const std::vector<double> radius = sim.in_scene_order(sim.particles().radius);
  for (std::size_t i = bag.ball_first; i < bag.ball_first + bag.balls; ++i) {
    s.ball_position.push_back(x[i] - c);
    s.ball_radius.push_back(radius[i]);
  }
  s.shape = bag.shape;
  s.axis = bag.axis;
  s.side = bag.side;
  const BagReport r = measure_bag(scene, sim);
  s.size = r.outer;
  s.fill_fraction = r.packing_fraction;
  s.film_thickness = bag.film.thickness;
  return s;
}

}  // namespace bagdem
