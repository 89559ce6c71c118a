#include "bagdem/neighbour/spatial_order.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace bagdem {
namespace {

// Sorts order[first, last) (scene indices) by slab (longest axis), layer (shortest axis), then the
// coordinate along the third.
void sort_segment(const std::vector<ParticleInit>& balls, double width, std::uint32_t* first, std::uint32_t* last) {
  if (last - first < 2) return;
  Vec3 lo = balls[*first].x, hi = lo;
  for (const std::uint32_t* i = first; i != last; ++i) lo = lo.cwiseMin(balls[*i].x), hi = hi.cwiseMax(balls[*i].x);
  std::array<int, 3> axis{0, 1, 2};  // longest side first
  const Vec3 side = hi - lo;
  std::stable_sort(axis.begin(), axis.end(), [&](int a, int b) { return side[a] > side[b]; });
  struct Key {
    double slab, layer, along;
    std::uint32_t ball;  // scene index
    bool operator<(const Key& o) const {
      if (slab != o.slab) return slab < o.slab;
      if (layer != o.layer) return layer < o.layer;
      if (along != o.along) return along < o.along;
      return ball < o.ball;  // ties keep the scene's order
    }
  };
  std::vector<Key> keys;
  keys.reserve(static_cast<std::size_t>(last - first));
  for (const std::uint32_t* i = first; i != last; ++i) {
    const Vec3& x = balls[*i].x;
    keys.push_back({std::floor((x[axis[0]] - lo[axis[0]]) / width), std::floor((x[axis[2]] - lo[axis[2]]) / width),
                    x[axis[1]], *i});
  }
  std::sort(keys.begin(), keys.end());
  for (const Key& k : keys) *first++ = k.ball;
}

}  // namespace

std::vector<std::uint32_t> spatial_order(const Scene& scene) {
  const std::vector<ParticleInit>& balls = scene.particles;
  std::vector<std::uint32_t> order(balls.size());
  std::iota(order.begin(), order.end(), 0u);
  if (balls.size() < kSpatialOrderMin) return order;
  double width = 0;
  for (const ParticleInit& b : balls) width = std::max(width, 2 * b.radius);
  std::size_t cut[4] = {0, 0, 0, balls.size()};
  if (scene.bag) cut[1] = scene.bag->ball_first, cut[2] = scene.bag->ball_first + scene.bag->balls;
  for (int s = 0; s < 3; ++s) sort_segment(balls, width, order.data() + cut[s], order.data() + cut[s + 1]);
  return order;
}

}  // namespace bagdem
