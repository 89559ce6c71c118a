// The neighbours stage (stage.hpp): the Verlet pair list renewed with its contact histories carried
// over, the walls near each ball and the triangulated surfaces' candidate lists, when a ball came
// near the skin's edge (kSkinStep), a film node or the cavity moved more than skin/2.
#include "neighbours.hpp"

#include <algorithm>
#include <cmath>

#include "bagdem/parallel.hpp"
#include "bagdem/scene.hpp"
#include "balls.hpp"
#include "cavity_track.hpp"
#include "film.hpp"
#include "pair_contacts.hpp"
#include "structure_coupling.hpp"
#include "surface_contacts.hpp"
#include "wall_contacts.hpp"

namespace bagdem {

namespace {

// From the installed pair list and its histories: the per-pair buffers, and the travel since the
// build at zero.
void derive_pair_buffers(Neighbours& nb, PairContacts& ps, std::size_t n) {
  const std::size_t np = ps.pairs.size();
  // A pair whose history was carried over may be touching; a fresh pair is not (all-zero history).
  ps.touching.assign(np, 0);
  ps.wake.assign(np, 0.0f);  // every pair looked at in the next pair stage (nb.travel >= 0)
  nb.travel = 0.0;
  nb.far_check_at = -1.0;  // the next drift checks the distances from nb.x_at_build (near_skin_edge)
  nb.near_edge = false;    // every ball is where it was at the build
  for (std::size_t k = 0; k < np; ++k) ps.touching[k] = ps.hist.holds(k);
  ps.first.resize(np);
  ps.reach = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t k = ps.pairs.begin[i]; k < ps.pairs.begin[i + 1]; ++k) {
      ps.first[k] = static_cast<std::uint32_t>(i);
      ps.reach = std::max<std::size_t>(ps.reach, ps.pairs.partner[k] - i);
    }
  ps.ranges = 0;  // cut into ranges at the next pair stage, for its thread count (derive_ranges)
}

// The walls within skin of each ball's surface at the build (nb.x_at_build, the cavity where it was
// then). Until the next build neither moves more than skin/2, so no other wall can be touched.
// A ball with no wall near touched none at the last step either (that wall would be near): it has
// no wall history to close (the wall stage).
void find_near_walls(const NeighbourStage& s) {
  const Scene& scene = s.scene;
  const std::size_t n = s.balls.size(), nw = scene.walls.size();
  CavityState at_build = s.cavity.now;
  at_build.position = s.cavity.pos_at_build;
  at_build.shear = s.cavity.shear_at_build;
  const std::vector<Vec3>& x_at_build = s.nb.x_at_build;
  const std::vector<double>& radius = s.balls.radius;
  const StructureCoupling& structure = s.structure;
  WallContacts& walls = s.walls;
  // Near the bounds: the centre within skin of them (it moves less than skin relative to the cavity
  // before the next build, so the others stay inside).
  std::vector<std::uint8_t>& in_reach = walls.near_scratch;
  in_reach.resize(n);
  parallel_for(n, [&](std::size_t p) {
    const Vec3 x = x_at_build[p];
    const double d = structure.tilt ? (x - at_build.position - scene.cavity_reference).dot(structure.load_axis) : 0.0;
    const Vec3 x_local = x - at_build.position - d * at_build.shear;
    std::uint32_t near = 0;
    for (std::size_t w = 0; w < nw; ++w) {
      Vec3 normal;
      if (wall_distance(scene.walls[w], x_local, normal) - radius[p] < scene.skin) near |= 1u << w;
    }
    walls.near[p] = near;
    const double d_bounds = std::min((x_local - scene.cavity_lo).minCoeff(), (scene.cavity_hi - x_local).minCoeff());
    in_reach[p] = near != 0 || d_bounds < scene.skin;
  });
  walls.near_balls.clear();
  for (std::size_t p = 0; p < n; ++p) {
    if (in_reach[p]) walls.near_balls.push_back(static_cast<std::uint32_t>(p));
    else if (s.structure.couple && s.surfaces.surfaces.empty()) s.structure.cavity_load[p].setZero();  // as the wall stage leaves a ball without a wall near
  }
}

// The surfaces' candidate lists from the positions of a build (the current ones, or those stored
// in a checkpoint), and the walls near each film node.
void build_surface_candidates(const NeighbourStage& s, const std::vector<Vec3>& balls, const std::vector<Vec3>& film, const Vec3& cavity) {
  s.surfaces.build_candidates(s.scene, s.balls.radius, balls, film, cavity);
  if (s.scene.bag) {
    find_film_walls_near(s.film, s.scene, s.frame, film, cavity);
    build_film_self_pairs(s.film, s.scene, film);
  }
}

}  // namespace

