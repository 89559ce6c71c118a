// Pieces the stepper's source files share (private to src/).
#pragma once
#include "bagdem/contact/mindlin.hpp"
#include "bagdem/contact/rolling.hpp"
#include "bagdem/vec3.hpp"

namespace bagdem {

// Calls fn.template operator()<b0, b1, ...>() with runtime flags turned into template arguments,
// so each configuration of the kernel is compiled without branches on the flags.
template <bool... Done, class Fn>
void with_flags(Fn&& fn) {
  fn.template operator()<Done...>();
}
template <bool... Done, class Fn, class... Rest>
void with_flags(Fn&& fn, bool first, Rest... rest) {
  if (first) with_flags<Done..., true>(fn, rest...);
  else with_flags<Done..., false>(fn, rest...);
}

// What a contact still held when it opened, as (normal, tangential, rolling) dissipation: the last
// half step of its forces' trapezoidal work (hertz.hpp, mindlin.hpp, rolling.hpp) and the energy
// its springs still stored. Both vanish with the overlap as dt -> 0; tallying them keeps the
// energy budget exact. n: normal from j to i; v_c, w_rel: half-step relative motion.
template <bool Tangential, bool Rolling>
Vec3 closing_tally(const Vec3& n, const Vec3& v_c, const Vec3& w_rel, double dt, double damping_prev,
                   const TangentialHistory* th, const RollingHistory* rh) {
  Vec3 d(-0.5 * damping_prev * v_c.dot(n) * dt, 0, 0);
  if constexpr (Tangential) d.y() = mindlin_energy(*th) - 0.5 * th->total.dot(v_c - v_c.dot(n) * n) * dt;
  if constexpr (Rolling) d.z() = rolling_energy(*rh) - 0.5 * rh->torque.dot(w_rel - w_rel.dot(n) * n) * dt;
  return d;
}

}  // namespace bagdem
