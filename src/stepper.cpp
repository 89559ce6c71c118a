// The stepper: the stage list of stepper.hpp, one plain loop per stage.
#include "bagdem/stepper.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "bagdem/contact/hertz.hpp"
#include "bagdem/error.hpp"

namespace bagdem {

namespace {
// Parallel loops below this size run on one thread (fork/join costs more than the work).
constexpr std::size_t kParallelMin = 512;

// Calls fn.template operator()<b0, b1, ...>() with runtime flags turned into template arguments,
// so each configuration of the kernel is compiled without branches on the flags.
template <bool... Done, class Fn>
void with_flags(Fn&& fn) {
  fn.template operator()<Done...>();
}
template <bool... Done, class Fn, class... Rest>
void with_flags(Fn&& fn, bool first, Rest... rest) {
  if (first) with_flags<Done..., true>(fn, rest...);
  else with_flags<Done..., false>(fn, rest...);
}

// What a contact still held when it opened, as (normal, tangential, rolling) dissipation: the last
// half step of its forces' trapezoidal work (hertz.hpp, mindlin.hpp, rolling.hpp) and the energy
// its springs still stored. Both vanish with the overlap as dt -> 0; tallying them keeps the
// energy budget exact. n: normal from j to i; v_c, w_rel: half-step relative motion.
template <bool Tangential, bool Rolling>
Vec3 closing_tally(const Vec3& n, const Vec3& v_c, const Vec3& w_rel, double dt, double damping_prev,
                   const TangentialHistory* th, const RollingHistory* rh) {
  Vec3 d(-0.5 * damping_prev * v_c.dot(n) * dt, 0, 0);
  if constexpr (Tangential) d.y() = mindlin_energy(*th) - 0.5 * th->total.dot(v_c - v_c.dot(n) * n) * dt;
  if constexpr (Rolling) d.z() = rolling_energy(*rh) - 0.5 * rh->torque.dot(w_rel - w_rel.dot(n) * n) * dt;
  return d;
}
}  // namespace

Simulation::Simulation(const Scene& scene) : scene_(scene), broad_(make_broad_phase(scene.broad_phase)) {
  const std::size_t n = scene.particles.size();
  p_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const ParticleInit& q = scene.particles[i];
    const double rho = scene.materials[static_cast<std::size_t>(q.material)].density;
    const double m = rho * 4.0 / 3.0 * M_PI * q.radius * q.radius * q.radius;
    p_.x[i] = q.x;
    p_.v[i] = q.v;
    p_.w[i] = q.w;
    p_.radius[i] = q.radius;
    p_.mass[i] = m;
    p_.inv_mass[i] = 1.0 / m;
    p_.inv_inertia[i] = 1.0 / (0.4 * m * q.radius * q.radius);
    p_.material[i] = q.material;
  }
  p_.v_pred = p_.v;
  p_.w_pred = p_.w;
  tally_.resize(n);
  const std::size_t nw = scene.walls.size();
  if (scene.models.tangential) wall_tan_.assign(n * nw, {});
  if (scene.models.rolling) wall_roll_.assign(n * nw, {});
  if (scene.models.energy) wall_damping_prev_.assign(n * nw, 0.0);
  wall_touch_.assign(n, 0);  // 32 bits: a cavity has at most 32 walls (checked when loading)
  cavity_ = cavity_prev_ = cavity_at(0.0);
  update_neighbours(true);
  for (std::size_t i = 0; i < n; ++i) start_sums(i);
  dt_step_ = 0.0;  // set-up force evaluation: no history increment, no dissipation
  pair_contacts();
  gather_walls();
  potential0_ = potential_energy();
  const EnergySample e0 = energy();
  kinetic_elastic0_ = e0.kinetic + e0.elastic;
}

CavityState Simulation::cavity_at(double t) const {
  if (t < scene_.settle) return {scene_.motion->at(0.0).position, Vec3::Zero()};
  return scene_.motion->at(t - scene_.settle);
}