void neighbours_stage(const NeighbourStage& s, bool force_rebuild) {
  const Scene& scene = s.scene;
  const Balls& balls = s.balls;
  Neighbours& nb = s.nb;
  PairContacts& ps = s.pairs;
  const std::size_t n = balls.size();
  if (!force_rebuild && !nb.needs_rebuild) {
    const double tilt = s.structure.tilt ? s.cavity.now.shear.norm() * s.structure.tilt_extent : 0.0;
    if (!s.surfaces.need_rebuild(scene, balls.x, nb.x_at_build, s.film.x, s.cavity.now.position, tilt)) return;
  }
  ++nb.builds;
  nb.x_at_build = balls.x;
  // The new list and its histories go into spare buffers (kept between rebuilds, so a rebuild
  // reuses their memory), then swap places with the current ones.
  CandidatePairs& fresh = nb.spare.pairs;
  nb.broad->find(balls.x, balls.radius, scene.skin, fresh);

  // Carry contact histories over: merge the old and new partner lists of each i (both sorted).
  ContactHistories& carried = nb.spare.hist;
  carried.assign(fresh.size(), scene.models.tangential, scene.models.rolling, scene.models.energy);
  if (carried.any_role() && !ps.pairs.partner.empty()) {
    parallel_for(n, [&](std::size_t i) {
      std::uint32_t a = ps.pairs.begin[i], b = fresh.begin[i];
      const std::uint32_t a_end = ps.pairs.begin[i + 1], b_end = fresh.begin[i + 1];
      while (a < a_end && b < b_end) {
        if (ps.pairs.partner[a] < fresh.partner[b]) { ++a; continue; }
        if (ps.pairs.partner[a] > fresh.partner[b]) { ++b; continue; }
        carried.carry(b, ps.hist, a);
        ++a, ++b;
      }
    });
  }
  std::swap(ps.pairs, nb.spare.pairs);
  ps.hist.swap(nb.spare.hist);
  derive_pair_buffers(nb, ps, n);
  s.cavity.pos_at_build = s.cavity.now.position;
  s.cavity.shear_at_build = s.cavity.now.shear;
  find_near_walls(s);
  if (!s.surfaces.surfaces.empty()) build_surface_candidates(s, balls.x, s.film.x, s.cavity.now.position);
}

void neighbours_restored(const NeighbourStage& s) {
  derive_pair_buffers(s.nb, s.pairs, s.balls.size());
  s.nb.near_edge = s.nb.near_skin_edge(s.balls.x, s.scene.skin);  // as the run that saved the image found it at this step (end_drift)
  find_near_walls(s);
  if (!s.surfaces.surfaces.empty()) build_surface_candidates(s, s.nb.x_at_build, s.surfaces.film_at_build, s.surfaces.cavity_at_build);
}

void Neighbours::end_drift(double step2, const std::vector<Vec3>& x, double skin) {
  largest_step = std::sqrt(step2);
  // Rounded up twice over (the square root and the sum): travel never falls short of the true sum
  // of the steps, which the pair stage's skipping relies on (PairState::wake).
  travel = std::nextafter(travel + largest_step * (1.0 + 1e-14), HUGE_VAL);
  // The list is renewed a step ahead (kSkinStep): before the pairs at these positions when a ball
  // was near the skin's edge at the last ones.
  needs_rebuild = near_edge;
  near_edge = travel > far_check_at && near_skin_edge(x, skin);
}

// Asked only when it could be (end_drift): a ball moved at most travel - t since travel was t, so
// after a check found them all within d of their place at the build, none can pass the edge before
// travel has grown by edge - d. The same steps rebuild as with the test at every step, and the
// drift does not read x_at_build. In the shaken PD-box bed the check runs a few times per rebuild
// (the slack shrinks by a fraction each time).
bool Neighbours::near_skin_edge(const std::vector<Vec3>& x, double skin) {
  const Vec3 *xs = x.data(), *at_build = x_at_build.data();
  const double d2 = parallel_fold(x.size(), 0.0, [=](std::size_t i) { return (xs[i] - at_build[i]).squaredNorm(); },
                                  [](double a, double b) { return std::max(a, b); });
  return near_edge_of(d2, travel, far_check_at, skin);
}

bool Neighbours::near_edge_of(double d2, double travel, double& far, double skin) {
  const double edge = (0.5 - kSkinStep) * skin;
  if (d2 > edge * edge) return true;
  // Rounded down by far more than the rounding of these few operations (1e-16 of skin).
  far = travel + (edge - std::nextafter(std::sqrt(d2), HUGE_VAL)) - 1e-12 * skin;
  return false;
}

}  // namespace bagdem
