// A bag pulled tight around its balls (tight_bag.hpp).
#include "tight_bag.hpp"

#include <cmath>
#include <sstream>

#include "bagdem/mesh/triangle_mesh.hpp"

namespace bagdem {

void pull_tight(const CaseReader& in, double ball_volume, Bag& b) {
  const double shrink = in.quantity("bag.film.shrink", dim::none, 1.0);
  if (!(shrink >= 0.7 && shrink <= 1.0)) in.fail("bag.film.shrink", "must be in [0.7, 1]: the film's unstretched size over its made size");
  // Balls at random close packing (0.64) fill the tightest bag they can be pulled into.
  constexpr double kClosePacking = 0.64;
  if (const double made = ball_volume / enclosed_volume(b.rest, b.rest.vertices); shrink < 1 && made / std::pow(shrink, 3) > kClosePacking) {
    std::ostringstream m;
    m << "makes the unstretched film hold the balls at a fill of " << made / std::pow(shrink, 3)
      << ", above random close packing (0.64), so that the film could only close on them by crushing them: give at least "
      << std::ceil(1000 * std::cbrt(made / kClosePacking)) / 1000;
    in.fail("bag.film.shrink", m.str());
  }
  b.shrink = shrink;
  if (shrink < 1) {
    Vec3 c = Vec3::Zero();
    for (const Vec3& v : b.rest.vertices) c += v;
    c /= static_cast<double>(b.rest.vertices.size());
    for (Vec3& v : b.rest.vertices) v = c + shrink * (v - c);
  }
}

}  // namespace bagdem
