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
void check_guards(const GuardStage& st) {
  const Scene& scene = st.scene;
  const Balls& balls = st.balls;
  const GuardValues& guard = st.guard;
  const SurfaceContacts& surfaces = st.surfaces;
  const std::size_t n = balls.size();
  const bool bad = !guard.all_finite;  // a NaN position makes the next velocity NaN too
  const bool overlap = guard.overlap_excess > 0.0;
  const bool escaped = guard.min_boundary_distance < 0.0;
  constexpr std::size_t none = static_cast<std::size_t>(-1);
  const bool crossed = guard.crossed != none, crowded = guard.mesh_overflow != none;
  // The walls' stop (film.cpp) holds film nodes on an STL wall's inner side; a node's centre half its
  // reach beyond the surface went past it within a step (the wall's contact sees a node only within
  // its reach, half the film's thickness, of the surface).
  const bool film_out = scene.bag && st.film.deepest < -0.25 * scene.bag->film.thickness;
  const bool ball_fault = balls_fail(guard.all_finite, guard.overlap_excess, guard.min_boundary_distance, st.largest_step, st.skin_step * scene.skin);
  if (!ball_fault && !crossed && !crowded && !film_out) return;

  std::ostringstream m;
  m << "run stopped at t = " << st.time << " s (step " << st.step << "): ";
  if (bad) {
    m << "a particle position or velocity is not a number. The integration diverged: reduce "
         "simulation.timestep (or its safety factor), or check the material parameters.";
    throw RunError(m.str());
  }
  if (crossed && !surfaces.surfaces[guard.crossed_surface].film) {
    const std::size_t i = guard.crossed;
    m << "ball " << balls.order[i] << " left the cavity through the STL wall '" << scene.mesh_walls[guard.crossed_surface - (scene.bag ? 1 : 0)].name
      << "' (its centre is " << guard.crossed_depth << " m beyond it). It went through within one step: reduce "
         "simulation.timestep, the cavity acceleration or the particle speeds, or raise the wall's Young's modulus "
         "(law = \"hooke\": the pair's stiffness).";
    throw RunError(m.str());
  }
  if (crossed) {
    const std::size_t i = guard.crossed;
    m << "ball " << balls.order[i] << " crossed the bag's film (its centre is " << guard.crossed_depth
      << " m beyond the film's mid-surface, at (" << balls.x[i].x() << ", " << balls.x[i].y() << ", " << balls.x[i].z()
      << ") m), or the film folded through itself and the ball faces its outer side"
      << (scene.bag->self_radius > 0 ? "" : " (bag.film.self_contact = false lets the film pass through itself: set it true)")
      << ". The film contact is too soft for these impacts, or the film too coarse for the ball: raise "
         "the film material's youngs_modulus, refine the film (bag.triangles), reduce simulation.timestep, or "
         "lower the excitation.";
    throw RunError(m.str());
  }
  if (crowded) {
    m << "ball " << balls.order[guard.mesh_overflow] << " touches more than " << kMaxMeshContacts
      << " separate patches of the film or an STL wall at once: the surface is wrapped round it (a ball much "
         "larger than the triangles, such as one ball in a bag hardly wider than it; docs/bag.md, Guards). Give "
         "a coarser film (bag.triangles) or STL mesh, or smaller balls.";
    throw RunError(m.str());
  }
  if (film_out) {
    m << "a node of the bag's film is " << -st.film.deepest
      << " m beyond an STL wall's surface, past the walls' stop that holds the film on the inner side: it went there "
         "within one step. Reduce simulation.timestep, or lower the excitation.";
    throw RunError(m.str());
  }
  // A particle outside the cavity also shows as a huge wall overlap: name the escape first.
  if (escaped) {
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 xl = balls.x[i] - st.frame.at(balls.x[i]).pos;
      std::string where;
      for (const Wall& w : scene.walls) {
        Vec3 nrm;
        if (wall_distance(w, xl, nrm) < 0) where = "through wall '" + scene.wall_names[static_cast<std::size_t>(&w - scene.walls.data())] + "'";
      }
      if (where.empty() && ((xl - scene.cavity_lo).minCoeff() < 0 || (scene.cavity_hi - xl).minCoeff() < 0))
        where = "beyond the cavity bounds (cavity.min/max)";
      if (where.empty()) continue;
      m << "particle " << balls.order[i] << " left the cavity " << where << " at (" << balls.x[i].x() << ", " << balls.x[i].y()
        << ", " << balls.x[i].z()
        << ") m. It went through the boundary within one step or flew out of an open cavity: reduce "
           "simulation.timestep, the cavity acceleration or the particle speeds, raise the wall's "
           "Young's modulus (law = \"hooke\": the pair's stiffness), or close the cavity.";
      throw RunError(m.str());
    }
  }
  if (overlap) {
    // The guard's own figure: how far beyond the limit (the ratio over the pairs and walls, taken
    // again here, may miss the contact that passed it: a triangulated surface's).
    m << "a contact overlap passed " << 100 * scene.max_overlap_fraction << "% of the smaller radius (key simulation.max_overlap) by "
      << guard.overlap_excess << " m";
    if (const double ratio = st.largest_overlap_ratio(); ratio > scene.max_overlap_fraction)
      m << " (the largest ball-ball or ball-wall overlap: " << 100 * ratio << "% of a radius)";
    m << ". Impacts are faster or contacts softer than the time step "
         "and stiffness allow: reduce simulation.timestep, raise simulation.expected_speed, or "
         "raise the Young's modulus (law = \"hooke\": the pair's interactions.NAME.stiffness).";
    if (scene.bag && scene.bag->shrink < 1 && st.time < scene.settle)
      m << " The bag's film, pulled tight (bag.film.shrink = " << scene.bag->shrink
        << "), closes on its balls as they settle: a value nearer 1 closes it more gently.";
    throw RunError(m.str());
  }
  // Last: a ball that fast has usually done one of the above already, which names what it did.
  m << "a ball moved " << st.largest_step << " m in one step, more than " << st.skin_step << " of the neighbour skin ("
    << st.skin_step * scene.skin << " m of simulation.skin = " << scene.skin
    << " m). The pair list is renewed a step ahead, for that much motion a step; a faster ball could miss "
       "contacts. Reduce simulation.timestep or raise simulation.skin.";
  throw RunError(m.str());
}

void Stepper::guards() {
  check_guards({scene_, frame(), p_, film_, mesh_, guard_, nb_.largest_step, kSkinStep, time(), step_,
                [this] { return largest_overlap_ratio(); }});
}

}  // namespace bagdem
