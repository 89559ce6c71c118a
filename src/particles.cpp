#include "bagdem/particles.hpp"

namespace bagdem {

void Particles::resize(std::size_t n) {
  x.resize(n, Vec3::Zero());
  v.resize(n, Vec3::Zero());
  w.resize(n, Vec3::Zero());
  v_pred.resize(n, Vec3::Zero());
  w_pred.resize(n, Vec3::Zero());
  f.resize(n, Vec3::Zero());
  t.resize(n, Vec3::Zero());
  radius.resize(n, 0.0);
  mass.resize(n, 0.0);
  inv_mass.resize(n, 0.0);
  inv_inertia.resize(n, 0.0);
  material.resize(n, 0);
}

void ParticleTallies::resize(std::size_t n) {
  wall_force_prev.assign(n, Vec3::Zero());
  wall_impulse.assign(n, Vec3::Zero());
  wall_ang_impulse.assign(n, Vec3::Zero());
  step_dissipation.assign(n, Vec3::Zero());
  work_cavity.assign(n, 0.0);
  diss_normal.assign(n, 0.0);
  diss_tangential.assign(n, 0.0);
  diss_rolling.assign(n, 0.0);
}

}  // namespace bagdem