void Simulation::step() {
  dt_step_ = scene_.dt;
  kick_drift();
  move_cavity();
  update_neighbours(false);
  pair_contacts();
  gather_walls();
  kick();
  ++step_;
  guards();
}

// ---- 1. kick_drift ------------------------------------------------------------------------------
// Also predicts the end-of-step velocities the contact law uses, v(n+1/2) + dt/2 F(n)/m: with the
// half-step velocity alone (as LAMMPS and LIGGGHTS do) the damping force lags by dt/2, a first-order
// error in the restitution (-26% at e = 0.01 with 40 steps per contact); the prediction makes it
// second order. Also finds whether any particle moved more than skin/2 since the last build.
void Simulation::kick_drift() {
  const double dt = scene_.dt, h = 0.5 * dt;
  const std::size_t n = p_.size();
  const bool rot = scene_.models.rotation;
  const double limit2 = 0.25 * scene_.skin * scene_.skin;
  bool moved = false;
#pragma omp parallel for schedule(static) reduction(|| : moved) if (n > kParallelMin)
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 dv = h * p_.inv_mass[i] * p_.f[i];
    p_.v[i] += dv;
    p_.x[i] += dt * p_.v[i];
    p_.v_pred[i] = p_.v[i] + dv;
    if (rot) {
      const Vec3 dw = h * p_.inv_inertia[i] * p_.t[i];
      p_.w[i] += dw;
      p_.w_pred[i] = p_.w[i] + dw;
    }
    moved = moved || (p_.x[i] - x_at_build_[i]).squaredNorm() > limit2;
    start_sums(i);
  }
  needs_rebuild_ = moved;
}

// Per-particle sums of the new step start from gravity and zero torque and dissipation.
void Simulation::start_sums(std::size_t i) {
  p_.f[i] = scene_.models.gravity ? Vec3(p_.mass[i] * scene_.gravity) : Vec3::Zero();
  p_.t[i].setZero();
  if (scene_.models.energy) tally_.step_dissipation[i].setZero();
}

// ---- 2. move_cavity -----------------------------------------------------------------------------
void Simulation::move_cavity() {
  cavity_prev_ = cavity_;
  const double t = static_cast<double>(step_ + 1) * scene_.dt;
  cavity_ = cavity_at(t);
  ++cavity_sums_.steps;
  cavity_sums_.time += t;
  cavity_sums_.position += cavity_.position;
  cavity_sums_.velocity += cavity_.velocity;
}

// ---- 3. neighbours ------------------------------------------------------------------------------
void Simulation::update_neighbours(bool force_rebuild) {
  const std::size_t n = p_.size();
  if (!force_rebuild && !needs_rebuild_) return;
  ++builds_;
  x_at_build_ = p_.x;
  CandidatePairs fresh;
  broad_->find(p_.x, p_.radius, scene_.skin, fresh);

  // Carry contact histories over: merge the old and new partner lists of each i (both sorted).
  const bool tan = scene_.models.tangential, roll = scene_.models.rolling, en = scene_.models.energy;
  std::vector<TangentialHistory> tan_new(tan ? fresh.size() : 0);
  std::vector<RollingHistory> roll_new(roll ? fresh.size() : 0);
  std::vector<double> damp_new(en ? fresh.size() : 0, 0.0);
  if ((tan || roll || en) && !ps_.pairs.partner.empty()) {
#pragma omp parallel for schedule(static) if (n > kParallelMin)
    for (std::size_t i = 0; i < n; ++i) {
      std::uint32_t a = ps_.pairs.begin[i], b = fresh.begin[i];
      const std::uint32_t a_end = ps_.pairs.begin[i + 1], b_end = fresh.begin[i + 1];
      while (a < a_end && b < b_end) {
        if (ps_.pairs.partner[a] < fresh.partner[b]) { ++a; continue; }
        if (ps_.pairs.partner[a] > fresh.partner[b]) { ++b; continue; }
        if (tan) tan_new[b] = ps_.tangential[a];
        if (roll) roll_new[b] = ps_.rolling[a];
        if (en) damp_new[b] = ps_.damping_prev[a];
        ++a, ++b;
      }
    }
  }
  install_pairs(std::move(fresh), std::move(tan_new), std::move(roll_new), std::move(damp_new));
}

