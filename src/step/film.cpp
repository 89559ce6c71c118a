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
#include <limits>

#include "bagdem/contact/surface_law.hpp"
#include "stepper.hpp"
#include "loops.hpp"

namespace bagdem {

namespace {
template <bool Tangential, bool Energy>
void film_walls(const FilmStage& s);
void film_wall_stops(const FilmStage& s);
}  // namespace

void Film::set_up(const Scene& scene) {
  if (!scene.bag) return;
  const Bag& bag = *scene.bag;
  membrane = std::make_unique<Membrane>(bag.rest, bag.film);
  const std::size_t nn = bag.x0.size();
  x = bag.x0;
  v.assign(nn, Vec3::Zero());
  v_pred = v;
  f.assign(nn, Vec3::Zero());
  f_damp.assign(nn, Vec3::Zero());
  f_damp_prev.assign(nn, Vec3::Zero());
  wall_force_prev.assign(nn, Vec3::Zero());
  mass.resize(nn);
  inv_mass.resize(nn);
  for (std::size_t k = 0; k < nn; ++k) {
    mass[k] = membrane->node_mass()[k] * bag.mass_scaling;
    inv_mass[k] = 1.0 / mass[k];
  }
  const std::size_t nw = scene.walls.size();
  wall_hist.assign(nn * nw, scene.models.tangential, false, scene.models.energy);
  wall_touch.assign(nn, 0);
  wall_gap.assign(nn, std::numeric_limits<double>::infinity());
  stl_gap.assign(nn, std::numeric_limits<double>::infinity());
  stl_normal.assign(nn, Vec3::Zero());
  strings.assign(bag.strings.size(), {});
  if (bag.self_radius > 0) {
    self_broad = make_broad_phase(scene.broad_phase);
    self_radii.assign(nn, bag.self_radius);
    std::vector<std::vector<std::uint32_t>> around(nn);
    for (const auto& e : bag.rest.edge_vertices) around[e[0]].push_back(e[1]), around[e[1]].push_back(e[0]);
    neighbour_begin.assign(1, 0);
    for (auto& a : around) {
      std::sort(a.begin(), a.end());
      neighbour.insert(neighbour.end(), a.begin(), a.end());
      neighbour_begin.push_back(static_cast<std::uint32_t>(neighbour.size()));
    }
  }
}

double Film::drift(double dt) {
  const double h = 0.5 * dt;
  return parallel_fold(size(), 0.0, [&](std::size_t k) {
    const Vec3 dv = h * inv_mass[k] * f[k];
    v[k] += dv;
    const Vec3 step = dt * v[k];
    x[k] += step;
    v_pred[k] = v[k] + dv;
    return step.squaredNorm();
  }, [](double a, double b) { return std::max(a, b); });
}

bool Film::kick(double dt) {
  const double h = 0.5 * dt;
  return parallel_fold(size(), true, [&](std::size_t k) {
    v[k] += h * inv_mass[k] * f[k];
    return std::isfinite(v[k].squaredNorm());
  }, [](bool a, bool b) { return a && b; });
}

void film_stage(const FilmStage& s) {
  const Scene& scene = s.scene;
  if (!scene.bag) return;
  Film& film = s.film;
  const SurfaceContacts& surfaces = s.surfaces;
  const Bag& bag = *scene.bag;
  const std::size_t nn = film.size();
  const bool gravity = scene.models.gravity;
  parallel_for(nn, [&](std::size_t k) {
    film.f[k] = gravity ? Vec3(film.mass[k] * scene.gravity) : Vec3::Zero();
    film.f_damp[k].setZero();
  });
  s.load_moments.setZero();
  // Damping sees the velocity predicted to the end of the step, as the contact dashpots do.
  // Bending on its slower clock (Bag::bending_interval N): N times its force at the positions of
  // every N-th step (step 0's included), none at the others; velocity Verlet's two half-kicks around
  // such a step then give the impulse scheme's kick of N dt.
  const int N = bag.bending_interval;
  const bool bending_now = !s.ctx.stepping() || (s.ctx.step + 1) % static_cast<std::uint64_t>(N) == 0;
  film.membrane->add_forces(film.x, film.v_pred, film.f, film.f_damp, bending_now ? N : 0.0);
  with_flags([&s]<bool T, bool E>() { film_walls<T, E>(s); }, scene.models.tangential, scene.models.energy);
  film_self_contacts(s);

  // Strings, from the tie's mean position to the anchor moving with the cavity.
  const double dt = s.ctx.dt;
  for (std::size_t i = 0; i < bag.strings.size(); ++i) {
    const BagString& st = bag.strings[i];
    // The anchor moves with the cavity at its own place (the slope's shear included).
    const WallMotion wm = s.frame.at(st.anchor + s.frame.cavity.now.position);
    const Vec3& c_half = wm.half;
    Vec3 c(0, 0, 0), vc(0, 0, 0), vc_half(0, 0, 0);
    for (std::uint32_t k : st.nodes) {
      c += film.x[k];
      vc += film.v_pred[k];
      vc_half += film.v[k];
    }
    const double inv_n = 1.0 / static_cast<double>(st.nodes.size());
    c *= inv_n, vc *= inv_n, vc_half *= inv_n;
    const Vec3 d = st.anchor + wm.pos - c;
    const double L = d.norm();
    Film::StringState& state = film.strings[i];
    double tension = 0, damping = 0;
    Vec3 u = L > 0 ? Vec3(d / L) : Vec3::Zero();
    if (L > st.rest_length) {
      const double elastic = st.stiffness * (L - st.rest_length);
      tension = std::max(0.0, elastic + st.damping * (wm.vel - vc).dot(u));
      damping = tension - elastic;
    }
    const Vec3 pull = tension * u;  // on the tie, towards the anchor (on the cavity: -pull)
    for (std::uint32_t k : st.nodes) film.f[k] += inv_n * pull;
    if (scene.models.energy) {
      film.tally.diss_damping += 0.5 * (damping + state.damping_prev) * (c_half - vc_half).dot(u) * dt;
      film.tally.work_cavity += 0.5 * (pull + state.pull_prev).dot(wm.step);
    }
    state.damping_prev = damping;
    state.pull_prev = pull;
    film.tally.impulse -= dt * pull;
    film.tally.ang_impulse -= dt * (st.anchor - scene.cavity_reference).cross(pull);
    if (s.frame.structure.couple) s.load_moments += s.frame.load_moments(st.anchor, -pull);
  }

  // The balls' loads, ball by ball.
  constexpr std::size_t K = kMaxMeshContacts;
  for (std::size_t p = 0; p < surfaces.slot_count.size(); ++p) {
    for (std::size_t j = 0; j < surfaces.slot_count[p]; ++j) {
      if (!surfaces.surfaces[surfaces.slots[p * K + j].surface].film) continue;
      const FilmLoad& load = surfaces.film_load[p * K + j];
      for (std::size_t i = 0; i < load.count; ++i) {
        const auto& tri = bag.rest.triangles[load.triangle[i]];
        for (int a = 0; a < 3; ++a) film.f[tri[a]] += load.weights[i][a] * load.force[i];
      }
    }
    for (const NodePush& push : surfaces.film_push[p]) film.f[push.node] += push.force;
  }

  // Membrane damping joins the force; its work over the step is tallied as dissipation.
  double diss = 0;
  for (std::size_t k = 0; k < nn; ++k) {
    film.f[k] += film.f_damp[k];
    if (scene.models.energy) diss -= 0.5 * (film.f_damp[k] + film.f_damp_prev[k]).dot(film.v[k]) * dt;
    film.f_damp_prev[k] = film.f_damp[k];
  }
  film.tally.diss_damping += diss;
  film_wall_stops(s);
}

void find_film_walls_near(Film& film, const Scene& scene, const CavityFrame& frame, const std::vector<Vec3>& at_build, const Vec3& cavity) {
  const std::size_t nn = at_build.size(), nw = scene.walls.size();
  const double reach = 0.5 * scene.bag->film.thickness;
  const StructureCoupling& structure = frame.structure;
  film.wall_near.resize(nn);
  for (std::size_t k = 0; k < nn; ++k) {
    const double s = structure.tilt ? (at_build[k] - cavity - scene.cavity_reference).dot(structure.load_axis) : 0.0;
    const Vec3 x_local = at_build[k] - cavity - s * frame.cavity.shear_at_build;
    std::uint32_t near = 0;
    for (std::size_t w = 0; w < nw; ++w) {
      Vec3 normal;
      if (wall_distance(scene.walls[w], x_local, normal) - reach < scene.skin) near |= 1u << w;
    }
    film.wall_near[k] = near;
  }
}

// Film nodes against the cavity's walls (planes, cylinders): those near (film.wall_near) and
// those touched at the last step; no other can be touched. deepest: over the STL walls (the walls'
// stop, film_wall_stops, holds the nodes on their inner side; the guard looks for one beyond it).
namespace {
template <bool Tangential, bool Energy>
void film_walls(const FilmStage& s) {
  const Scene& scene = s.scene;
  Film& film = s.film;
  const StructureCoupling& structure = s.frame.structure;
  const Bag& bag = *scene.bag;
  const std::size_t nn = film.size(), nw = scene.walls.size();
  const double dt = s.ctx.dt;
  const WallMotion rigid = s.frame.rigid();
  const double reach = 0.5 * bag.film.thickness;
  double work = 0, dn = 0, dtg = 0, deepest = 1e300;
  Vec3 J(0, 0, 0), L(0, 0, 0), load(0, 0, 0);
  const bool stl = !s.surfaces.node_reach.empty();
  for (std::size_t k = 0; k < nn; ++k) {
    // No wall near and none touched at the last step (nor an STL wall to look at): no force now,
    // none then (wall_force_prev is 0), nothing to add.
    film.wall_gap[k] = std::numeric_limits<double>::infinity();
    if ((film.wall_near[k] | film.wall_touch[k]) == 0 && !stl) continue;
    const WallMotion wm = structure.tilt ? s.frame.at(film.x[k]) : rigid;
    const Vec3 &c_vel = wm.vel, &c_half = wm.half, &c_step = wm.step;
    const Vec3 x_local = film.x[k] - wm.pos;
    Vec3 F_wall(0, 0, 0);
    const std::uint32_t touched_before = film.wall_touch[k];
    std::uint32_t touched = 0;
    for (std::uint32_t bits = film.wall_near[k] | touched_before; bits != 0; bits &= bits - 1) {
      const auto w = static_cast<std::size_t>(std::countr_zero(bits));
      const Wall& wall = scene.walls[w];
      Vec3 n;
      const double d = wall_distance(wall, x_local, n);
      film.wall_gap[k] = std::min(film.wall_gap[k], d);
      const double overlap = reach - d;
      const std::size_t h = k * nw + w;
      if (overlap <= 0) {
        if (touched_before & (1u << w)) {
          const Vec3 dd = film.wall_hist.open<Tangential, false, Energy>(h, dt, [&] {
            return OpeningMotion{n, film.v[k] - c_half, Vec3::Zero()};
          });
          if constexpr (Energy) dn += dd.x(), dtg += dd.y();
        }
        continue;
      }
      touched |= 1u << w;
      const Vec3 Fc = film_node_contact<Tangential, Energy>(s, k, n, overlap, scene.laws(bag.material, wall.material), c_vel,
                                                       c_half, film.wall_hist, h, dn, dtg);
      F_wall += Fc;
      L -= dt * (x_local - d * n - scene.cavity_reference).cross(Fc);
      if (structure.couple) load += s.frame.load_moments(x_local - d * n, -Fc);
    }
    film.wall_touch[k] = touched;
    if (stl) film_node_stl_contacts<Tangential, Energy>(s, k, F_wall, L, load, dn, dtg, deepest);
    film.f[k] += F_wall;
    J -= dt * F_wall;
    if constexpr (Energy) {
      work += 0.5 * (F_wall + film.wall_force_prev[k]).dot(c_step);
      film.wall_force_prev[k] = F_wall;
    }
  }
  film.tally.impulse += J;
  film.tally.ang_impulse += L;
  s.load_moments += load;
  film.tally.work_cavity += work;
  film.tally.diss_normal += dn;
  film.tally.diss_tangential += dtg;
  film.deepest = deepest;
}

// The walls' stop: however large the force on a node, it ends no deeper in a wall (plane, cylinder
// or the deepest hit of an STL wall, film_node_stl_contacts) than the guard's overlap,
// simulation.max_overlap x bag.film.contact_radius; in an STL wall, whose contact sees a node only
// within its reach (half the film's thickness) of the surface, on either side, no deeper than its
// centre on the surface when that comes first. Once the node's whole
// force of the step is known, so is its place after the step (x + dt u, u = v + dt F/m its mid-step
// velocity, as Film::drift makes it), and the wall's (moving at its velocity V now: to first order
// in the step, so a node may end deeper by the cavity's acceleration x dt^2, and in a cylinder by
// the curvature's share, second order in its step). Where the node would end deeper, a force along
// the wall's normal puts it at that depth, or holds it at its depth when it is deeper already (it
// is never thrown out): an inelastic stop within the step (the velocity-level contact of Moreau's
// contact dynamics; Box2D's speculative contacts likewise look one step ahead). It acts only where
// the film-wall law cannot hold the node, so a run it never touches keeps its bits; a run it touches
// counts those steps (tally.wall_stops). In set-up nothing moves, and it does nothing.
// Tallies, by the trapezoidal rule the other contacts use: the force F does work F.dx on the node
// over its displacements dx in the step before and the step after (half each), and F.dc through
// the cavity's; the difference, minus F times the node's displacement relative to the wall, is
// dissipated (zero for a node held still, the kinetic energy of the normal approach for a node
// stopped from speed).
// Nodes looked at: those near a wall or touching it (an STL wall: hit this step) whose step (relative to the cavity, the slope's
// share bounded by twice the cavity's half length) could take them from this step's distance
// (film_walls: wall_gap) to the stop, and any whose step is half the allowed overlap or more (a
// node not near is farther than its reach from every wall: find_film_walls_near).
void film_wall_stops(const FilmStage& s) {
  const Scene& scene = s.scene;
  Film& film = s.film;
  const StructureCoupling& structure = s.frame.structure;
  const Bag& bag = *scene.bag;
  const std::size_t nn = film.size(), nw = scene.walls.size();
  const double dt = s.ctx.dt;
  if (!s.ctx.stepping()) return;
  const WallMotion rigid = s.frame.rigid();
  const double allowed = scene.max_overlap_fraction * bag.contact_radius;
  const double limit = 0.5 * bag.film.thickness - allowed;  // the nearest a node's centre may end to a wall
  const double limit_stl = std::max(limit, 0.0);             // to an STL wall
  const std::uint32_t every_wall = nw >= 32 ? ~0u : (1u << nw) - 1;
  // A bound on the square of a node's step relative to the walls: |a|^2, or with the slope's share
  // b, 2 (|a|^2 + b^2) >= (|a| + b)^2.
  const double slope_step = structure.tilt ? 2 * dt * s.frame.cavity.now.shear_rate.norm() * structure.tilt_extent : 0.0;
  const double slope2 = slope_step * slope_step, fast2 = 0.25 * allowed * allowed;
  double diss = 0, work = 0;
  Vec3 J(0, 0, 0), L(0, 0, 0), load(0, 0, 0);
  bool stopped = false;
  for (std::size_t k = 0; k < nn; ++k) {
    Vec3 u = film.v[k] + dt * film.inv_mass[k] * film.f[k];
    const double a2 = (dt * (u - rigid.vel)).squaredNorm(), step2 = structure.tilt ? 2 * (a2 + slope2) : a2;
    std::uint32_t walls = film.wall_near[k] | film.wall_touch[k];
    const bool stl = std::isfinite(film.stl_gap[k]);
    const double gap = std::min(film.wall_gap[k] - limit, film.stl_gap[k] - limit_stl);
    if (step2 >= fast2) walls = every_wall;
    else if (gap > 0 && gap * gap > 1.002 * step2) continue;
    if (walls == 0 && !stl) continue;
    const WallMotion wm = structure.tilt || stl ? s.frame.at(film.x[k]) : rigid;
    const Vec3 x_local = film.x[k] - wm.pos;
    Vec3 F_node(0, 0, 0);
    bool held = false;
    // The node at distance d from a wall of normal n (towards the node), held at `nearest` at least.
    auto hold = [&](double d, const Vec3& n, double nearest) {
      const double ahead = d + dt * (u - wm.vel).dot(n), target = std::min(nearest, d);
      if (ahead >= target) return;
      const double dv = (target - ahead) / dt;
      const Vec3 F = (film.mass[k] * dv / dt) * n;
      F_node += F;
      u += dv * n;
      J -= dt * F;
      L -= dt * (x_local - d * n - scene.cavity_reference).cross(F);
      if (structure.couple) load += s.frame.load_moments(x_local - d * n, -F);
      held = true;
    };
    for (; walls != 0; walls &= walls - 1) {
      Vec3 n;
      const double d = wall_distance(scene.walls[static_cast<std::size_t>(std::countr_zero(walls))], x_local, n);
      hold(d, n, limit);
    }
    if (stl) hold(film.stl_gap[k], film.stl_normal[k], limit_stl);
    if (!held) continue;
    film.f[k] += F_node;
    const Vec3 node_moves = dt * film.v[k] + dt * u, cavity_moves = wm.step + dt * wm.vel;
    work += 0.5 * F_node.dot(cavity_moves);
    diss -= 0.5 * F_node.dot(node_moves - cavity_moves);
    stopped = true;
  }
  if (!stopped) return;
  ++film.tally.wall_stops;
  film.tally.diss_normal += diss;
  film.tally.work_cavity += work;
  film.tally.impulse += J;
  film.tally.ang_impulse += L;
  s.load_moments += load;
}

}  // namespace

// Elastic energy held by the film: membrane and bending, strings, film-wall contacts.
double film_elastic_energy(const Scene& scene, const CavityFrame& frame, const Film& film, const SurfaceContacts& surfaces) {
  if (!scene.bag) return 0.0;
  const Bag& bag = *scene.bag;
  double u = film.membrane->elastic_energy(film.x) + film_self_energy(scene, film);
  for (std::size_t s = 0; s < bag.strings.size(); ++s) {
    const BagString& st = bag.strings[s];
    Vec3 c(0, 0, 0);
    for (std::uint32_t k : st.nodes) c += film.x[k];
    c /= static_cast<double>(st.nodes.size());
    const double L = (st.anchor + frame.at(st.anchor + frame.cavity.now.position).pos - c).norm();
    if (L > st.rest_length) u += 0.5 * st.stiffness * (L - st.rest_length) * (L - st.rest_length);
  }
  for (std::size_t k = 0; k < surfaces.node_slot_count.size(); ++k) {
    u += surfaces.node_elastic[k];
    if (scene.models.tangential)
      for (std::size_t j = 0; j < surfaces.node_slot_count[k]; ++j) u += mindlin_energy(surfaces.node_slot_hist.tangential[k * kMaxMeshContacts + j]);
  }
  const std::size_t nw = scene.walls.size();
  for (std::size_t k = 0; k < film.size(); ++k)
    for (std::size_t w = 0; w < nw; ++w) {
      Vec3 n;
      const double overlap = 0.5 * bag.film.thickness - wall_distance(scene.walls[w], film.x[k] - frame.at(film.x[k]).pos, n);
      if (overlap <= 0) continue;
      u += law_energy(scene.laws(bag.material, scene.walls[w].material), bag.contact_radius, overlap);
      if (scene.models.tangential) u += mindlin_energy(film.wall_hist.tangential[k * nw + w]);
    }
  return u;
}

}  // namespace bagdem
