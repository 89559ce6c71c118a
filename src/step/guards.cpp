// The guards stage (stage.hpp): the run-time guards, and the messages that say what happened and what to
// change.
#include "stepper.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "bagdem/contact/hertz.hpp"
#include "bagdem/error.hpp"

namespace bagdem {

// ---- 7. guards ----------------------------------------------------------------------------------
void Stepper::guards() {
  const std::size_t n = p_.size();
  const bool bad = !guard_.all_finite;  // a NaN position makes the next velocity NaN too
  const bool overlap = guard_.overlap_excess > 0.0;
  const bool escaped = guard_.min_boundary_distance < 0.0;
  constexpr std::size_t none = static_cast<std::size_t>(-1);
  const bool crossed = guard_.crossed != none, crowded = guard_.mesh_overflow != none;
  const bool film_out = scene_.bag && film_.deepest < 0.5 * scene_.bag->film.thickness -
                                                       scene_.max_overlap_fraction * scene_.bag->contact_radius;
  const bool balls = balls_fail(guard_.all_finite, guard_.overlap_excess, guard_.min_boundary_distance, nb_.largest_step, kSkinStep * scene_.skin);
  if (!balls && !crossed && !crowded && !film_out) return;

  std::ostringstream m;
  m << "run stopped at t = " << time() << " s (step " << step_ << "): ";
  if (bad) {
    m << "a particle position or velocity is not a number. The integration diverged: reduce "
         "simulation.timestep (or its safety factor), or check the material parameters.";
    throw RunError(m.str());
  }
  if (crossed && !mesh_.surfaces[guard_.crossed_surface].film) {
    const std::size_t i = guard_.crossed;
    m << "ball " << p_.order[i] << " left the cavity through the STL wall '" << scene_.mesh_walls[guard_.crossed_surface - (scene_.bag ? 1 : 0)].name
      << "' (its centre is " << guard_.crossed_depth << " m beyond it). It went through within one step: reduce "
         "simulation.timestep, the cavity acceleration or the particle speeds, or raise the wall's Young's modulus "
         "(law = \"hooke\": the pair's stiffness).";
    throw RunError(m.str());
  }
  if (crossed) {
    const std::size_t i = guard_.crossed;
    m << "ball " << p_.order[i] << " crossed the bag's film (its centre is " << guard_.crossed_depth
      << " m beyond the film's mid-surface, at (" << p_.x[i].x() << ", " << p_.x[i].y() << ", " << p_.x[i].z()
      << ") m), or the film folded through itself (film-film contact is not modelled) and the ball faces its "
         "outer side. The film contact is too soft for these impacts, or the film too coarse for the ball: raise "
         "the film material's youngs_modulus, refine the film (bag.triangles), reduce simulation.timestep, or "
         "lower the excitation.";
    throw RunError(m.str());
  }
  if (crowded) {
    m << "ball " << p_.order[guard_.mesh_overflow] << " touches more than " << kMaxMeshContacts
      << " separate patches of the film or an STL wall at once: the surface is wrapped round it (a ball much "
         "larger than the triangles, such as one ball in a bag hardly wider than it; docs/bag.md, Guards). Give "
         "a coarser film (bag.triangles) or STL mesh, or smaller balls.";
    throw RunError(m.str());
  }
  if (film_out) {
    m << "a node of the bag's film is pressed " << 0.5 * scene_.bag->film.thickness - film_.deepest
      << " m into a cavity wall (limit " << scene_.max_overlap_fraction << " x bag.film.contact_radius = "
      << scene_.max_overlap_fraction * scene_.bag->contact_radius
      << " m): the film-wall contact is too soft for the load or the step too coarse. Raise "
         "bag.film.contact_radius, reduce simulation.timestep, or lower the excitation.";
    throw RunError(m.str());
  }
  // A particle outside the cavity also shows as a huge wall overlap: name the escape first.
  if (escaped) {
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 xl = p_.x[i] - motion_at(p_.x[i]).pos;
      std::string where;
      for (const Wall& w : scene_.walls) {
        Vec3 nrm;
        if (wall_distance(w, xl, nrm) < 0) where = "through wall '" + scene_.wall_names[static_cast<std::size_t>(&w - scene_.walls.data())] + "'";
      }
      if (where.empty() && ((xl - scene_.cavity_lo).minCoeff() < 0 || (scene_.cavity_hi - xl).minCoeff() < 0))
        where = "beyond the cavity bounds (cavity.min/max)";
      if (where.empty()) continue;
      m << "particle " << p_.order[i] << " left the cavity " << where << " at (" << p_.x[i].x() << ", " << p_.x[i].y()
        << ", " << p_.x[i].z()
        << ") m. It went through the boundary within one step or flew out of an open cavity: reduce "
           "simulation.timestep, the cavity acceleration or the particle speeds, raise the wall's "
           "Young's modulus (law = \"hooke\": the pair's stiffness), or close the cavity.";
      throw RunError(m.str());
    }
  }
  if (overlap) {
    // The guard's own figure: how far beyond the limit (the ratio over the pairs and walls, taken
    // again here, may miss the contact that passed it: a triangulated surface's).
    m << "a contact overlap passed " << 100 * scene_.max_overlap_fraction << "% of the smaller radius (key simulation.max_overlap) by "
      << guard_.overlap_excess << " m";
    if (const double ratio = largest_overlap_ratio(); ratio > scene_.max_overlap_fraction)
      m << " (the largest ball-ball or ball-wall overlap: " << 100 * ratio << "% of a radius)";
    m << ". Impacts are faster or contacts softer than the time step "
         "and stiffness allow: reduce simulation.timestep, raise simulation.expected_speed, or "
         "raise the Young's modulus (law = \"hooke\": the pair's interactions.NAME.stiffness).";
    throw RunError(m.str());
  }
  // Last: a ball that fast has usually done one of the above already, which names what it did.
  m << "a ball moved " << nb_.largest_step << " m in one step, more than " << kSkinStep << " of the neighbour skin ("
    << kSkinStep * scene_.skin << " m of simulation.skin = " << scene_.skin
    << " m). The pair list is renewed a step ahead, for that much motion a step; a faster ball could miss "
       "contacts. Reduce simulation.timestep or raise simulation.skin.";
  throw RunError(m.str());
}

}  // namespace bagdem