// Installs a pair list with its histories and derives the per-pair buffers and the gather CSR.
void Simulation::install_pairs(CandidatePairs pairs, std::vector<TangentialHistory> tangential,
                               std::vector<RollingHistory> rolling, std::vector<double> damping_prev) {
  const std::size_t n = p_.size();
  ps_.pairs = std::move(pairs);
  ps_.tangential = std::move(tangential);
  ps_.rolling = std::move(rolling);
  ps_.damping_prev = std::move(damping_prev);
  const std::size_t np = ps_.pairs.size();
  ps_.out.assign(np, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  // A pair whose history was carried over may be touching; a fresh pair is not (all-zero history).
  ps_.touching.assign(np, 0);
  for (std::size_t k = 0; k < np; ++k) {
    const bool t = !ps_.tangential.empty() && ps_.tangential[k].stiffness != 0;
    const bool r = !ps_.rolling.empty() && ps_.rolling[k].stiffness != 0;
    const bool d = !ps_.damping_prev.empty() && ps_.damping_prev[k] != 0;
    ps_.touching[k] = t || r || d;
  }
  ps_.first.resize(np);
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t k = ps_.pairs.begin[i]; k < ps_.pairs.begin[i + 1]; ++k)
      ps_.first[k] = static_cast<std::uint32_t>(i);

  // Gather CSR, each particle's entries sorted by partner: first the pairs where it is j (partner
  // i < p, visited in ascending i), then those where it is i (partner j > p, ascending).
  ps_.gather_begin.assign(n + 1, 0);
  for (std::size_t k = 0; k < np; ++k) {
    ++ps_.gather_begin[ps_.first[k] + 1];
    ++ps_.gather_begin[ps_.pairs.partner[k] + 1];
  }
  for (std::size_t i = 0; i < n; ++i) ps_.gather_begin[i + 1] += ps_.gather_begin[i];
  ps_.gather.resize(2 * np);
  std::vector<std::uint32_t> fill(ps_.gather_begin.begin(), ps_.gather_begin.end() - 1);
  for (std::size_t k = 0; k < np; ++k) ps_.gather[fill[ps_.pairs.partner[k]]++] = static_cast<std::uint32_t>(2 * k + 1);
  for (std::size_t k = 0; k < np; ++k) ps_.gather[fill[ps_.first[k]]++] = static_cast<std::uint32_t>(2 * k);
}

// ---- 4. pair_contacts ---------------------------------------------------------------------------
// Two ways to sum pair forces onto particles, bitwise identical by construction:
//  scatter (one thread, or few pairs): the pair loop adds each force to f[i] and f[j] at once.
//    Pairs run in (i, j) order, so particle p receives its pairs (k, p), k < p ascending, then
//    (p, j) ascending: partner order.
//  gather (several threads): each pair writes its record, then each particle sums its records in
//    partner order (gather_walls). Same operands, same order, same result.
void Simulation::pair_contacts() {
  scatter_ = omp_get_max_threads() == 1 || ps_.pairs.size() <= kParallelMin;
  // The contact-law configuration is chosen once here, never inside the loop.
  with_flags([this]<bool T, bool R, bool E, bool S>() { pair_contacts_impl<T, R, E, S>(); },
             scene_.models.tangential, scene_.models.rolling, scene_.models.energy, scatter_);
}

