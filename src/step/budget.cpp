// What the step tallies, read at output time: the energy budget, the cavity samples, contact
// counts. Totals are summed over particles (or pairs) in index order, so they are the same for any
// thread count.
#include "stepper.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "bagdem/contact/law.hpp"

namespace bagdem {

// ---- energy budget and loads --------------------------------------------------------------------
double Stepper::potential_energy() const {
  if (!scene_.models.gravity) return 0.0;
  double u = 0;
  for (std::size_t i = 0; i < p_.size(); ++i) u -= p_.mass[i] * scene_.gravity.dot(p_.x[i]);
  for (std::size_t k = 0; k < film_.size(); ++k) u -= film_.mass[k] * scene_.gravity.dot(film_.x[k]);
  return u;
}

template <class Fn>
void Stepper::for_each_contact(Fn&& fn) const {
  for (std::size_t k = 0; k < ps_.pairs.size(); ++k) {
    const std::uint32_t i = ps_.first[k], j = ps_.pairs.partner[k];
    ContactGeometry g;
    if (!sphere_sphere(p_.x[i], p_.x[j], p_.radius[i], p_.radius[j], g)) continue;
    fn(g.overlap, law_energy(scene_.laws(p_.material[i], p_.material[j]), g.R_eff, g.overlap),
       scene_.models.tangential ? &ps_.hist.tangential[k] : nullptr, scene_.models.rolling ? &ps_.hist.rolling[k] : nullptr,
       std::min(p_.radius[i], p_.radius[j]));
  }
  const std::size_t nw = scene_.walls.size();
  for (std::size_t p = 0; p < p_.size(); ++p) {
    for (std::size_t w = 0; w < nw; ++w) {
      const Wall& wall = scene_.walls[w];
      Vec3 n;
      const double overlap = p_.radius[p] - wall_distance(wall, p_.x[p] - motion_at(p_.x[p]).pos, n);
      if (overlap <= 0) continue;
      fn(overlap, law_energy(scene_.laws(p_.material[p], wall.material), wall_effective_radius(wall, p_.radius[p]), overlap),
         scene_.models.tangential ? &walls_.hist.tangential[wall_slot(p, w)] : nullptr,
         scene_.models.rolling ? &walls_.hist.rolling[wall_slot(p, w)] : nullptr, p_.radius[p]);
    }
    // Triangulated surfaces (film, STL walls): the slots of the last step.
    for (std::size_t s = 0; s < (mesh_.slot_count.empty() ? 0 : mesh_.slot_count[p]); ++s) {
      const std::size_t at = p * kMaxMeshContacts + s;
      const MeshSlot& m = mesh_.slots[at];
      fn(m.overlap, 0.0, scene_.models.tangential ? &mesh_.slot_hist.tangential[at] : nullptr,
         scene_.models.rolling ? &mesh_.slot_hist.rolling[at] : nullptr, p_.radius[p]);
    }
  }
}

double Stepper::elastic_energy() const {
  double u = 0;
  for_each_contact([&](double, double elastic, const TangentialHistory* t, const RollingHistory* r, double) {
    u += elastic;
    if (t) u += mindlin_energy(*t);
    if (r) u += rolling_energy(*r);
  });
  for (double e : mesh_.elastic) u += e;  // the triangulated surfaces' (surfaces.cpp)
  return u;
}

// The largest overlap / smaller radius of any contact now (for messages).
double Stepper::largest_overlap_ratio() const {
  double worst = 0;
  for_each_contact([&](double overlap, double, const TangentialHistory*, const RollingHistory*, double r_min) { worst = std::max(worst, overlap / r_min); });
  return worst;
}

EnergySample Stepper::energy() const {
  EnergySample e;
  for (std::size_t i = 0; i < p_.size(); ++i) {
    e.kinetic += 0.5 * p_.mass[i] * p_.v[i].squaredNorm();
    if (scene_.models.rotation) e.kinetic += 0.5 * p_.w[i].squaredNorm() / p_.inv_inertia[i];
    e.work_cavity += p_.tally.work_cavity[i];
    e.dissipated_normal += p_.tally.diss_normal[i];
    e.dissipated_tangential += p_.tally.diss_tangential[i];
    e.dissipated_rolling += p_.tally.diss_rolling[i];
  }
  for (std::size_t k = 0; k < film_.size(); ++k) e.kinetic += 0.5 * film_.mass[k] * film_.v[k].squaredNorm();
  e.work_cavity += film_.tally.work_cavity;
  e.dissipated_normal += film_.tally.diss_normal;
  e.dissipated_tangential += film_.tally.diss_tangential;
  e.dissipated_damping = film_.tally.diss_damping;
  e.elastic = elastic_energy() + film_elastic_energy(scene_, frame(), film_, mesh_);
  e.work_gravity = energy0_.potential - potential_energy();
  return e;
}

CavitySample Stepper::take_cavity_sample() {
  Vec3 J(0, 0, 0), L(0, 0, 0);
  for (std::size_t i = 0; i < p_.size(); ++i) {
    J += p_.tally.wall_impulse[i];
    L += p_.tally.wall_ang_impulse[i];
    p_.tally.wall_impulse[i].setZero();
    p_.tally.wall_ang_impulse[i].setZero();
  }
  J += film_.tally.impulse;
  L += film_.tally.ang_impulse;
  film_.tally.impulse.setZero();
  film_.tally.ang_impulse.setZero();
  CavitySample c;
  const double n = static_cast<double>(cavity_.sums.steps);
  if (n > 0) {
    const double span = n * scene_.dt;
    c.time = cavity_.sums.time / n;
    c.position = cavity_.sums.position / n;
    c.velocity = cavity_.sums.velocity / n;
    c.force = J / span;
    c.torque = L / span;
  }
  cavity_.sums = {};
  c.contents_velocity = contents_relative_velocity();  // at the end of the interval
  return c;
}

void Stepper::add_contents_velocity(const Vec3& dv) {
  for (std::size_t i = 0; i < p_.size(); ++i) p_.v[i] += dv;
  for (std::size_t k = 0; k < film_.size(); ++k) film_.v[k] += dv;
}

Vec3 Stepper::contents_relative_velocity() const {
  Vec3 momentum = Vec3::Zero();
  for (std::size_t i = 0; i < p_.size(); ++i) momentum += p_.mass[i] * p_.v[i];
  for (std::size_t k = 0; k < film_.size(); ++k) momentum += film_.mass[k] * film_.v[k];
  return energy0_.contents_mass > 0 ? Vec3(momentum / energy0_.contents_mass - cavity_.now.velocity) : Vec3::Zero();
}

std::size_t Stepper::contact_count() const {
  std::size_t c = 0;
  for_each_contact([&](double, double, const TangentialHistory*, const RollingHistory*, double) { ++c; });
  return c;
}

}  // namespace bagdem
