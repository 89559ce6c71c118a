// The triangles stage (stage.hpp): balls against triangulated surfaces, the bag's film (deformable, surface 0
// when there is a bag) and STL walls (rigid, moving with the cavity).
//
// Elastic force: the Euler sum over the features within reach (surface_features.hpp, euler_terms),
// a potential of the positions that counts no contacts: exact on a flat triangulation, continuous
// where contacts are born, merge or split. Each term's force (the law's) acts on the ball along its
// normal, and its reaction on the feature's nodes by the closest point's barycentric weights (the
// exact derivative of the distance with respect to the node positions): the pair is conservative.
// Damping and friction: the contact law, on the contacts of the one-contact-per-feature rule (a
// ball on a flat triangulation has the one contact it would have with the plane), one per patch
// (hits with normals within 30 degrees: PatchBlend) so that a shallow fold does not double them.
// The law sees the overlap whose stiffness is the Euler sum's along the contact's normal
// (law_overlaps), so its damping gives the requested restitution, and its elastic part is taken
// off. A ball is on one side of a surface for the whole run (mesh_.side: inside the film for the bag's
// balls, inside an STL cavity always); the normal points to that side, and a centre found beyond
// the mid-surface stops the run (guards).
// Law: the pair law of the ball's and the surface's materials (contact/law.hpp), with the film's half thickness added to the reach, R* = the ball's radius (a flat
// triangle), and m* from the ball's mass and the contact point's effective mass on the film,
// 1/m_s = sum_k w_k^2 / m_k over the triangle's nodes (w: barycentric weights; the exact inverse
// mass of a point tied to three particles). A rigid wall has 1/m_s = 0, so as the film's nodes get
// heavy (or a wall is meshed) the law is exactly the ball-wall law.
// Histories: each contact is a slot of its ball, keyed by surface and feature. A contact that moves
// to a neighbouring feature (face -> edge -> next face across a shared edge) takes over the history
// of the slot it came from (the closed slot of the same surface with the most aligned normal), so
// friction springs survive grazing motion across a triangulation as they do on a plane.
#include <algorithm>
#include <cmath>
#include <limits>

#include "bagdem/contact/sphere_triangle.hpp"
#include "bagdem/contact/surface_law.hpp"
#include "loops.hpp"
#include "stepper.hpp"
#include "surface_features.hpp"

