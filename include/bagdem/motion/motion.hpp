// Prescribed motion of the cavity (a rigid translation). Kinds, one file each in src/motion/:
//   fixed     : at rest
//   harmonic  : x(t) = X sin(w t + phase) along a unit direction
//   table     : positions tabulated in a CSV file (t, x, y, z), cubic Hermite interpolation with
//               central-difference slopes; velocity is the exact derivative of that interpolant
//               inside the table (at rest outside it).
// Any motion can be wrapped in a smooth start (src/motion/ramp.cpp, make_ramped_motion).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "bagdem/vec3.hpp"

namespace bagdem {

struct CavityState {
  Vec3 position = Vec3::Zero();  // displacement of the cavity frame from its rest place (unit: m)
  Vec3 velocity = Vec3::Zero();  // (unit: m/s)
  // A beam's slope carried by the cavity (primary.follow_slope): the small rotation theta about
  // axis x e, linearised as a shear, adds shear * s to the displacement of a point at axial
  // coordinate s (structure/primary.hpp). shear = theta e; zero for prescribed motion.
  Vec3 shear = Vec3::Zero();       // (unit: 1)
  Vec3 shear_rate = Vec3::Zero();  // (unit: 1/s)
};

class Motion {
 public:
  virtual ~Motion() = default;
  virtual CavityState at(double t) const = 0;   // t: motion time (unit: s), t >= 0
  virtual double max_speed() const = 0;         // largest |velocity| (unit: m/s), for dt selection
  virtual std::string describe() const = 0;     // one line for `bagdem check`
  virtual double frequency() const { return 0; } // drive frequency of periodic motion (unit: Hz), 0 if none
  virtual double ramp_time() const { return 0; } // time of a smooth start (unit: s), 0 if none
};

std::unique_ptr<Motion> make_fixed_motion();
// amplitude X (m), frequency f (Hz), unit direction, phase (rad): x = X sin(2 pi f t + phase) dir.
std::unique_ptr<Motion> make_harmonic_motion(double amplitude, double frequency, const Vec3& direction,
                                             double phase);
// Tabulated positions: strictly increasing times (s), positions (m); at least two rows.
// Before the first time the first position holds; after the last, the last (both at rest).
std::unique_ptr<Motion> make_table_motion(std::vector<double> times, std::vector<Vec3> positions,
                                          std::string source);
// Smooth start of `inner` over ramp_time T_r (s, finite and > 0, else std::invalid_argument):
// x_r = s(t) x(t), v_r = s'(t) x(t) + s(t) v(t) with s = (1 - cos(pi t/T_r))/2 on [0, T_r] and
// s = 1 after, so the motion starts at rest at position 0 instead of with a velocity jump.
std::unique_ptr<Motion> make_ramped_motion(std::unique_ptr<Motion> inner, double ramp_time);

}  // namespace bagdem