template <bool Tangential, bool Rolling, bool Energy, bool Scatter>
void Simulation::pair_contacts_impl() {
  const std::size_t np = ps_.pairs.size();
  const double dt = dt_step_;
  const PairLawTable& laws = scene_.laws;
  const double frac = scene_.max_overlap_fraction;
  double excess = -1e300;
#pragma omp parallel for schedule(static) reduction(max : excess) if (!Scatter)
  for (std::size_t k = 0; k < np; ++k) {
    const std::uint32_t i = ps_.first[k], j = ps_.pairs.partner[k];
    PairState::Output& out = ps_.out[k];
    ContactGeometry g;
    if (!sphere_sphere(p_.x[i], p_.x[j], p_.radius[i], p_.radius[j], g)) {
      if constexpr (!Scatter) {
        out.force.setZero();
        if constexpr (Tangential || Rolling) {
          out.torque_i.setZero();
          out.torque_j.setZero();
        }
        if constexpr (Energy) out.dissipated.setZero();
      }
      // A contact that just opened: tally what it still held, clear its history (untouched pairs
      // cost no history access).
      if (ps_.touching[k]) {
        ps_.touching[k] = 0;
        if constexpr (Energy) {
          const Vec3 n = (p_.x[i] - p_.x[j]).normalized();
          const Vec3 v_c = p_.v[i] - p_.v[j] - (p_.radius[i] * p_.w[i] + p_.radius[j] * p_.w[j]).cross(n);
          const Vec3 d = closing_tally<Tangential, Rolling>(n, v_c, p_.w[i] - p_.w[j], dt, ps_.damping_prev[k],
                                                            Tangential ? &ps_.tangential[k] : nullptr,
                                                            Rolling ? &ps_.rolling[k] : nullptr);
          if constexpr (Scatter) {
            tally_.step_dissipation[i] += 0.5 * d;
            tally_.step_dissipation[j] += 0.5 * d;
          } else {
            out.dissipated = d;
          }
          ps_.damping_prev[k] = 0.0;
        }
        if constexpr (Tangential) ps_.tangential[k] = {};
        if constexpr (Rolling) ps_.rolling[k] = {};
      }
      continue;
    }
    ps_.touching[k] = 1;
    excess = std::max(excess, g.overlap - frac * std::min(p_.radius[i], p_.radius[j]));
    g.m_eff = 1.0 / (p_.inv_mass[i] + p_.inv_mass[j]);
    if constexpr (Tangential || Rolling) {
      g.v_rel = contact_velocity(p_.v_pred[i], p_.v_pred[j], p_.w_pred[i], p_.w_pred[j], g);
      g.v_half = contact_velocity(p_.v[i], p_.v[j], p_.w[i], p_.w[j], g);
      g.w_half = p_.w[i] - p_.w[j];
    } else {
      g.v_rel = p_.v_pred[i] - p_.v_pred[j];
      g.v_half = p_.v[i] - p_.v[j];
    }
    const PairLaw& law = laws(p_.material[i], p_.material[j]);
    const NormalResult nr = hertz_normal(g, law);
    Vec3 F = nr.force * g.n;
    [[maybe_unused]] Vec3 diss(0, 0, 0);
    if constexpr (Energy) diss.x() = normal_dissipation(nr, g.v_half.dot(g.n), dt, ps_.damping_prev[k]);
    if constexpr (Tangential || Rolling) {
      Vec3 Ti(0, 0, 0), Tj(0, 0, 0);
      if constexpr (Tangential) {
        const TangentialResult tr = mindlin_tangential(g, law, nr, dt, ps_.tangential[k]);
        F += tr.force;
        const Vec3 nxF = g.n.cross(tr.force);
        Ti = -g.arm_i * nxF;
        Tj = -g.arm_j * nxF;
        if constexpr (Energy) diss.y() = tr.dissipated;
      }
      if constexpr (Rolling) {
        const RollingResult rr = epsd_rolling(g, law, nr.stiffness, nr.force, dt, ps_.rolling[k]);
        Ti += rr.torque;
        Tj -= rr.torque;
        if constexpr (Energy) diss.z() = rr.dissipated;
      }
      if constexpr (Scatter) {
        p_.t[i] += Ti;
        p_.t[j] += Tj;
      } else {
        out.torque_i = Ti;
        out.torque_j = Tj;
      }
    }
    if constexpr (Scatter) {
      p_.f[i] += F;
      p_.f[j] -= F;
      if constexpr (Energy) {
        tally_.step_dissipation[i] += 0.5 * diss;
        tally_.step_dissipation[j] += 0.5 * diss;
      }
    } else {
      out.force = F;
      if constexpr (Energy) out.dissipated = diss;
    }
  }
  overlap_excess_ = excess;
}

