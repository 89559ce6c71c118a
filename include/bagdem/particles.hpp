// Particle state as flat arrays, split by temperature.
//  Particles: what the contact loop and the integrator touch every step.
//  ParticleTallies: per-particle running sums read only at output time (energy budget, impulses).
#pragma once
#include <cstddef>
#include <vector>

#include "bagdem/vec3.hpp"

namespace bagdem {

// Mass of a solid sphere of density rho and radius r (unit: kg).
inline double sphere_mass(double rho, double r) { return rho * 4.0 / 3.0 * 3.14159265358979323846 * r * r * r; }

struct Particles {
  std::vector<Vec3> x;             // position (unit: m)
  std::vector<Vec3> v;             // velocity (unit: m/s)
  std::vector<Vec3> w;             // angular velocity (unit: rad/s)
  std::vector<Vec3> v_pred;        // velocity predicted to the end of the step for the contact law (unit: m/s)
  std::vector<Vec3> w_pred;        // same for the angular velocity (unit: rad/s)
  std::vector<Vec3> f;             // force of the current step, gravity included (unit: N)
  std::vector<Vec3> t;             // torque of the current step (unit: N m)
  std::vector<double> radius;      // (unit: m)
  std::vector<double> mass;        // (unit: kg)
  std::vector<double> inv_mass;    // 1/mass (unit: 1/kg)
  std::vector<double> inv_inertia; // 1/(2/5 m R^2), solid sphere (unit: 1/(kg m^2))
  std::vector<int> material;       // index into the scene's materials

  std::size_t size() const { return x.size(); }
  void resize(std::size_t n);
};

// Running sums per particle, so that totals are summed in particle order only when written
// (deterministic for any thread count, and no reduction in the step).
struct ParticleTallies {
  std::vector<Vec3> wall_force_prev;   // same, previous step (trapezoidal work) (unit: N)
  std::vector<Vec3> wall_impulse;      // impulse the particle gave the walls since the last sample (unit: N s)
  std::vector<Vec3> wall_ang_impulse;  // angular impulse about the cavity reference point (unit: N m s)
  std::vector<Vec3> step_dissipation;  // scratch of one step: its (normal, tangential, rolling) share (unit: J)
  std::vector<double> work_cavity;     // cumulative work of the walls on the contents (unit: J)
  std::vector<double> diss_normal;     // cumulative dissipation, half of each pair's share (unit: J)
  std::vector<double> diss_tangential; // (unit: J)
  std::vector<double> diss_rolling;    // (unit: J)
  void resize(std::size_t n);
};

}  // namespace bagdem
