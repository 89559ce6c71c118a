// Stages 4 and 5 of the step: pair contacts and walls, the contact kernel (layer 3 of neighbour
// search -> contact geometry -> contact law). Each configuration of the model switches is compiled
// as its own loop (with_flags), so no switch is tested per contact.
#include "bagdem/stepper.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "bagdem/contact/hertz.hpp"
#include "bagdem/contact/surface_law.hpp"
#include "stepper_detail.hpp"

namespace bagdem {


// ---- 4. pair_contacts ---------------------------------------------------------------------------
// Two ways to sum pair forces onto particles, bitwise identical by construction:
//  scatter (one thread, or few pairs): the pair loop adds each force to f[i] and f[j] at once.
//    Pairs run in (i, j) order, so particle p receives its pairs (k, p), k < p ascending, then
//    (p, j) ascending: partner order.
//  gather (several threads): each pair writes its record, then each particle sums its records in
//    partner order (gather_walls). Same operands, same order, same result.
void Simulation::pair_contacts() {
  const bool scattered = scatter_;
  scatter_ = omp_get_max_threads() == 1 || ps_.pairs.size() <= kParallelMin;
  // Scattering keeps no records: back to gathering (the thread count changed), they restart at zero.
  if (scattered && !scatter_) {
    std::fill(ps_.rec.begin(), ps_.rec.end(), PairState::Record{Vec3::Zero(), Vec3::Zero()});
    std::fill(ps_.rec_diss.begin(), ps_.rec_diss.end(), Vec3::Zero());
  }
  // The contact-law configuration is chosen once here, never inside the loop.
  with_flags([this]<bool T, bool R, bool E, bool S, bool U>() { pair_contacts_impl<T, R, E, S, U>(); },
             scene_.models.tangential, scene_.models.rolling, scene_.models.energy, scatter_, uniform_);
}

// A pair contact opened this step: tally what it still held (closing_tally) and clear its
// history. Rare, so kept out of line: the pair loop stays small.
template <bool Tangential, bool Rolling, bool Energy, bool Scatter>
[[gnu::noinline]] void Simulation::open_pair(std::size_t k, std::uint32_t i, std::uint32_t j) {
  // Gathering, the pair's record holds this step's closing tally (forces zero): state 2 until the
  // next step. Scattering, it is done with.
  ps_.touching[k] = Scatter ? 0 : 2;
  if constexpr (!Scatter) {
    for (const std::uint32_t e : {ps_.slot[2 * k], ps_.slot[2 * k + 1]}) {
      ps_.rec[e] = {Vec3::Zero(), Vec3::Zero()};
      if constexpr (Energy) ps_.rec_diss[e].setZero();
    }
  }
  if constexpr (Energy) {
    const Vec3 n = (p_.x[i] - p_.x[j]).normalized();
    const Vec3 v_c = p_.v[i] - p_.v[j] - (p_.radius[i] * p_.w[i] + p_.radius[j] * p_.w[j]).cross(n);
    const Vec3 d = closing_tally<Tangential, Rolling>(n, v_c, p_.w[i] - p_.w[j], dt_step_, ps_.damping_prev[k],
                                                      Tangential ? &ps_.tangential[k] : nullptr,
                                                      Rolling ? &ps_.rolling[k] : nullptr);
    if constexpr (Scatter) {
      tally_.step_dissipation[i] += 0.5 * d;
      tally_.step_dissipation[j] += 0.5 * d;
    } else {
      ps_.rec_diss[ps_.slot[2 * k]] = d;
      ps_.rec_diss[ps_.slot[2 * k + 1]] = d;
    }
    ps_.damping_prev[k] = 0.0;
  }
  if constexpr (Tangential) ps_.tangential[k] = {};
  if constexpr (Rolling) ps_.rolling[k] = {};
}

// Uniform: all balls alike, so their radius, inverse mass and law are the first ball's (the same
// values, so the same results; R* and m* are then loop constants, two divisions fewer per contact).
template <bool Tangential, bool Rolling, bool Energy, bool Scatter, bool Uniform>
void Simulation::pair_contacts_impl() {
  const std::size_t np = ps_.pairs.size();
  const double dt = dt_step_;
  const PairLawTable& laws = scene_.laws;
  const double frac = scene_.max_overlap_fraction;
  double excess = -1e300;
  const double r0 = np > 0 ? p_.radius[0] : 0.0, im0 = np > 0 ? p_.inv_mass[0] : 0.0;
  const PairLaw* law0 = np > 0 ? &laws(p_.material[0], p_.material[0]) : nullptr;
  auto radius = [this, r0](std::uint32_t i) BAGDEM_INLINE_LAMBDA { return Uniform ? r0 : p_.radius[i]; };
  // The contact law on kLanes pairs side by side (surface_contact_lanes): lane l is the pair ks[l]
  // for l < n; the lanes past n repeat the last pair (its histories are written again with the same
  // values, its results go to out[n..kLanes), unused). Each pair's force, torques and dissipation go
  // to out[l] as rows of 4 doubles (x, y, z, unused), its histories are updated. No accumulation here.
  struct alignas(32) Out {
    double F[4], Ti[4], Tj[4], diss[4];
  };
  auto pair_lanes = [this, dt, frac, &laws, r0, im0, law0](const std::uint32_t* ks, int n, Out* out, double& excess)
                        BAGDEM_INLINE_LAMBDA {
    std::uint32_t K[kLanes], I[kLanes], J[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      K[l] = ks[std::min(l, n - 1)];
      I[l] = ps_.first[K[l]];
      J[l] = ps_.pairs.partner[K[l]];
    }
    auto gather = [](const auto& a, const std::uint32_t* at) BAGDEM_INLINE_LAMBDA {
      return Lanes{a[at[0]], a[at[1]], a[at[2]], a[at[3]]};  // built whole, not lane by lane (lanes.hpp)
    };
    ContactGeometryT<Lanes> g;
    const Lanes ri = Uniform ? splat<Lanes>(r0) : gather(p_.radius, I), rj = Uniform ? splat<Lanes>(r0) : gather(p_.radius, J);
    sphere_sphere_geometry<Lanes>(gather3(p_.x.data(), I), gather3(p_.x.data(), J), ri, rj, g);
    const Lanes deep = g.overlap - frac * min_of(ri, rj);
    for (int l = 0; l < n; ++l) excess = std::max(excess, deep[l]);
    g.m_eff = Uniform ? splat<Lanes>(1.0 / (im0 + im0)) : 1.0 / (gather(p_.inv_mass, I) + gather(p_.inv_mass, J));
    if constexpr (Tangential || Rolling) {
      const Lanes3 wi = gather3(p_.w.data(), I), wj = gather3(p_.w.data(), J);
      g.v_rel = contact_velocity<Lanes>(gather3(p_.v_pred.data(), I), gather3(p_.v_pred.data(), J), gather3(p_.w_pred.data(), I), gather3(p_.w_pred.data(), J), g);
      g.v_half = contact_velocity<Lanes>(gather3(p_.v.data(), I), gather3(p_.v.data(), J), wi, wj, g);
      g.w_half = wi - wj;
    } else {
      g.v_rel = gather3(p_.v_pred.data(), I) - gather3(p_.v_pred.data(), J);
      g.v_half = gather3(p_.v.data(), I) - gather3(p_.v.data(), J);
    }
    double* damping[kLanes];
    TangentialHistory* th[kLanes];
    RollingHistory* rh[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      damping[l] = Energy ? &ps_.damping_prev[K[l]] : nullptr;
      th[l] = Tangential ? &ps_.tangential[K[l]] : nullptr;
      rh[l] = Rolling ? &ps_.rolling[K[l]] : nullptr;
    }
    auto with_law = [&](const auto& law) BAGDEM_INLINE_LAMBDA {
      const SurfaceLanes c = surface_contact_lanes<Tangential, Rolling, Energy>(g, law, dt, damping, th, rh);
      using Row = double[4];
      auto rows = [out](Row Out::*m) BAGDEM_INLINE_LAMBDA {
        return std::array<double*, kLanes>{out[0].*m, out[1].*m, out[2].*m, out[3].*m};
      };
      to_rows(c.F, splat<Lanes>(0), rows(&Out::F).data());
      if constexpr (Tangential || Rolling) {
        // As surface_contact's torque: -arm_i (n x F_t), then the rolling torque (on j: -arm_j (n x F_t)
        // and the opposite rolling torque).
        to_rows(-(g.arm_i * c.nxFt) + c.roll, splat<Lanes>(0), rows(&Out::Ti).data());
        to_rows(-(g.arm_j * c.nxFt) - c.roll, splat<Lanes>(0), rows(&Out::Tj).data());
      }
      if constexpr (Energy) to_rows(c.diss, splat<Lanes>(0), rows(&Out::diss).data());
    };
    if constexpr (Uniform) {
      with_law(*law0);
    } else {
      const PairLaw* e[kLanes];
      for (int l = 0; l < kLanes; ++l) e[l] = &laws(p_.material[I[l]], p_.material[J[l]]);
      with_law(law_lanes(e));
    }
  };
  // The pair's force and torques onto its particles (scattering: on one thread, outside any
  // parallel region) or into its records (gathering).
  auto apply = [this](std::size_t k, const Out& o) BAGDEM_INLINE_LAMBDA {
    ps_.touching[k] = 1;
    auto row = [](const double* r) BAGDEM_INLINE_LAMBDA { return Vec3(r[0], r[1], r[2]); };
    const struct {
      Vec3 F, Ti, Tj, diss;
    } out{row(o.F), row(o.Ti), row(o.Tj), row(o.diss)};
    const std::uint32_t i = ps_.first[k], j = ps_.pairs.partner[k];
    if constexpr (Scatter) {
      p_.f[i] += out.F;
      p_.f[j] -= out.F;
      if constexpr (Tangential || Rolling) {
        p_.t[i] += out.Ti;
        p_.t[j] += out.Tj;
      }
      if constexpr (Energy) {
        tally_.step_dissipation[i] += 0.5 * out.diss;
        tally_.step_dissipation[j] += 0.5 * out.diss;
      }
    } else {
      PairState::Record& ri = ps_.rec[ps_.slot[2 * k]];
      PairState::Record& rj = ps_.rec[ps_.slot[2 * k + 1]];
      ri.force = out.F;
      rj.force = -out.F;  // F - x and F + (-x) are the same bits
      if constexpr (Tangential || Rolling) {
        ri.torque = out.Ti;
        rj.torque = out.Tj;
      }
      if constexpr (Energy) ps_.rec_diss[ps_.slot[2 * k]] = ps_.rec_diss[ps_.slot[2 * k + 1]] = out.diss;
    }
  };
  // A pair that touched at the last step and is apart now: the contact opened (pairs that stay
  // apart cost no history access, and their records stay zero).
  auto apart = [this](std::size_t k) BAGDEM_INLINE_LAMBDA {
    if (ps_.touching[k] == 1) {
      open_pair<Tangential, Rolling, Energy, Scatter>(k, ps_.first[k], ps_.pairs.partner[k]);
    } else {
      ps_.touching[k] = 0;
      if constexpr (Energy && !Scatter) ps_.rec_diss[ps_.slot[2 * k]] = ps_.rec_diss[ps_.slot[2 * k + 1]] = Vec3::Zero();
    }
  };
  // The pairs in blocks of kBlock, in three passes:
  //  1. a branch-free scan for the pairs that touch now (`closed`) and those that touched at the
  //     last step and are apart now (`opened`); most candidate pairs are neither. The test is
  //     sphere_sphere's (spheres_apart).
  //  2. the contact law on the closed pairs, kLanes at a time (pair_lanes);
  //  3. in pair order, each closed pair's results applied (so each particle's sums are in partner
  //     order, as the gather's), or the opened pair closed.
  // A block's lanes hold the same pairs whatever the thread count, so the results do not depend on it.
  constexpr std::size_t kBlock = 128;
  auto one_block = [this, np, &pair_lanes, &apply, &apart, radius](std::size_t b, double& excess) BAGDEM_INLINE_LAMBDA {
    const std::size_t k0 = b * kBlock, k1 = std::min(np, k0 + kBlock);
    std::uint32_t closed[kBlock], opened[kBlock];
    std::size_t nc = 0, no = 0;
    const std::uint32_t* first = ps_.first.data();
    const std::uint32_t* partner = ps_.pairs.partner.data();
    const std::uint8_t* touching = ps_.touching.data();
    const Vec3* x = p_.x.data();
    for (std::size_t k = k0; k < k1; ++k) {
      const std::uint32_t i = first[k], j = partner[k];
      const bool touches = !spheres_apart(x[i], x[j], radius(i) + radius(j));
      closed[nc] = opened[no] = static_cast<std::uint32_t>(k);
      nc += touches;
      no += !touches & (touching[k] != 0);
    }
    Out out[kBlock + kLanes];  // the last lanes of a block may run past nc
    for (std::size_t a = 0; a < nc; a += kLanes)
      pair_lanes(closed + a, static_cast<int>(std::min<std::size_t>(kLanes, nc - a)), out + a, excess);
    for (std::size_t a = 0, o = 0; a < nc || o < no;) {
      if (o == no || (a < nc && closed[a] < opened[o])) {
        apply(closed[a], out[a]);
        ++a;
      } else {
        apart(opened[o++]);
      }
    }
  };
  for_items<4>((np + kBlock - 1) / kBlock, !Scatter, excess, one_block, [](double& a, double b) { a = std::max(a, b); });
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
  const WallMotion rigid = rigid_motion();  // the walls' motion (per ball with a slope: motion_at)
  const Vec3 lo = scene_.cavity_lo, hi = scene_.cavity_hi;
  const PairLawTable& laws = scene_.laws;
  const double frac = scene_.max_overlap_fraction;
  struct GuardValues {
    double excess, min_dist;
    bool finite;
  } ext{overlap_excess_, 1e300, true};
  // Stage 9's kick of the balls, done here while the ball's force and torque are at hand when no
  // later stage adds to them (kick_balls_here; the same operations as kick()).
  const bool kick = kick_balls_here(), rotation = scene_.models.rotation;
  const double h = 0.5 * dt;
  auto finish = [this, kick, rotation, h](std::size_t p, const Vec3& F, const Vec3& T, GuardValues& ext)
                    BAGDEM_INLINE_LAMBDA {
    if (kick) ext.finite = kick_ball(p, F, T, h, rotation) && ext.finite;
  };
  auto one_ball = [this, nw, dt, rigid, lo, hi, &laws, frac, finish](std::size_t p, GuardValues& ext) BAGDEM_INLINE_LAMBDA {
    double& excess = ext.excess;
    double& min_dist = ext.min_dist;
    // Starts from gravity (kick_drift), plus the pairs when they were scattered.
    Vec3 F = p_.f[p];
    Vec3 T = p_.t[p];
    [[maybe_unused]] Vec3 diss(0, 0, 0);
    if constexpr (Energy) diss = tally_.step_dissipation[p];
    for (std::uint32_t e = Gather ? ps_.gather_begin[p] : 0; e < (Gather ? ps_.gather_begin[p + 1] : 0); ++e) {
      F += ps_.rec[e].force;
      if constexpr (Tangential || Rolling) T += ps_.rec[e].torque;
      if constexpr (Energy) diss += 0.5 * ps_.rec_diss[e];
    }

    // Walls: the pair law with R_j = m_j = infinity; the wall moves with the cavity.
    const WallMotion wm = tilt_ ? motion_at(p_.x[p]) : rigid;
    const Vec3 &c_vel = wm.vel, &c_half = wm.half, &c_step = wm.step;  // c_half: mean over the step
    const Vec3 x_local = p_.x[p] - wm.pos;
    const double r = p_.radius[p];
    // The cavity's bounds: a centre outside them has left the cavity (for "planes" cavities the
    // planes need not enclose anything).
    const double d_bounds = std::min((x_local - lo).minCoeff(), (hi - x_local).minCoeff());
    const std::uint32_t near = wall_near_[p];
    if (near == 0) {
      // No wall can touch this ball (find_near_walls): only the sums and the bounds. What it adds
      // to its tallies this step is zero and is skipped (its last wall force was zero too).
      if constexpr (Gather) {
        p_.f[p] = F;
        p_.t[p] = T;
      }
      if (couple_) cavity_load_[p].setZero();
      if constexpr (Energy) {
        tally_.diss_normal[p] += diss.x();
        tally_.diss_tangential[p] += diss.y();
        tally_.diss_rolling[p] += diss.z();
      }
      min_dist = std::min(min_dist, d_bounds);
      finish(p, F, T, ext);
      return;
    }
    double d_min = 1e300;  // nearest wall
    Vec3 F_wall(0, 0, 0), T_cavity(0, 0, 0), load(0, 0, 0);
    const std::uint32_t touched_before = wall_touch_[p];
    std::uint32_t touched = 0;
    for (std::uint32_t bits = near; bits != 0; bits &= bits - 1) {
      const auto w = static_cast<std::size_t>(std::countr_zero(bits));
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
      [[maybe_unused]] double no_tally = 0;
      const Vec3 Fc = surface_contact<Tangential, Rolling, Energy>(
          g, law, dt, Energy ? wall_damping_prev_[p * nw + w] : no_tally, Tangential ? &wall_tan_[p * nw + w] : nullptr,
          Rolling ? &wall_roll_[p * nw + w] : nullptr, T, diss);
      F += Fc;
      F_wall += Fc;
      // Torque on the cavity about its reference point, from the contact point on the wall.
      T_cavity -= cross(Vec3(x_local - d * g.n - scene_.cavity_reference), Fc);
      if (couple_) load += load_moments(x_local - d * g.n, -Fc);
    }
    if (couple_) cavity_load_[p] = load;
    p_.f[p] = F;
    p_.t[p] = T;
    wall_touch_[p] = touched;
    min_dist = std::min({min_dist, d_min, d_bounds});
    excess = std::max(excess, r - d_min - frac * r);  // the deepest wall contact
    finish(p, F, T, ext);

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
  };
  for_items(n, threaded(n), ext, one_ball, [](GuardValues& a, const GuardValues& b) {
    a.excess = std::max(a.excess, b.excess);
    a.min_dist = std::min(a.min_dist, b.min_dist);
    a.finite = a.finite && b.finite;
  });
  overlap_excess_ = ext.excess;
  min_boundary_distance_ = ext.min_dist;
  balls_finite_ = ext.finite;
}

}  // namespace bagdem