// ---- 5. gather_walls ----------------------------------------------------------------------------
void Simulation::gather_walls() {
  with_flags([this]<bool T, bool R, bool E, bool G>() { gather_walls_impl<T, R, E, G>(); },
             scene_.models.tangential, scene_.models.rolling, scene_.models.energy, !scatter_);
}

template <bool Tangential, bool Rolling, bool Energy, bool Gather>
void Simulation::gather_walls_impl() {
  const std::size_t n = p_.size();
  const std::size_t nw = scene_.walls.size();
  const double dt = dt_step_;
  const Vec3 c_pos = cavity_.position, c_vel = cavity_.velocity;
  const Vec3 c_step = cavity_.position - cavity_prev_.position;
  const Vec3 c_half = dt > 0 ? Vec3(c_step / dt) : c_vel;  // mean cavity velocity over the step
  const Vec3 lo = scene_.cavity_lo, hi = scene_.cavity_hi;
  const PairLawTable& laws = scene_.laws;
  const double frac = scene_.max_overlap_fraction;
  double excess = overlap_excess_;
  double min_dist = 1e300;
#pragma omp parallel for schedule(static) reduction(max : excess) reduction(min : min_dist) if (n > kParallelMin)
  for (std::size_t p = 0; p < n; ++p) {
    // Starts from gravity (kick_drift), plus the pairs when they were scattered.
    Vec3 F = p_.f[p];
    Vec3 T = p_.t[p];
    [[maybe_unused]] Vec3 diss(0, 0, 0);
    if constexpr (Energy) diss = tally_.step_dissipation[p];
    for (std::uint32_t e = Gather ? ps_.gather_begin[p] : 0; e < (Gather ? ps_.gather_begin[p + 1] : 0); ++e) {
      const std::uint32_t entry = ps_.gather[e];
      const PairState::Output& out = ps_.out[entry >> 1];
      if (entry & 1u) {
        F -= out.force;
        if constexpr (Tangential || Rolling) T += out.torque_j;
      } else {
        F += out.force;
        if constexpr (Tangential || Rolling) T += out.torque_i;
      }
      if constexpr (Energy) diss += 0.5 * out.dissipated;
    }

    // Walls: the pair law with R_j = m_j = infinity; the wall moves with the cavity.
    const Vec3 x_local = p_.x[p] - c_pos;
    const double r = p_.radius[p];
    // The cavity's bounds: a centre outside them has left the cavity (for "planes" cavities the
    // planes need not enclose anything).
    const double d_bounds = std::min((x_local - lo).minCoeff(), (hi - x_local).minCoeff());
    double d_min = 1e300;  // nearest wall
    Vec3 F_wall(0, 0, 0), T_cavity(0, 0, 0);
    const std::uint32_t touched_before = wall_touch_[p];
    std::uint32_t touched = 0;
    for (std::size_t w = 0; w < nw; ++w) {
      const Wall& wall = scene_.walls[w];
      ContactGeometry g;
      const double d = wall_distance(wall, x_local, g.n);
      d_min = std::min(d_min, d);
      g.overlap = r - d;
      if (g.overlap <= 0) {
        // A contact that just opened: tally what it still held, clear its history (walls not
        // touched cost no memory access).
        if (touched_before & (1u << w)) {
          if constexpr (Energy) {
            const Vec3 v_c = p_.v[p] - c_half - r * p_.w[p].cross(g.n);
            diss += closing_tally<Tangential, Rolling>(g.n, v_c, p_.w[p], dt, wall_damping_prev_[p * nw + w],
                                                       Tangential ? &wall_tan_[p * nw + w] : nullptr,
                                                       Rolling ? &wall_roll_[p * nw + w] : nullptr);
            wall_damping_prev_[p * nw + w] = 0.0;
          }
          if constexpr (Tangential) wall_tan_[p * nw + w] = {};
          if constexpr (Rolling) wall_roll_[p * nw + w] = {};
        }
        continue;
      }
      touched |= 1u << w;
      g.R_eff = wall_effective_radius(wall, r);
      g.m_eff = p_.mass[p];
      g.arm_i = r - 0.5 * g.overlap;
      g.arm_j = 0;
      // The wall's velocity at the end of the step is exact (prescribed); at the half step it is
      // the mean over the step.
      if constexpr (Tangential || Rolling) {
        g.v_rel = contact_velocity(p_.v_pred[p], c_vel, p_.w_pred[p], Vec3::Zero(), g);
        g.v_half = contact_velocity(p_.v[p], c_half, p_.w[p], Vec3::Zero(), g);
        g.w_half = p_.w[p];
      } else {
        g.v_rel = p_.v_pred[p] - c_vel;
        g.v_half = p_.v[p] - c_half;
      }
      const PairLaw& law = laws(p_.material[p], wall.material);
      const NormalResult nr = hertz_normal(g, law);
      Vec3 Fc = nr.force * g.n;
      if constexpr (Energy) diss.x() += normal_dissipation(nr, g.v_half.dot(g.n), dt, wall_damping_prev_[p * nw + w]);
      if constexpr (Tangential) {
        const TangentialResult tr = mindlin_tangential(g, law, nr, dt, wall_tan_[p * nw + w]);
        Fc += tr.force;
        T -= g.arm_i * g.n.cross(tr.force);
        if constexpr (Energy) diss.y() += tr.dissipated;
      }
      if constexpr (Rolling) {
        const RollingResult rr = epsd_rolling(g, law, nr.stiffness, nr.force, dt, wall_roll_[p * nw + w]);
        T += rr.torque;
        if constexpr (Energy) diss.z() += rr.dissipated;
      }
      F += Fc;
      F_wall += Fc;
      // Torque on the cavity about its reference point, from the contact point on the wall.
      T_cavity -= (x_local - d * g.n - scene_.cavity_reference).cross(Fc);
    }
    p_.f[p] = F;
    p_.t[p] = T;
    wall_touch_[p] = touched;
    min_dist = std::min({min_dist, d_min, d_bounds});
    excess = std::max(excess, r - d_min - frac * r);  // the deepest wall contact

    // Tallies: the load on the cavity (always) and the energy budget (when asked).
    tally_.wall_impulse[p] -= dt * F_wall;
    tally_.wall_ang_impulse[p] += dt * T_cavity;
    if constexpr (Energy) {
      // Work of the walls on the contents: trapezoidal rule over the cavity's displacement.
      tally_.work_cavity[p] += 0.5 * (F_wall + tally_.wall_force_prev[p]).dot(c_step);
      tally_.wall_force_prev[p] = F_wall;
      tally_.diss_normal[p] += diss.x();
      tally_.diss_tangential[p] += diss.y();
      tally_.diss_rolling[p] += diss.z();
    }
  }
  overlap_excess_ = excess;
  min_boundary_distance_ = min_dist;
}

