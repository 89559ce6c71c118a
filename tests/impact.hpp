// Test support: one head-on impact (two spheres, or a sphere on a plane), stepped until the contact
// has ended, with what analytic references are compared against.
#pragma once
#include <cmath>

#include "bagdem/contact/law.hpp"
#include "bagdem/contact/pair_laws.hpp"
#include "bagdem/step/simulation.hpp"
#include "scene_builder.hpp"

namespace bagdem::testing {

struct ImpactResult {
  double restitution = 0;   // separation speed / approach speed
  double duration = 0;      // contact time, interpolated at both ends (unit: s)
  double max_overlap = 0;   // (unit: m)
  double min_normal_force = 0;  // smallest normal force during the contact (unit: N); < 0 = tensile
  double hertz_duration = 0;    // the law's theory for the same m*, R*, v (Hertz's by default)
  double hertz_overlap = 0;
};

// material: (rho, E, nu); `in` the pair's interaction (its law, e); v approach speed; wall = sphere
// on a plane. steps_per_contact sets dt from the law's contact time as the auto time step does
// (ContactLawRow::resolved_step).
inline ImpactResult head_on_impact(const Interaction& in, double rho, double E, double nu, double v, bool wall,
                                   double steps_per_contact = 40, double radius = 2e-3) {
  SceneBuilder b;
  b.material("m", rho, E, nu).interaction(in);
  const double m = sphere_mass(rho, radius);
  const double R_eff = wall ? radius : radius / 2, m_eff = wall ? m : m / 2;
  const PairLaw law = make_pair_laws({{"m", rho, E, nu}}, {in}).laws[0];
  const ContactLawRow& row = contact_law(law.kind);
  const double gap = 1e-3 * radius;
  if (wall) {
    b.plane(Vec3::Zero(), Vec3::UnitZ()).particle(Vec3(0, 0, radius + gap), Vec3(0, 0, -v), radius);
  } else {
    b.particle(Vec3(0, 0, -radius - gap / 2), Vec3(0, 0, v / 2), radius)
        .particle(Vec3(0, 0, radius + gap / 2), Vec3(0, 0, -v / 2), radius);
  }
  b.bounds(Vec3::Constant(-1), Vec3::Constant(1)).dt(row.resolved_step(law, m_eff, R_eff, v, steps_per_contact));
  const Scene scene = b.build();
  Simulation sim(scene);
  auto overlap = [&] {
    const auto& x = sim.particles().x;
    return wall ? radius - x[0].z() : 2 * radius - (x[1] - x[0]).norm();
  };
  auto normal_force = [&] { return wall ? sim.particles().f[0].z() : -sim.particles().f[0].z(); };
  ImpactResult r;
  r.hertz_duration = row.contact_time(law, m_eff, R_eff, v);
  r.hertz_overlap = row.max_overlap(law, m_eff, R_eff, v);
  r.min_normal_force = 1e300;
  double prev = overlap(), t_open = -1, t_close = -1;
  const double dt = scene.dt;
  for (int k = 0; k < 100000 && t_close < 0; ++k) {
    sim.step();
    const double now = overlap();
    if (now > 0) {
      r.max_overlap = std::max(r.max_overlap, now);
      r.min_normal_force = std::min(r.min_normal_force, normal_force());
    }
    // Linear interpolation of the overlap's zero crossings.
    if (prev <= 0 && now > 0) t_open = sim.time() - dt * now / (now - prev);
    if (prev > 0 && now <= 0 && t_open >= 0) t_close = sim.time() - dt * now / (now - prev);
    prev = now;
  }
  for (int k = 0; k < 5; ++k) sim.step();  // leave the contact for good
  r.duration = t_close - t_open;
  const auto& vel = sim.particles().v;
  r.restitution = wall ? vel[0].z() / v : (vel[1].z() - vel[0].z()) / v;
  return r;
}
inline ImpactResult head_on_impact(double rho, double E, double nu, double e, double v, bool wall,
                                   double steps_per_contact = 40, double radius = 2e-3) {
  return head_on_impact(Interaction{e, 0, 0}, rho, E, nu, v, wall, steps_per_contact, radius);
}

}  // namespace bagdem::testing
