// The film stage (stage.hpp): the bag's film. Its nodes carry gravity, the membrane's elastic and damping
// forces (bag/membrane.hpp), their contacts with the cavity walls, the strings' pull, and the
// loads of the balls' film contacts (surfaces.cpp), summed in a fixed order (node by node;
// the balls' loads in ball order), so results do not depend on the thread count.
//
// Film-wall contact: each node is the centre of a small patch of film of half thickness t/2; it
// touches a wall when closer than t/2 to it, with the contact law of the film's and the
// wall's materials, R* = bag.film.contact_radius and m* = the node's mass. (A penalty with the
// right scales: the film is thin, the patch radius sets the stiffness; what the balls feel through
// the film is the ball-film law.) Its force on the cavity enters the cavity's load and work.
// Strings: bag/bag.hpp (BagString); tension T = k (L - L0) + c dL/dt while L > L0, never negative.
#include <algorithm>
#include <bit>
#include <cmath>

#include "bagdem/contact/surface_law.hpp"
#include "stepper.hpp"
#include "loops.hpp"

namespace bagdem {

void Stepper::set_up_film() {
  if (!scene_.bag) return;
  const Bag& bag = *scene_.bag;
  film_.membrane = std::make_unique<Membrane>(bag.rest, bag.film);
  const std::size_t nn = bag.x0.size();
  film_.x = bag.x0;
  film_.v.assign(nn, Vec3::Zero());
  film_.v_pred = film_.v;
  film_.f.assign(nn, Vec3::Zero());
  film_.f_damp.assign(nn, Vec3::Zero());
  film_.f_damp_prev.assign(nn, Vec3::Zero());
  film_.wall_force_prev.assign(nn, Vec3::Zero());
  film_.mass.resize(nn);
  film_.inv_mass.resize(nn);
  for (std::size_t k = 0; k < nn; ++k) {
    film_.mass[k] = film_.membrane->node_mass()[k] * bag.mass_scaling;
    film_.inv_mass[k] = 1.0 / film_.mass[k];
  }
  const std::size_t nw = scene_.walls.size();
  film_.wall_hist.assign(nn * nw, scene_.models.tangential, false, scene_.models.energy);
  film_.wall_touch.assign(nn, 0);
  film_.strings.assign(bag.strings.size(), {});
}

void Stepper::film_stage() {
  if (!scene_.bag) return;
  const Bag& bag = *scene_.bag;
  const std::size_t nn = film_.size();
  const bool gravity = scene_.models.gravity;
  parallel_for(nn, [&](std::size_t k) {
    film_.f[k] = gravity ? Vec3(film_.mass[k] * scene_.gravity) : Vec3::Zero();
    film_.f_damp[k].setZero();
  });
  structure_.film_load_moments.setZero();
  // Damping sees the velocity predicted to the end of the step, as the contact dashpots do.
  film_.membrane->add_forces(film_.x, film_.v_pred, film_.f, film_.f_damp);
  with_flags([this]<bool T, bool E>() { film_walls<T, E>(); }, scene_.models.tangential, scene_.models.energy);

  // Strings, from the tie's mean position to the anchor moving with the cavity.
  const double dt = ctx_.dt;
  for (std::size_t s = 0; s < bag.strings.size(); ++s) {
    const BagString& st = bag.strings[s];
    // The anchor moves with the cavity at its own place (the slope's shear included).
    const WallMotion wm = motion_at(st.anchor + cavity_.now.position);
    const Vec3& c_half = wm.half;
    Vec3 c(0, 0, 0), vc(0, 0, 0), vc_half(0, 0, 0);
    for (std::uint32_t k : st.nodes) {
      c += film_.x[k];
      vc += film_.v_pred[k];
      vc_half += film_.v[k];
    }
    const double inv_n = 1.0 / static_cast<double>(st.nodes.size());
    c *= inv_n, vc *= inv_n, vc_half *= inv_n;
    const Vec3 d = st.anchor + wm.pos - c;
    const double L = d.norm();
    Film::StringState& state = film_.strings[s];
    double tension = 0, damping = 0;
    Vec3 u = L > 0 ? Vec3(d / L) : Vec3::Zero();
    if (L > st.rest_length) {
      const double elastic = st.stiffness * (L - st.rest_length);
      tension = std::max(0.0, elastic + st.damping * (wm.vel - vc).dot(u));
      damping = tension - elastic;
    }
    const Vec3 pull = tension * u;  // on the tie, towards the anchor (on the cavity: -pull)
    for (std::uint32_t k : st.nodes) film_.f[k] += inv_n * pull;
    if (scene_.models.energy) {
      film_.tally.diss_damping += 0.5 * (damping + state.damping_prev) * (c_half - vc_half).dot(u) * dt;
      film_.tally.work_cavity += 0.5 * (pull + state.pull_prev).dot(wm.step);
    }
    state.damping_prev = damping;
    state.pull_prev = pull;
    film_.tally.impulse -= dt * pull;
    film_.tally.ang_impulse -= dt * (st.anchor - scene_.cavity_reference).cross(pull);
    if (structure_.couple) structure_.film_load_moments += load_moments(st.anchor, -pull);
  }

  // The balls' loads, ball by ball.
  constexpr std::size_t K = kMaxMeshContacts;
  for (std::size_t p = 0; p < p_.size(); ++p) {
    for (std::size_t s = 0; s < mesh_.slot_count[p]; ++s) {
      if (!mesh_.surfaces[mesh_.slots[p * K + s].surface].film) continue;
      const FilmLoad& load = mesh_.film_load[p * K + s];
      for (std::size_t i = 0; i < load.count; ++i) {
        const auto& tri = bag.rest.triangles[load.triangle[i]];
        for (int a = 0; a < 3; ++a) film_.f[tri[a]] += load.weights[i][a] * load.force[i];
      }
    }
    for (const NodePush& push : mesh_.film_push[p]) film_.f[push.node] += push.force;
  }

  // Membrane damping joins the force; its work over the step is tallied as dissipation.
  double diss = 0;
  for (std::size_t k = 0; k < nn; ++k) {
    film_.f[k] += film_.f_damp[k];
    if (scene_.models.energy) diss -= 0.5 * (film_.f_damp[k] + film_.f_damp_prev[k]).dot(film_.v[k]) * dt;
    film_.f_damp_prev[k] = film_.f_damp[k];
  }
  film_.tally.diss_damping += diss;
}

// The walls within skin of each film node's reach at the build (film: the nodes then, cavity: its
// position then, with the shear then), as find_near_walls for the balls: film_.wall_near, bit w
// for wall w. Until the next build neither moves more than skin/2 (meshes_need_rebuild,
// move_cavity), so the film-wall stage skips the others.
void Stepper::find_film_walls_near(const std::vector<Vec3>& film, const Vec3& cavity) {
  const std::size_t nn = film.size(), nw = scene_.walls.size();
  const double reach = 0.5 * scene_.bag->film.thickness;
  film_.wall_near.resize(nn);
  for (std::size_t k = 0; k < nn; ++k) {
    const double s = structure_.tilt ? (film[k] - cavity - scene_.cavity_reference).dot(structure_.load_axis) : 0.0;
    const Vec3 x_local = film[k] - cavity - s * cavity_.shear_at_build;
    std::uint32_t near = 0;
    for (std::size_t w = 0; w < nw; ++w) {
      Vec3 normal;
      if (wall_distance(scene_.walls[w], x_local, normal) - reach < scene_.skin) near |= 1u << w;
    }
    film_.wall_near[k] = near;
  }
}

// Film nodes against the cavity's walls (planes, cylinders): those near (film_.wall_near) and
// those touched at the last step; no other can be touched. deepest: over the walls looked at (the
// others are farther than the skin, far from the guard's limit).
template <bool Tangential, bool Energy>
void Stepper::film_walls() {
  const Bag& bag = *scene_.bag;
  const std::size_t nn = film_.size(), nw = scene_.walls.size();
  const double dt = ctx_.dt;
  const WallMotion rigid = rigid_motion();
  const double reach = 0.5 * bag.film.thickness;
  double work = 0, dn = 0, dtg = 0, deepest = 1e300;
  Vec3 J(0, 0, 0), L(0, 0, 0), load(0, 0, 0);
  const bool stl = !mesh_.node_reach.empty();
  for (std::size_t k = 0; k < nn; ++k) {
    // No wall near and none touched at the last step (nor an STL wall to look at): no force now,
    // none then (wall_force_prev is 0), nothing to add.
    if ((film_.wall_near[k] | film_.wall_touch[k]) == 0 && !stl) continue;
    const WallMotion wm = structure_.tilt ? motion_at(film_.x[k]) : rigid;
    const Vec3 &c_vel = wm.vel, &c_half = wm.half, &c_step = wm.step;
    const Vec3 x_local = film_.x[k] - wm.pos;
    Vec3 F_wall(0, 0, 0);
    const std::uint32_t touched_before = film_.wall_touch[k];
    std::uint32_t touched = 0;
    for (std::uint32_t bits = film_.wall_near[k] | touched_before; bits != 0; bits &= bits - 1) {
      const auto w = static_cast<std::size_t>(std::countr_zero(bits));
      const Wall& wall = scene_.walls[w];
      Vec3 n;
      const double d = wall_distance(wall, x_local, n);
      deepest = std::min(deepest, d);
      const double overlap = reach - d;
      const std::size_t h = k * nw + w;
      if (overlap <= 0) {
        if (touched_before & (1u << w)) {
          const Vec3 dd = film_.wall_hist.open<Tangential, false, Energy>(h, dt, [&] {
            return OpeningMotion{n, film_.v[k] - c_half, Vec3::Zero()};
          });
          if constexpr (Energy) dn += dd.x(), dtg += dd.y();
        }
        continue;
      }
      touched |= 1u << w;
      const Vec3 Fc = node_contact<Tangential, Energy>(k, n, overlap, scene_.laws(bag.material, wall.material), c_vel,
                                                       c_half, film_.wall_hist, h, dn, dtg);
      F_wall += Fc;
      L -= dt * (x_local - d * n - scene_.cavity_reference).cross(Fc);
      if (structure_.couple) load += load_moments(x_local - d * n, -Fc);
    }
    film_.wall_touch[k] = touched;
    if (stl) node_mesh_contacts<Tangential, Energy>(k, F_wall, L, load, dn, dtg, deepest);
    film_.f[k] += F_wall;
    J -= dt * F_wall;
    if constexpr (Energy) {
      work += 0.5 * (F_wall + film_.wall_force_prev[k]).dot(c_step);
      film_.wall_force_prev[k] = F_wall;
    }
  }
  film_.tally.impulse += J;
  film_.tally.ang_impulse += L;
  structure_.film_load_moments += load;
  film_.tally.work_cavity += work;
  film_.tally.diss_normal += dn;
  film_.tally.diss_tangential += dtg;
  film_.deepest = deepest;
}

// Elastic energy held by the film: membrane and bending, strings, film-wall contacts.
double Stepper::film_elastic_energy() const {
  if (!scene_.bag) return 0.0;
  const Bag& bag = *scene_.bag;
  double u = film_.membrane->elastic_energy(film_.x);
  for (std::size_t s = 0; s < bag.strings.size(); ++s) {
    const BagString& st = bag.strings[s];
    Vec3 c(0, 0, 0);
    for (std::uint32_t k : st.nodes) c += film_.x[k];
    c /= static_cast<double>(st.nodes.size());
    const double L = (st.anchor + motion_at(st.anchor + cavity_.now.position).pos - c).norm();
    if (L > st.rest_length) u += 0.5 * st.stiffness * (L - st.rest_length) * (L - st.rest_length);
  }
  for (std::size_t k = 0; k < mesh_.node_slot_count.size(); ++k) {
    u += mesh_.node_elastic[k];
    if (scene_.models.tangential)
      for (std::size_t j = 0; j < mesh_.node_slot_count[k]; ++j) u += mindlin_energy(mesh_.node_slot_hist.tangential[k * kMaxMeshContacts + j]);
  }
  const std::size_t nw = scene_.walls.size();
  for (std::size_t k = 0; k < film_.size(); ++k)
    for (std::size_t w = 0; w < nw; ++w) {
      Vec3 n;
      const double overlap = 0.5 * bag.film.thickness - wall_distance(scene_.walls[w], film_.x[k] - motion_at(film_.x[k]).pos, n);
      if (overlap <= 0) continue;
      u += law_energy(scene_.laws(bag.material, scene_.walls[w].material), bag.contact_radius, overlap);
      if (scene_.models.tangential) u += mindlin_energy(film_.wall_hist.tangential[k * nw + w]);
    }
  return u;
}

}  // namespace bagdem