// ---- 6. kick ------------------------------------------------------------------------------------
// Also checks that every velocity is a number (a diverged integration shows there first).
void Simulation::kick() {
  const double h = 0.5 * scene_.dt;
  const std::size_t n = p_.size();
  const bool rot = scene_.models.rotation;
  bool finite = true;
#pragma omp parallel for schedule(static) reduction(&& : finite) if (n > kParallelMin)
  for (std::size_t i = 0; i < n; ++i) {
    p_.v[i] += h * p_.inv_mass[i] * p_.f[i];
    if (rot) p_.w[i] += h * p_.inv_inertia[i] * p_.t[i];
    finite = finite && std::isfinite(p_.v[i].squaredNorm());
  }
  all_finite_ = finite;
}

// ---- 7. guards ----------------------------------------------------------------------------------
void Simulation::guards() {
  const std::size_t n = p_.size();
  const bool bad = !all_finite_;  // a NaN position makes the next velocity NaN too
  const bool overlap = overlap_excess_ > 0.0;
  const bool escaped = min_boundary_distance_ < 0.0;
  if (!bad && !overlap && !escaped) return;

  std::ostringstream m;
  m << "run stopped at t = " << time() << " s (step " << step_ << "): ";
  if (bad) {
    m << "a particle position or velocity is not a number. The integration diverged: reduce "
         "simulation.timestep (or its safety factor), or check the material parameters.";
    throw RunError(m.str());
  }
  // A particle outside the cavity also shows as a huge wall overlap: name the escape first.
  if (escaped) {
    const Vec3 c = cavity_.position;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 xl = p_.x[i] - c;
      std::string where;
      for (const Wall& w : scene_.walls) {
        Vec3 nrm;
        if (wall_distance(w, xl, nrm) < 0) where = "through wall '" + scene_.wall_names[static_cast<std::size_t>(&w - scene_.walls.data())] + "'";
      }
      if (where.empty() && ((xl - scene_.cavity_lo).minCoeff() < 0 || (scene_.cavity_hi - xl).minCoeff() < 0))
        where = "beyond the cavity bounds (cavity.min/max)";
      if (where.empty()) continue;
      m << "particle " << i << " left the cavity " << where << " at (" << p_.x[i].x() << ", " << p_.x[i].y()
        << ", " << p_.x[i].z()
        << ") m. It went through the boundary within one step or flew out of an open cavity: reduce "
           "simulation.timestep, the cavity acceleration or the particle speeds, raise the wall's "
           "Young's modulus, or close the cavity.";
      throw RunError(m.str());
    }
  }
  {
    m << "a contact overlap reached " << 100 * largest_overlap_ratio() << "% of a particle radius (limit "
      << 100 * scene_.max_overlap_fraction
      << "%, key simulation.max_overlap). Impacts are faster or contacts softer than the time step "
         "and stiffness allow: reduce simulation.timestep, raise simulation.expected_speed, or "
         "raise the Young's modulus.";
  }
  throw RunError(m.str());
}