namespace bagdem {
using namespace surface_contacts;

void SurfaceContacts::set_up(const Scene& scene, const Balls& balls, const Film& film) {
  surfaces.clear();
  if (scene.bag) surfaces.push_back({&scene.bag->rest, true, scene.bag->material, 0.5 * scene.bag->film.thickness});
  for (const MeshWall& w : scene.mesh_walls) surfaces.push_back({&w.mesh, false, w.material, 0.0});
  if (surfaces.empty()) return;
  const std::size_t n = balls.size();
  slots.assign(n * kMaxMeshContacts, MeshSlot{});
  slot_hist.assign(n * kMaxMeshContacts, scene.models.tangential, scene.models.rolling, scene.models.energy);
  slot_count.assign(n, 0);
  film_load.assign(n * kMaxMeshContacts, FilmLoad{});
  elastic.assign(n, 0.0);
  film_push.assign(n, {});
  side.assign(n, -1);
  if (scene.bag) {
    // The bag's balls are inside its film; any other ball is on the side where it starts.
    const Bag& bag = *scene.bag;
    for (std::size_t i = 0; i < n; ++i) {
      const bool in_bag = i >= bag.ball_first && i < bag.ball_first + bag.balls;
      side[i] = in_bag || winding_number(bag.rest, film.x, balls.x[i]) > 0.5 ? -1 : 1;
    }
  }
  cand.assign(surfaces.size(), {});
  force_prev.assign(n, Vec3::Zero());
  node_cand.assign(surfaces.size(), {});
  if (scene.bag && !scene.mesh_walls.empty()) {
    node_reach.assign(film.size(), 0.5 * scene.bag->film.thickness);
    node_slots.assign(film.size() * kMaxMeshContacts, MeshSlot{});
    node_slot_hist.assign(film.size() * kMaxMeshContacts, scene.models.tangential, false, scene.models.energy);
    node_slot_count.assign(film.size(), 0);
    node_elastic.assign(film.size(), 0.0);
  }
}

// ---- 6. triangles -------------------------------------------------------------------------------
// From the positions of a build (the current ones, or those stored in a checkpoint).
void SurfaceContacts::build_candidates(const Scene& scene, const std::vector<double>& radius, const std::vector<Vec3>& balls,
                                       const std::vector<Vec3>& film, const Vec3& cavity) {
  for (std::size_t s = 0; s < surfaces.size(); ++s) {
    const Surface& sf = surfaces[s];
    if (sf.film) {
      find_mesh_candidates(*sf.mesh, film, balls, radius, Vec3::Zero(), sf.reach, scene.skin, cand[s]);
    } else {
      find_mesh_candidates(*sf.mesh, sf.mesh->vertices, balls, radius, cavity, 0.0, scene.skin, cand[s]);
      if (!node_reach.empty())
        find_mesh_candidates(*sf.mesh, sf.mesh->vertices, film, node_reach, cavity, 0.0, scene.skin, node_cand[s]);
    }
  }
  // Balls sleep when the film is the only surface (wake); after a build each is looked at.
  if (surfaces.size() == 1 && surfaces[0].film) wake.assign(balls.size(), 0.0);
  cavity_at_build = cavity;
  if (&film != &film_at_build) film_at_build = film;
}

// The candidate lists of STL walls hold while no ball moved more than skin/2 relative to the
// cavity; those of the film while no ball and no film node moved more than skin/2.
bool SurfaceContacts::need_rebuild(const Scene& scene, const std::vector<Vec3>& balls, const std::vector<Vec3>& x_at_build,
                                   const std::vector<Vec3>& film, const Vec3& cavity, double tilt) const {
  if (surfaces.empty()) return false;
  const double limit2 = 0.25 * scene.skin * scene.skin;
  // The candidates of STL walls are found for the cavity's translation; a slope moves a point at
  // most |shear| l (l: half the cavity's axial extent) further, which is taken off the allowance.
  const double limit_walls2 = std::pow(std::max(0.0, 0.5 * scene.skin - tilt), 2);
  if (!scene.mesh_walls.empty()) {
    const Vec3 dc = cavity - cavity_at_build;
    for (std::size_t i = 0; i < balls.size(); ++i)
      if ((balls[i] - x_at_build[i] - dc).squaredNorm() > limit_walls2) return true;
  }
  const Vec3 dc = cavity - cavity_at_build;
  for (std::size_t k = 0; k < film.size(); ++k) {
    if ((film[k] - film_at_build[k]).squaredNorm() > limit2) return true;
    if (!node_reach.empty() && (film[k] - film_at_build[k] - dc).squaredNorm() > limit_walls2) return true;
  }
  return false;
}

namespace {
using Surface = SurfaceContacts::Surface;

// Ball p against the triangulated surfaces: adds to its force F, torque T and dissipation diss,
// the STL walls' share to F_cavity / T_cavity (force on the ball, torque on the cavity) and load
// (its moments), and raises excess to its overlaps' (over the guard's limit).
template <bool Tangential, bool Rolling, bool Energy>
void mesh_contacts(const TriangleStage& st, std::size_t p, Vec3& F, Vec3& T, Vec3& diss, Vec3& F_cavity, Vec3& T_cavity, Vec3& load,
                   double& excess);
double euler_forces(const TriangleStage& st, std::size_t p, const std::vector<EulerTerm>& terms, Vec3& F, Vec3& F_cavity, Vec3& T_cavity,
                    Vec3& load);
void surface_reaction(const TriangleStage& st, const Found& fd, const Surface& sf, const Vec3& Fc, FilmLoad& fl, Vec3& F_cavity,
                      Vec3& T_cavity, Vec3& load);
double surface_point(const Film& film, const Found& fd, const Surface& sf, const Vec3& c_vel, const Vec3& c_half, double inv_m,
                     Vec3& v_end_out, Vec3& v_half_out);

// Each ball's contacts add to its force after its walls' (the same order for any thread count); the
// STL walls' share enters the cavity's load and work as the analytic walls' does.
// Asleep (SurfaceContacts::asleep): with the film the only surface, surfaces.travel bounds from above how far
// the balls and the film's nodes moved in all (the largest ball step plus the largest node step,
// summed over the steps, rounded up: kick_drift). A ball that touched nothing, with its candidates
// all `gap` beyond its reach when looked at (mesh_contacts), cannot touch one before surfaces.travel
// has grown by gap: it is not looked at before surfaces.travel reaches surfaces.wake[p] (0 after a
// build, when every ball is).
template <bool Tangential, bool Rolling, bool Energy>
void triangle_contacts_impl(const TriangleStage& st) {
  const std::size_t n = st.balls.size();
  const double dt = st.ctx.dt;
  const WallMotion rigid = st.frame.rigid();
  auto one = [&](std::size_t p) {
    double excess = -HUGE_VAL;
    if (st.surfaces.asleep(p)) return excess;  // nothing touched now or at the last step: nothing to add
    const Vec3 c_step = st.frame.structure.tilt ? st.frame.at(st.balls.x[p]).step : rigid.step;
    Vec3 F = st.balls.f[p], T = st.balls.t[p], diss(0, 0, 0), F_cavity(0, 0, 0), T_cavity(0, 0, 0), load(0, 0, 0);
    mesh_contacts<Tangential, Rolling, Energy>(st, p, F, T, diss, F_cavity, T_cavity, load, excess);
    if (st.frame.structure.couple) st.cavity_load[p] += load;
    st.balls.f[p] = F;
    st.balls.t[p] = T;
    st.balls.tally.wall_impulse[p] -= dt * F_cavity;
    st.balls.tally.wall_ang_impulse[p] += dt * T_cavity;
    if constexpr (Energy) {
      st.balls.tally.work_cavity[p] += 0.5 * (F_cavity + st.surfaces.force_prev[p]).dot(c_step);
      st.surfaces.force_prev[p] = F_cavity;
      st.balls.tally.diss_normal[p] += diss.x();
      st.balls.tally.diss_tangential[p] += diss.y();
      st.balls.tally.diss_rolling[p] += diss.z();
    }
    return excess;
  };
  st.guard.overlap_excess = parallel_fold(n, st.guard.overlap_excess, one, [](double a, double b) { return std::max(a, b); });
}

template <bool Tangential, bool Rolling, bool Energy>
void mesh_contacts(const TriangleStage& st, std::size_t p, Vec3& F, Vec3& T, Vec3& diss, Vec3& F_cavity, Vec3& T_cavity, Vec3& load,
                   double& excess) {
  constexpr std::size_t K = kMaxMeshContacts;
  const double dt = st.ctx.dt;
  const double r = st.balls.radius[p];
  const WallMotion wm = st.frame.at(st.balls.x[p]);
  const Vec3 &c_pos = wm.pos, &c_vel = wm.vel, &c_half = wm.half;

  // 1. Contacts now: closest points within reach, one per feature, with their normal and overlap.
  Found found[K];
  auto view = [&](std::uint32_t s) {
    const Surface& sf = st.surfaces.surfaces[s];
    return PointView{sf.film ? st.balls.x[p] : Vec3(st.balls.x[p] - c_pos), sf.film ? &st.film.x : &sf.mesh->vertices, r + sf.reach,
                     sf.film ? static_cast<double>(st.surfaces.side[p]) : -1.0, sf.film && st.scene.bag->self_radius > 0};
  };
  auto crossed = [&](std::uint32_t s, double overlap, double reach, bool own_side) {
    if (own_side) return;
#pragma omp critical(bagdem_crossed)
    if (st.guard.crossed == static_cast<std::size_t>(-1) || overlap - reach > st.guard.crossed_depth) {
      st.guard.crossed = p;
      st.guard.crossed_depth = overlap - reach;
      st.guard.crossed_surface = s;
    }
  };
  auto overflow = [&] {
#pragma omp critical(bagdem_crossed)
    st.guard.mesh_overflow = p;
  };
  double gap = 0;
  thread_local std::vector<EulerTerm> terms;
  const std::size_t nf = find_features<K>(st.surfaces.surfaces, st.surfaces.cand, p, view, crossed, overflow, found, terms,
                                          st.surfaces.wake.empty() ? nullptr : &gap);
  st.surfaces.elastic[p] = 0;
  if (st.scene.bag) st.surfaces.film_push[p].clear();

  // 2. Histories (match_slots). A ball that touches no surface now and touched none at the last
  // step has nothing more to do (most of a bag's balls, at any step); it sleeps while it cannot.
  MeshSlot* slot = &st.surfaces.slots[p * K];
  const std::size_t n_prev = st.surfaces.slot_count[p];
  if (nf == 0 && n_prev == 0) {
    if (!st.surfaces.wake.empty()) st.surfaces.wake[p] = st.surfaces.travel + gap;
    return;
  }
  bool taken[K] = {};
  MeshSlot prev[K];
  ContactHistory prev_hist[K];
  carry_slots(slot, st.surfaces.slot_hist, p * K, n_prev, found, nf, prev, prev_hist, taken);
  // Slots closed for good: tally what they still held.
  if constexpr (Energy) {
    for (std::size_t k = 0; k < n_prev; ++k) {
      if (taken[k]) continue;
      const Vec3 v_c = st.balls.v[p] - prev[k].surface_velocity - r * st.balls.w[p].cross(prev[k].n);
      diss += closing_tally<Tangential, Rolling>(prev[k].n, v_c, st.balls.w[p], dt, prev_hist[k].damping_prev,
                                                 Tangential ? &prev_hist[k].tangential : nullptr,
                                                 Rolling ? &prev_hist[k].rolling : nullptr);
    }
  }

  // 3. The contact law, as for a wall, with the surface point's velocity and effective mass: its
  // damping and friction (the elastic force is the Euler sum's, step 4), on the overlap whose
  // stiffness is the Euler sum's along the contact's normal (law_overlaps).
  const PairLawTable& laws = st.scene.laws;
  double law_overlap[K];
  law_overlaps(terms, found, nf, [&](std::uint32_t s) -> const PairLaw& { return laws(st.balls.material[p], st.surfaces.surfaces[s].material); },
               law_overlap);
  for (std::size_t f = 0; f < nf; ++f) {
    const Found& fd = found[f];
    const Surface& sf = st.surfaces.surfaces[fd.surface];
    const std::size_t at = p * K + f;
    MeshSlot& s = renew_slot(slot, st.surfaces.slot_hist, at, f, fd, prev, prev_hist);
    ContactGeometry g;
    g.n = fd.n;
    g.overlap = law_overlap[f];
    g.R_eff = r;
    g.arm_i = r - 0.5 * fd.overlap;
    g.arm_j = 0;
    Vec3 vs_end, vs_half;
    const double inv_m = surface_point(st.film, fd, sf, c_vel, c_half, st.balls.inv_mass[p], vs_end, vs_half);
    g.m_eff = 1.0 / inv_m;
    s.surface_velocity = vs_half;
    st.balls.motion_against_surface<Tangential || Rolling>(p, vs_end, vs_half, g);
    [[maybe_unused]] double no_tally = 0;
    double elastic = 0;
    Vec3 Fc = surface_contact<Tangential, Rolling, Energy>(
        g, laws(st.balls.material[p], sf.material), dt, Energy ? st.surfaces.slot_hist.damping_prev[at] : no_tally,
        Tangential ? &st.surfaces.slot_hist.tangential[at] : nullptr, Rolling ? &st.surfaces.slot_hist.rolling[at] : nullptr, T, diss, &elastic);
    Fc -= elastic * g.n;
    F += Fc;
    excess = std::max(excess, fd.overlap - st.scene.max_overlap_fraction * r);
    surface_reaction(st, fd, sf, Fc, st.surfaces.film_load[p * K + f], F_cavity, T_cavity, load);
  }
  st.surfaces.slot_count[p] = static_cast<std::uint8_t>(nf);

  // 4. The elastic force and energy: the Euler sum's terms.
  st.surfaces.elastic[p] = euler_forces(st, p, terms, F, F_cavity, T_cavity, load);
}

// The reaction of contact fd's force Fc on the ball (its damping and friction) on the surface:
// on the film, the loads of its hits' points on their triangles' nodes (film_load, by their shares
// of a patch); on an STL wall, the cavity's force, torque and load.
void surface_reaction(const TriangleStage& st, const Found& fd, const Surface& sf, const Vec3& Fc, FilmLoad& fl, Vec3& F_cavity,
                      Vec3& T_cavity, Vec3& load) {
  Vec3 parts[kPatchMembers] = {Fc};
  for (std::size_t i = 0; i < fd.members && fd.members > 1; ++i) parts[i] = fd.member[i].share * Fc;
  if (sf.film) {
    fl.count = fd.members;
    for (std::size_t i = 0; i < fd.members; ++i) {
      fl.force[i] = -parts[i];
      fl.weights[i] = fd.members > 1 ? fd.member[i].weights : fd.hit.hit.weights;
      fl.triangle[i] = fd.members > 1 ? fd.member[i].triangle : fd.hit.triangle;
    }
  } else {
    F_cavity += Fc;
    for (std::size_t i = 0; i < fd.members; ++i) {
      const Vec3& point = fd.members > 1 ? fd.member[i].point : fd.hit.hit.point;
      T_cavity -= (point - st.scene.cavity_reference).cross(parts[i]);
      if (st.frame.structure.couple) load += st.frame.load_moments(point, -parts[i]);
    }
  }
}

// The elastic force and energy of ball p on the triangulated surfaces: the Euler sum's terms
// (euler_terms), each the law's force along its normal, its reaction on the feature's nodes by the
// closest point's weights (on the film: film_push; on an STL wall: the cavity's force, torque and
// load). Returns the energy (unit: J).
double euler_forces(const TriangleStage& st, std::size_t p, const std::vector<EulerTerm>& terms, Vec3& F, Vec3& F_cavity, Vec3& T_cavity,
                    Vec3& load) {
  double U = 0;
  for (const EulerTerm& e : terms) {
    const Surface& sf = st.surfaces.surfaces[e.surface];
    const auto [u, Fe] = euler_load(e, st.scene.laws(st.balls.material[p], sf.material), st.balls.radius[p]);
    U += u;
    F += Fe;
    if (sf.film) {
      for (int a = 0; a < 3; ++a)
        if (e.weights[a] != 0) st.surfaces.film_push[p].push_back({e.node[a], -e.weights[a] * Fe});
    } else {
      F_cavity += Fe;
      T_cavity -= (e.point - st.scene.cavity_reference).cross(Fe);
      if (st.frame.structure.couple) load += st.frame.load_moments(e.point, -Fe);
    }
  }
  return U;
}

// The surface point of contact fd (one hit, or a patch of hits): its velocities at the end of the
// step and over it (into v_end_out, v_half_out), and inv_m (the ball's inverse mass) plus its
// inverse effective mass, returned: on the film the barycentric mean of the triangle's nodes,
// 1/m_s = sum w_k^2 / m_k (a patch: its hits' mean by their shares); on a rigid surface the
// cavity's motion at infinite mass.
double surface_point(const Film& film, const Found& fd, const Surface& sf, const Vec3& c_vel, const Vec3& c_half, double inv_m,
                     Vec3& v_end_out, Vec3& v_half_out) {
  // The film point's velocities and inverse mass (a rigid surface: the cavity's, at infinity).
  Vec3 v_end[kPatchMembers], v_half[kPatchMembers];
  double inv_m_s[kPatchMembers] = {};
  for (std::size_t i = 0; i < fd.members; ++i) {
    v_end[i] = c_vel, v_half[i] = c_half;
    if (!sf.film) continue;
    const auto& tri = sf.mesh->triangles[fd.members > 1 ? fd.member[i].triangle : fd.hit.triangle];
    const Vec3& w = fd.members > 1 ? fd.member[i].weights : fd.hit.hit.weights;
    v_end[i] = w[0] * film.v_pred[tri[0]] + w[1] * film.v_pred[tri[1]] + w[2] * film.v_pred[tri[2]];
    v_half[i] = w[0] * film.v[tri[0]] + w[1] * film.v[tri[1]] + w[2] * film.v[tri[2]];
    inv_m_s[i] = w[0] * w[0] * film.inv_mass[tri[0]] + w[1] * w[1] * film.inv_mass[tri[1]] +
                 w[2] * w[2] * film.inv_mass[tri[2]];
  }
  // A patch's: the point of its hits' mean by their shares.
  Vec3 vs_end = Vec3::Zero(), vs_half = Vec3::Zero();
  for (std::size_t i = 0; i < fd.members; ++i) {
    const double a = fd.members > 1 ? fd.member[i].share : 1.0;
    vs_end += a * v_end[i], vs_half += a * v_half[i], inv_m += a * inv_m_s[i];
  }
  v_end_out = vs_end, v_half_out = vs_half;
  return inv_m;
}


}  // namespace

void triangle_stage(const TriangleStage& st) {
  if (st.surfaces.surfaces.empty()) return;
  const ModelSwitches& m = st.scene.models;
  with_flags([&st]<bool T, bool R, bool E>() { triangle_contacts_impl<T, R, E>(st); }, m.tangential, m.rolling, m.energy);
}

// Film nodes against the STL walls: the film-wall law of film.cpp (R* = the film's contact
// radius, m* = the node's mass, reach = half the thickness) on the sphere-triangle contact.
template <bool Tangential, bool Energy>
void film_node_stl_contacts(const FilmStage& st, std::size_t k, Vec3& F_wall, Vec3& L, Vec3& load, double& dn, double& dtg,
                            double& deepest) {
  constexpr std::size_t K = kMaxMeshContacts;
  const Scene& scene = st.scene;
  const Film& film = st.film;
  SurfaceContacts& mesh = st.surfaces;
  const Bag& bag = *scene.bag;
  const double dt = st.ctx.dt;
  const WallMotion wm = st.frame.at(film.x[k]);
  const Vec3 &c_pos = wm.pos, &c_vel = wm.vel, &c_half = wm.half;
  const double reach = mesh.node_reach[k];
  const Vec3 x = film.x[k] - c_pos;
  Found found[K];
  auto view = [&](std::uint32_t s) {
    const SurfaceContacts::Surface& sf = mesh.surfaces[s];
    return PointView{x, &sf.mesh->vertices, reach, -1.0};  // STL walls only: the film has no candidate list
  };
  auto deepest_of = [&](std::uint32_t, double overlap, double, bool) { deepest = std::min(deepest, reach - overlap); };
  thread_local std::vector<EulerTerm> terms;
  const std::size_t nf = find_features<K>(mesh.surfaces, mesh.node_cand, k, view, deepest_of, [] {}, found, terms);
  // The deepest hit, for the walls' stop (film.cpp, film_wall_stops).
  st.film.stl_gap[k] = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < nf; ++f)
    if (reach - found[f].overlap < st.film.stl_gap[k]) st.film.stl_gap[k] = reach - found[f].overlap, st.film.stl_normal[k] = found[f].n;
  mesh.node_elastic[k] = 0;
  MeshSlot* slot = &mesh.node_slots[k * K];
  const std::size_t n_prev = mesh.node_slot_count[k];
  if (nf == 0 && n_prev == 0) return;  // no STL wall touched, now or at the last step
  bool taken[K] = {};
  MeshSlot prev[K];
  ContactHistory prev_hist[K];
  carry_slots(slot, mesh.node_slot_hist, k * K, n_prev, found, nf, prev, prev_hist, taken);
  double law_overlap[K];
  law_overlaps(terms, found, nf,
               [&](std::uint32_t s) -> const PairLaw& { return scene.laws(bag.material, mesh.surfaces[s].material); }, law_overlap);
  if constexpr (Energy) {
    for (std::size_t j = 0; j < n_prev; ++j) {
      if (taken[j]) continue;
      const Vec3 d = closing_tally<Tangential, false>(prev[j].n, film.v[k] - prev[j].surface_velocity, Vec3::Zero(), dt,
                                                      prev_hist[j].damping_prev, Tangential ? &prev_hist[j].tangential : nullptr,
                                                      nullptr);
      dn += d.x(), dtg += d.y();
    }
  }
  for (std::size_t f = 0; f < nf; ++f) {
    const Found& fd = found[f];
    const std::size_t at = k * K + f;
    MeshSlot& s = renew_slot(slot, mesh.node_slot_hist, at, f, fd, prev, prev_hist);
    s.surface_velocity = c_half;
    // The law gives damping and friction; the elastic force is the Euler sum's (below).
    double elastic = 0;
    Vec3 Fc = film_node_contact<Tangential, Energy>(st, k, fd.n, law_overlap[f], scene.laws(bag.material, mesh.surfaces[fd.surface].material),
                                               c_vel, c_half, mesh.node_slot_hist, at, dn, dtg, &elastic);
    Fc -= elastic * fd.n;
    Vec3 parts[kPatchMembers] = {Fc};
    for (std::size_t i = 0; i < fd.members && fd.members > 1; ++i) parts[i] = fd.member[i].share * Fc;
    F_wall += Fc;
    for (std::size_t i = 0; i < fd.members; ++i) {
      const Vec3& point = fd.members > 1 ? fd.member[i].point : fd.hit.hit.point;
      L -= dt * (point - scene.cavity_reference).cross(parts[i]);
      if (st.frame.structure.couple) load += st.frame.load_moments(point, -parts[i]);
    }
  }
  mesh.node_slot_count[k] = static_cast<std::uint8_t>(nf);
  double U = 0;
  for (const EulerTerm& e : terms) {
    const auto [u, Fe] = euler_load(e, scene.laws(bag.material, mesh.surfaces[e.surface].material), bag.contact_radius);
    U += u;
    F_wall += Fe;
    L -= dt * (e.point - scene.cavity_reference).cross(Fe);
    if (st.frame.structure.couple) load += st.frame.load_moments(e.point, -Fe);
  }
  mesh.node_elastic[k] = U;
}

template void film_node_stl_contacts<false, false>(const FilmStage&, std::size_t, Vec3&, Vec3&, Vec3&, double&, double&, double&);
template void film_node_stl_contacts<false, true>(const FilmStage&, std::size_t, Vec3&, Vec3&, Vec3&, double&, double&, double&);
template void film_node_stl_contacts<true, false>(const FilmStage&, std::size_t, Vec3&, Vec3&, Vec3&, double&, double&, double&);
template void film_node_stl_contacts<true, true>(const FilmStage&, std::size_t, Vec3&, Vec3&, Vec3&, double&, double&, double&);

std::size_t Stepper::mesh_contact_count() const {
  std::size_t c = 0;
  for (std::uint8_t k : mesh_.slot_count) c += k;
  return c;
}

std::vector<std::size_t> Stepper::balls_outside_bag() const {
  std::vector<std::size_t> out;
  if (!scene_.bag) return out;
  const Bag& bag = *scene_.bag;
  for (std::size_t i = bag.ball_first; i < bag.ball_first + bag.balls; ++i)
    if (winding_number(bag.rest, film_.x, p_.x[i]) < 0.5) out.push_back(p_.order[i]);
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace bagdem
