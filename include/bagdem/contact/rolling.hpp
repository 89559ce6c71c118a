// Rolling role (optional): elastic-plastic spring-dashpot rolling resistance, "EPSD2" of
// Wensrich & Katterfeld (Powder Technology 217, 2012), as in LIGGGHTS' rolling_friction epsd2.
//
//   k_r = 2.25 S_n mu_r^2 R*^2,  M_r <- M_r - k_r w_roll dt,  |M_r| <= mu_r R* F_n
// w_roll is the relative angular velocity without its twisting part (along n). The stored torque is
// carried into the tangent plane like the tangential spring (carry_spring in geometry.hpp).
#pragma once
#include <cmath>

#include "bagdem/contact/geometry.hpp"
#include "bagdem/material.hpp"

namespace bagdem {

// T as in hertz.hpp. torque and stiffness stay adjacent: surface_contact_lanes moves them as one row.
template <class T>
struct RollingHistoryT {
  V3<T> torque = zero3<T>();  // elastic rolling torque on i (unit: N m)
  T stiffness = splat<T>(0);  // k_r at the previous step (unit: N m/rad)
};
using RollingHistory = RollingHistoryT<double>;

template <class T>
struct RollingResultT {
  V3<T> torque;   // rolling torque on i (on j: the opposite) (unit: N m)
  T dissipated;   // energy dissipated in this step (unit: J)
};
using RollingResult = RollingResultT<double>;

template <class T, class Law>
BAGDEM_INLINE RollingResultT<T> epsd_rolling(const ContactGeometryT<T>& g, const Law& law, T S_n, T F_n, double dt,
                                             RollingHistoryT<T>& h) {
  const V3<T> w_roll = g.w_half - dot(g.w_half, g.n) * g.n;
  const T k_r = 2.25 * S_n * law.rolling * law.rolling * g.R_eff * g.R_eff;
  const V3<T> M_prev = h.torque;
  const T energy_before = select(h.stiffness > 0, dot(M_prev, M_prev) / (2.0 * h.stiffness), splat<T>(0.0));
  V3<T> M = carry_spring<T>(h.torque, g.n, h.stiffness, k_r);
  M -= k_r * dt * w_roll;
  const T cap = law.rolling * g.R_eff * F_n;
  const T M2 = dot(M, M);
  if constexpr (std::is_same_v<T, double>) {
    if (M2 > cap * cap) M *= cap / std::sqrt(M2);
  } else {
    M *= select(M2 > cap * cap, cap / sqrt_of(M2), splat<T>(1.0));  // x 1 is exact
  }
  h.torque = M;
  h.stiffness = k_r;
  const T energy_after = select(k_r > 0, dot(M, M) / (2.0 * k_r), splat<T>(0.0));
  // Trapezoidal work, as in mindlin.hpp.
  return {M, -0.5 * dot(M + M_prev, w_roll) * dt - (energy_after - energy_before)};
}

BAGDEM_INLINE double rolling_energy(const RollingHistory& h) {
  return h.stiffness > 0 ? h.torque.squaredNorm() / (2.0 * h.stiffness) : 0.0;
}

}  // namespace bagdem