// The largest overlap / smaller radius of any contact now (for messages; a serial scan).
double Simulation::largest_overlap_ratio() const {
  double worst = 0;
  for (std::size_t k = 0; k < ps_.pairs.size(); ++k) {
    const std::uint32_t i = ps_.first[k], j = ps_.pairs.partner[k];
    ContactGeometry g;
    if (sphere_sphere(p_.x[i], p_.x[j], p_.radius[i], p_.radius[j], g))
      worst = std::max(worst, g.overlap / std::min(p_.radius[i], p_.radius[j]));
  }
  for (std::size_t p = 0; p < p_.size(); ++p)
    for (const Wall& w : scene_.walls) {
      Vec3 n;
      worst = std::max(worst, 1.0 - wall_distance(w, p_.x[p] - cavity_.position, n) / p_.radius[p]);
    }
  return worst;
}

// ---- energy budget and loads --------------------------------------------------------------------
double Simulation::potential_energy() const {
  if (!scene_.models.gravity) return 0.0;
  double u = 0;
  for (std::size_t i = 0; i < p_.size(); ++i) u -= p_.mass[i] * scene_.gravity.dot(p_.x[i]);
  return u;
}

double Simulation::elastic_energy() const {
  double u = 0;
  for (std::size_t k = 0; k < ps_.pairs.size(); ++k) {
    const std::uint32_t i = ps_.first[k], j = ps_.pairs.partner[k];
    ContactGeometry g;
    if (!sphere_sphere(p_.x[i], p_.x[j], p_.radius[i], p_.radius[j], g)) continue;
    u += hertz_energy(scene_.laws(p_.material[i], p_.material[j]), g.R_eff, g.overlap);
    if (scene_.models.tangential) u += mindlin_energy(ps_.tangential[k]);
    if (scene_.models.rolling) u += rolling_energy(ps_.rolling[k]);
  }
  const std::size_t nw = scene_.walls.size();
  for (std::size_t p = 0; p < p_.size(); ++p) {
    for (std::size_t w = 0; w < nw; ++w) {
      Vec3 n;
      const double overlap = p_.radius[p] - wall_distance(scene_.walls[w], p_.x[p] - cavity_.position, n);
      if (overlap <= 0) continue;
      u += hertz_energy(scene_.laws(p_.material[p], scene_.walls[w].material),
                        wall_effective_radius(scene_.walls[w], p_.radius[p]), overlap);
      if (scene_.models.tangential) u += mindlin_energy(wall_tan_[p * nw + w]);
      if (scene_.models.rolling) u += rolling_energy(wall_roll_[p * nw + w]);
    }
  }
  return u;
}

