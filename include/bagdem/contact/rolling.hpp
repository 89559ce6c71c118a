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

struct RollingHistory {
  Vec3 torque = Vec3::Zero();  // elastic rolling torque on i (unit: N m)
  double stiffness = 0;        // k_r at the previous step (unit: N m/rad)
};

struct RollingResult {
  Vec3 torque;        // rolling torque on i (on j: the opposite) (unit: N m)
  double dissipated;  // energy dissipated in this step (unit: J)
};

BAGDEM_INLINE RollingResult epsd_rolling(const ContactGeometry& g, const PairLaw& law, double S_n,
                                  double F_n, double dt, RollingHistory& h) {
  const Vec3 w_roll = g.w_half - g.w_half.dot(g.n) * g.n;
  const double k_r = 2.25 * S_n * law.rolling * law.rolling * g.R_eff * g.R_eff;
  const Vec3 M_prev = h.torque;
  const double energy_before = h.stiffness > 0 ? M_prev.squaredNorm() / (2.0 * h.stiffness) : 0.0;
  Vec3 M = carry_spring(h.torque, g.n, h.stiffness, k_r);
  M -= k_r * dt * w_roll;
  const double cap = law.rolling * g.R_eff * F_n;
  const double M2 = M.squaredNorm();
  if (M2 > cap * cap) M *= cap / std::sqrt(M2);
  h.torque = M;
  h.stiffness = k_r;
  const double energy_after = k_r > 0 ? M.squaredNorm() / (2.0 * k_r) : 0.0;
  // Trapezoidal work, as in mindlin.hpp.
  return {M, -0.5 * (M + M_prev).dot(w_roll) * dt - (energy_after - energy_before)};
}

BAGDEM_INLINE double rolling_energy(const RollingHistory& h) {
  return h.stiffness > 0 ? h.torque.squaredNorm() / (2.0 * h.stiffness) : 0.0;
}

}  // namespace bagdem