EnergySample Simulation::energy() const {
  EnergySample e;
  for (std::size_t i = 0; i < p_.size(); ++i) {
    e.kinetic += 0.5 * p_.mass[i] * p_.v[i].squaredNorm();
    if (scene_.models.rotation) e.kinetic += 0.5 * p_.w[i].squaredNorm() / p_.inv_inertia[i];
    e.work_cavity += tally_.work_cavity[i];
    e.dissipated_normal += tally_.diss_normal[i];
    e.dissipated_tangential += tally_.diss_tangential[i];
    e.dissipated_rolling += tally_.diss_rolling[i];
  }
  e.elastic = elastic_energy();
  e.work_gravity = potential0_ - potential_energy();
  return e;
}

Simulation::CavitySample Simulation::take_cavity_sample() {
  Vec3 J(0, 0, 0), L(0, 0, 0);
  for (std::size_t i = 0; i < p_.size(); ++i) {
    J += tally_.wall_impulse[i];
    L += tally_.wall_ang_impulse[i];
    tally_.wall_impulse[i].setZero();
    tally_.wall_ang_impulse[i].setZero();
  }
  CavitySample c;
  const double n = static_cast<double>(cavity_sums_.steps);
  if (n > 0) {
    const double span = n * scene_.dt;
    c.time = cavity_sums_.time / n;
    c.position = cavity_sums_.position / n;
    c.velocity = cavity_sums_.velocity / n;
    c.force = J / span;
    c.torque = L / span;
  }
  cavity_sums_ = {};
  return c;
}

std::size_t Simulation::contact_count() const {
  std::size_t c = 0;
  for (std::size_t k = 0; k < ps_.pairs.size(); ++k) {
    ContactGeometry g;
    c += sphere_sphere(p_.x[ps_.first[k]], p_.x[ps_.pairs.partner[k]], p_.radius[ps_.first[k]],
                       p_.radius[ps_.pairs.partner[k]], g);
  }
  for (std::size_t p = 0; p < p_.size(); ++p)
    for (const Wall& w : scene_.walls) {
      Vec3 n;
      c += wall_distance(w, p_.x[p] - cavity_.position, n) < p_.radius[p];
    }
  return c;
}

}  // namespace bagdem
