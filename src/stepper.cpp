// The stepper: the stage list of stepper.hpp. This file: set-up, the step, and the stages that move
// particles and the cavity (kick-drift, move cavity, neighbours, kick). The contact stages are in
// stepper_contacts.cpp (pairs) and stepper_walls.cpp, the guards in stepper_guards.cpp, energy and
// loads in stepper_budget.cpp.
#include "bagdem/stepper.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "bagdem/neighbour/spatial_order.hpp"
#include "bagdem/particles.hpp"
#include "stepper_detail.hpp"

namespace bagdem {

Simulation::Simulation(const Scene& scene) : scene_(scene), broad_(make_broad_phase(scene.broad_phase)) {
  const std::size_t n = scene.particles.size();
  order_ = spatial_order(scene);
  p_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const ParticleInit& q = scene.particles[order_[i]];
    const double rho = scene.materials[static_cast<std::size_t>(q.material)].density;
    const double m = sphere_mass(rho, q.radius);
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
  // Balls all alike (one radius, one material): the pair kernel takes R*, m* and the law as constants.
  uniform_ = n > 0 && std::all_of(scene.particles.begin(), scene.particles.end(), [&](const ParticleInit& q) {
               return q.radius == scene.particles[0].radius && q.material == scene.particles[0].material;
             });
  tally_.resize(n);
  const std::size_t nw = scene.walls.size();
  if (scene.models.tangential) wall_tan_.assign(n * nw, {});
  if (scene.models.rolling) wall_roll_.assign(n * nw, {});
  if (scene.models.energy) wall_damping_prev_.assign(n * nw, 0.0);
  wall_touch_.assign(n, 0);  // 32 bits: a cavity has at most 32 walls (checked when loading)
  wall_near_.assign(n, 0);
  cavity_ = cavity_prev_ = cavity_at(0.0);
  set_up_structure();
  set_up_film();
  set_up_meshes();
  // The contents' mass, balls then film nodes (the order contents_relative_velocity sums them in).
  for (std::size_t i = 0; i < n; ++i) contents_mass_ += p_.mass[i];
  for (std::size_t k = 0; k < film_.size(); ++k) contents_mass_ += film_.mass[k];
  update_neighbours(true);
  for (std::size_t i = 0; i < n; ++i) start_sums(i);
  dt_step_ = 0.0;  // set-up force evaluation: no history increment, no dissipation
  pair_contacts();
  wall_contacts();
  triangle_contacts();
  film_stage();
  if (couple_) {
    structure_forces();  // the contents' load at rest
    release_step_ = static_cast<std::uint64_t>(std::llround(scene_.settle / scene_.dt));
    if (release_step_ == 0) release_structure();
  }
  potential0_ = potential_energy();
  const EnergySample e0 = energy();
  kinetic_elastic0_ = e0.kinetic + e0.elastic;
}

CavityState Simulation::cavity_at(double t) const {
  if (couple_) return structure_cavity();
  if (t < scene_.settle) return {scene_.motion->at(0.0).position, Vec3::Zero()};
  return scene_.motion->at(t - scene_.settle);
}

void Simulation::advance(std::uint64_t steps) {
  for (std::uint64_t k = 0; k < steps;) {
    const std::uint64_t pipelined = k + 1 < steps ? run_pipelined(steps - 1 - k) : 0;  // not the last (its kick)
    if (pipelined > 0) {
      k += pipelined;
    } else {
      step_once(k + 1 == steps);
      ++k;
    }
  }
}

void Simulation::step_once(bool last) {
  dt_step_ = scene_.dt;
  defer_kick_ = !last && surfaces_.empty();
  if (couple_ && step_ == release_step_ && !structure_.scalars.released) release_structure();
  if (!profile_) {
    kick_drift();
    move_cavity();
    update_neighbours(false);
    if (fusable()) {
      fused_contacts();
    } else {
      pair_contacts();
      wall_contacts();
      triangle_contacts();
      film_stage();
    }
    if (couple_) structure_forces();
    kick();
    ++step_;
    guards();
    end_balance();
    return;
  }
  // The same stages, each timed.
  double t = omp_get_wtime();
  auto lap = [&t](double& into) {
    const double now = omp_get_wtime();
    into += now - t;
    t = now;
  };
  kick_drift();
  move_cavity();
  lap(times_.integrate);
  update_neighbours(false);
  lap(times_.neighbours);
  pair_contacts();
  lap(times_.pairs);
  wall_contacts();
  lap(times_.walls);
  triangle_contacts();
  lap(times_.triangles);
  film_stage();
  lap(times_.film);
  if (couple_) structure_forces();
  kick();
  lap(times_.integrate);
  ++step_;
  ++times_.steps;
  guards();
  end_balance();
  lap(times_.guards);
}

// The threads' spans are moved by the clock (SpanBalance); the pair stage's ranges are cut anew
// where its cuts moved.
void Simulation::end_balance() {
  if (balance_.end_step()) ps_.ranges = 0;
}

// ---- 1. kick_drift ------------------------------------------------------------------------------
// Also predicts the end-of-step velocities the contact law uses, v(n+1/2) + dt/2 F(n)/m: with the
// half-step velocity alone (as LAMMPS and LIGGGHTS do) the damping force lags by dt/2, a first-order
// error in the restitution (-26% at e = 0.01 with 40 steps per contact); the prediction makes it
// second order. Also finds the largest step a ball took (travel_; end_drift).
template <bool Finish, bool Rotation, bool Gravity, bool Energy>
void Simulation::drift_span(std::size_t b0, std::size_t b1, const WallMotion&, StageFold& fold) {
  const double dt = scene_.dt, h = 0.5 * dt;
  const Vec3 g = scene_.gravity;
  // The arrays and the folds in locals, and every ball's values read before any is written: the
  // compiler then keeps them in registers (through the members, each store made it reload them, as
  // a store may alias: the drift took 19-20% of the step at N = 10000, now 14-16%).
  Vec3 *x = p_.x.data(), *v = p_.v.data(), *w = p_.w.data(), *v_pred = p_.v_pred.data(), *w_pred = p_.w_pred.data();
  Vec3 *f = p_.f.data(), *t = p_.t.data(), *diss = tally_.step_dissipation.data();
  const double *mass = p_.mass.data(), *inv_mass = p_.inv_mass.data(), *inv_inertia = p_.inv_inertia.data();
  bool finite = fold.finished_finite;
  double step2 = fold.step2;
  // Balls all alike (uniform_): their mass and inertia are the first ball's (the same values, so
  // the same results), and the loop reads three arrays fewer.
  auto balls = [&](auto mass_of, auto inv_mass_of, auto inv_inertia_of) BAGDEM_INLINE_LAMBDA {
    for (std::size_t i = b0; i < b1; ++i) {
      const Vec3 dv = h * inv_mass_of(i) * f[i];
      const Vec3 x0 = x[i];
      Vec3 vi = v[i];
      if constexpr (Finish) {
        vi = vi + dv;  // the last step's stage 9 (kick_ball's operations on the same force)
        finite = finite & std::isfinite(vi.squaredNorm());
      }
      vi = vi + dv;
      const Vec3 xi = x0 + dt * vi;
      if constexpr (Rotation) {
        const Vec3 dw = h * inv_inertia_of(i) * t[i];
        Vec3 wi = w[i];
        if constexpr (Finish) wi = wi + dw;
        wi = wi + dw;
        w[i] = wi;
        w_pred[i] = wi + dw;
      }
      v[i] = vi;
      x[i] = xi;
      v_pred[i] = vi + dv;
      step2 = std::max(step2, (xi - x0).squaredNorm());  // the step as taken, rounding included
      // The sums of the new step (start_sums, inlined here with its switches resolved).
      f[i] = Gravity ? Vec3(mass_of(i) * g) : Vec3::Zero();
      t[i].setZero();
      if constexpr (Energy) diss[i].setZero();
    }
  };
  if (uniform_) {
    const double m = mass[0], im = inv_mass[0], ii = inv_inertia[0];
    balls([m](std::size_t) { return m; }, [im](std::size_t) { return im; }, [ii](std::size_t) { return ii; });
  } else {
    balls([mass](std::size_t i) { return mass[i]; }, [inv_mass](std::size_t i) { return inv_mass[i]; },
          [inv_inertia](std::size_t i) { return inv_inertia[i]; });
  }
  fold.finished_finite = finite, fold.step2 = step2;
}

Simulation::BallSpan Simulation::drift_stage(bool finish) const {
  BallSpan span = nullptr;
  with_flags([&span]<bool Finish, bool Rotation, bool Gravity, bool Energy>() { span = &Simulation::drift_span<Finish, Rotation, Gravity, Energy>; },
             finish, scene_.models.rotation, scene_.models.gravity, scene_.models.energy);
  return span;
}

void Simulation::over_balls(BallSpan span, StageFold& fold) {
  const WallMotion cavity = rigid_motion();
  for_range_spans(balance_, p_.size(), fold, [this, span, &cavity](std::size_t b0, std::size_t b1, StageFold& f) { (this->*span)(b0, b1, cavity, f); },
                  [](StageFold& a, const StageFold& b) { a.merge(b); });
}

void Simulation::StageFold::merge(const StageFold& o) {
  excess = std::max(excess, o.excess);
  min_dist = std::min(min_dist, o.min_dist);
  kicked_finite = kicked_finite && o.kicked_finite;
  step2 = std::max(step2, o.step2);
  finished_finite = finished_finite && o.finished_finite;
}

void Simulation::end_drift(const StageFold& fold) {
  finished_finite_ = fold.finished_finite;
  largest_step_ = std::sqrt(fold.step2);
  // Rounded up twice over (the square root and the sum): travel_ never falls short of the true
  // sum of the steps, which the pair stage's skipping relies on (PairState::wake).
  travel_ = std::nextafter(travel_ + largest_step_ * (1.0 + 1e-14), HUGE_VAL);
  // The list is renewed a step ahead (kSkinStep): before the pairs at these positions when a ball
  // was near the skin's edge at the last ones.
  needs_rebuild_ = near_edge_;
  near_edge_ = travel_ > far_check_at_ && near_skin_edge();
}

// Whether a ball is more than skin/2 - kSkinStep x skin from where it was at the last build.
// Asked only when it could be (end_drift): a ball moved at most travel_ - t since travel_ was t,
// so after a check found them all within d of their place at the build, none can pass the edge
// before travel_ has grown by edge - d. The same steps rebuild as with the test at every step, and
// the drift does not read x_at_build_. In the shaken PD-box bed the check runs a few times per
// rebuild (the slack shrinks by a fraction each time).
bool Simulation::near_skin_edge() {
  const Vec3 *x = p_.x.data(), *at_build = x_at_build_.data();
  const double d2 = parallel_fold(p_.size(), 0.0, [=](std::size_t i) { return (x[i] - at_build[i]).squaredNorm(); },
                                  [](double a, double b) { return std::max(a, b); });
  return near_edge(d2, travel_, far_check_at_);
}

bool Simulation::near_edge(double d2, double travel, double& far) const {
  const double edge = (0.5 - kSkinStep) * scene_.skin;
  if (d2 > edge * edge) return true;
  // Rounded down by far more than the rounding of these few operations (1e-16 of skin).
  far = travel + (edge - std::nextafter(std::sqrt(d2), HUGE_VAL)) - 1e-12 * scene_.skin;
  return false;
}

void Simulation::kick_drift() {
  const double dt = scene_.dt, h = 0.5 * dt;
  if (!drifted_) {
    StageFold fold;
    over_balls(drift_stage(kick_pending_), fold);
    end_drift(fold);
  }
  drifted_ = false;
  kick_pending_ = false;
  const std::size_t nn = film_.size();
  parallel_for(nn, [&](std::size_t k) {
    const Vec3 dv = h * film_.inv_mass[k] * film_.f[k];
    film_.v[k] += dv;
    film_.x[k] += dt * film_.v[k];
    film_.v_pred[k] = film_.v[k] + dv;
  });
  if (couple_) structure_drift();
}


// ---- 2. move_cavity -----------------------------------------------------------------------------
void Simulation::move_cavity() {
  const double t = static_cast<double>(step_ + 1) * scene_.dt;
  cavity_to(t, cavity_at(t));
  // The walls' candidates (wall_near_) hold while the cavity moved at most skin/2 since the last
  // build; a slope moves a point at most |d shear| l further (l: half the cavity's axial extent).
  const double moved = (cavity_.position - cavity_pos_at_build_).norm() +
                       (tilt_ ? (cavity_.shear - cavity_shear_at_build_).norm() * tilt_extent_ : 0.0);
  if (moved > 0.5 * scene_.skin) needs_rebuild_ = true;
}

void Simulation::cavity_to(double t, const CavityState& c) {
  cavity_prev_ = cavity_;
  cavity_ = c;
  ++cavity_sums_.steps;
  cavity_sums_.time += t;
  cavity_sums_.position += cavity_.position;
  cavity_sums_.velocity += cavity_.velocity;
}

// ---- 3. neighbours ------------------------------------------------------------------------------
void Simulation::update_neighbours(bool force_rebuild) {
  const std::size_t n = p_.size();
  if (!force_rebuild && !needs_rebuild_ && !meshes_need_rebuild()) return;
  ++builds_;
  x_at_build_ = p_.x;
  // The new list and its histories go into spare buffers (kept between rebuilds, so a rebuild
  // reuses their memory), then swap places with the current ones.
  CandidatePairs& fresh = spare_.pairs;
  broad_->find(p_.x, p_.radius, scene_.skin, fresh);

  // Carry contact histories over: merge the old and new partner lists of each i (both sorted).
  const bool tan = scene_.models.tangential, roll = scene_.models.rolling, en = scene_.models.energy;
  auto& tan_new = spare_.tangential;
  auto& roll_new = spare_.rolling;
  auto& damp_new = spare_.damping_prev;
  tan_new.assign(tan ? fresh.size() : 0, {});
  roll_new.assign(roll ? fresh.size() : 0, {});
  damp_new.assign(en ? fresh.size() : 0, 0.0);
  if ((tan || roll || en) && !ps_.pairs.partner.empty()) {
    parallel_for(n, [&](std::size_t i) {
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
    });
  }
  std::swap(ps_.pairs, spare_.pairs);
  std::swap(ps_.tangential, spare_.tangential);
  std::swap(ps_.rolling, spare_.rolling);
  std::swap(ps_.damping_prev, spare_.damping_prev);
  derive_pair_buffers();
  cavity_pos_at_build_ = cavity_.position;
  cavity_shear_at_build_ = cavity_.shear;
  find_near_walls();
  if (!surfaces_.empty()) build_mesh_candidates(p_.x, film_.x, cavity_.position);
}

// The walls within skin of each ball's surface at the build (x_at_build_, the cavity where it was
// then). Until the next build neither moves more than skin/2, so no other wall can be touched.
// A ball with no wall near touched none at the last step either (that wall would be near): it has
// no wall history to close (wall_contacts).
void Simulation::find_near_walls() {
  const std::size_t n = p_.size(), nw = scene_.walls.size();
  CavityState at_build = cavity_;
  at_build.position = cavity_pos_at_build_;
  at_build.shear = cavity_shear_at_build_;
  // Near the bounds: the centre within skin of them (it moves less than skin relative to the cavity
  // before the next build, so the others stay inside).
  std::vector<std::uint8_t>& in_reach = near_scratch_;
  in_reach.resize(n);
  parallel_for(n, [&](std::size_t p) {
    const Vec3 x = x_at_build_[p];
    const double s = tilt_ ? (x - at_build.position - scene_.cavity_reference).dot(load_axis_) : 0.0;
    const Vec3 x_local = x - at_build.position - s * at_build.shear;
    std::uint32_t near = 0;
    for (std::size_t w = 0; w < nw; ++w) {
      Vec3 normal;
      if (wall_distance(scene_.walls[w], x_local, normal) - p_.radius[p] < scene_.skin) near |= 1u << w;
    }
    wall_near_[p] = near;
    const double d_bounds = std::min((x_local - scene_.cavity_lo).minCoeff(), (scene_.cavity_hi - x_local).minCoeff());
    in_reach[p] = near != 0 || d_bounds < scene_.skin;
  });
  near_balls_.clear();
  for (std::size_t p = 0; p < n; ++p) {
    if (in_reach[p]) near_balls_.push_back(static_cast<std::uint32_t>(p));
    else if (couple_ && surfaces_.empty()) cavity_load_[p].setZero();  // as the wall stage leaves a ball without a wall near
  }
}

// From the installed pair list and its histories: the per-pair buffers.
void Simulation::derive_pair_buffers() {
  const std::size_t n = p_.size();
  const std::size_t np = ps_.pairs.size();
  // A pair whose history was carried over may be touching; a fresh pair is not (all-zero history).
  ps_.touching.assign(np, 0);
  ps_.wake.assign(np, 0.0f);  // every pair looked at in the next pair stage (travel_ >= 0)
  travel_ = 0.0;
  far_check_at_ = -1.0;       // the next drift checks the distances from x_at_build_ (near_skin_edge)
  near_edge_ = false;         // every ball is where it was at the build
  for (std::size_t k = 0; k < np; ++k) {
    const bool t = !ps_.tangential.empty() && ps_.tangential[k].stiffness != 0;
    const bool r = !ps_.rolling.empty() && ps_.rolling[k].stiffness != 0;
    const bool d = !ps_.damping_prev.empty() && ps_.damping_prev[k] != 0;
    ps_.touching[k] = t || r || d;
  }
  ps_.first.resize(np);
  ps_.reach = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t k = ps_.pairs.begin[i]; k < ps_.pairs.begin[i + 1]; ++k) {
      ps_.first[k] = static_cast<std::uint32_t>(i);
      ps_.reach = std::max<std::size_t>(ps_.reach, ps_.pairs.partner[k] - i);
    }
  ps_.ranges = 0;  // cut into ranges at the next pair stage, for its thread count (derive_ranges)
}

// The particles cut into `ranges` ranges, the cross pairs and their records (PairState). Redone
// after each neighbour build, when the thread count changes and when the pair stage's balance moved
// its cuts. The cuts are the balance's (SpanBalance), at first of about equal pair counts.
void Simulation::derive_ranges(std::uint32_t ranges) {
  const std::size_t n = p_.size(), np = ps_.pairs.size();
  const CandidatePairs& pairs = ps_.pairs;
  if (balance_.spans() != ranges || balance_.cuts().back() != n) {
    std::vector<std::uint32_t> cuts(ranges + 1, static_cast<std::uint32_t>(n));
    cuts[0] = 0;
    for (std::uint32_t r = 1; r < ranges; ++r) cuts[r] = ps_.first[np * r / ranges];
    balance_.reset(cuts);
  }
  ps_.ranges = ranges;
  ps_.range_first = balance_.cuts();
  ps_.cross.clear();
  ps_.is_cross.assign(np, 0);
  for (std::uint32_t r = 0; r < ranges; ++r)
    for (std::uint32_t k = pairs.begin[ps_.range_first[r]]; k < pairs.begin[ps_.range_first[r + 1]]; ++k)
      if (pairs.partner[k] >= ps_.range_first[r + 1]) {
        ps_.cross.push_back(k);
        ps_.is_cross[k] = 1;
      }
  ps_.j_side.clear();
  for (std::size_t c = 0; c < ps_.cross.size(); ++c)
    ps_.j_side.push_back({pairs.partner[ps_.cross[c]], static_cast<std::uint32_t>(c)});
  // By j; for one j by i, as the cross list is.
  std::stable_sort(ps_.j_side.begin(), ps_.j_side.end(),
                   [](const PairState::JSide& a, const PairState::JSide& b) { return a.particle < b.particle; });
  ps_.j_side_range.resize(ranges + 1);
  for (std::uint32_t r = 0; r <= ranges; ++r)
    ps_.j_side_range[r] = static_cast<std::uint32_t>(
        std::lower_bound(ps_.j_side.begin(), ps_.j_side.end(), ps_.range_first[r],
                         [](const PairState::JSide& e, std::uint32_t p) { return e.particle < p; }) -
        ps_.j_side.begin());
  // The cross pairs by j's range (each range's thread computes those into it), and where each
  // range's own pairs first need records (PairState).
  auto range_of = [&](std::uint32_t p) {
    return static_cast<std::uint32_t>(std::upper_bound(ps_.range_first.begin(), ps_.range_first.end(), p) - ps_.range_first.begin() - 1);
  };
  ps_.cross_into_range.assign(ranges + 1, 0);
  ps_.records_upto.resize(ranges);
  ps_.records_from.resize(ranges);
  ps_.cross_from.resize(ranges);
  for (std::uint32_t r = 0; r < ranges; ++r) {
    ps_.records_upto[r] = ps_.cross_from[r] = r;
    ps_.records_from[r] = pairs.begin[ps_.range_first[r + 1]];
  }
  for (const std::uint32_t k : ps_.cross) {
    const std::uint32_t i = ps_.first[k], ri = range_of(i), rj = range_of(pairs.partner[k]);
    ++ps_.cross_into_range[rj + 1];
    ps_.records_upto[ri] = std::max(ps_.records_upto[ri], rj);
    ps_.cross_from[rj] = std::min(ps_.cross_from[rj], ri);
    ps_.records_from[ri] = std::min(ps_.records_from[ri], k);
  }
  for (std::uint32_t r = 0; r < ranges; ++r) ps_.cross_into_range[r + 1] += ps_.cross_into_range[r];
  ps_.cross_into.resize(ps_.cross.size());
  std::vector<std::uint32_t> fill(ps_.cross_into_range.begin(), ps_.cross_into_range.end() - 1);
  for (std::size_t c = 0; c < ps_.cross.size(); ++c)
    ps_.cross_into[fill[range_of(pairs.partner[ps_.cross[c]])]++] = static_cast<std::uint32_t>(c);
  cross_done_ = std::vector<CrossStamp>(ranges);
  progress_ = std::vector<RangeProgress>(ranges);
  ps_.rec.assign(2 * ps_.cross.size(), {Vec3::Zero(), Vec3::Zero()});
  ps_.rec_diss.assign(scene_.models.energy ? ps_.cross.size() : 0, Vec3::Zero());
}

// ---- 6. kick ------------------------------------------------------------------------------------
// Also checks that every velocity is a number (a diverged integration shows there first).
void Simulation::kick() {
  const double h = 0.5 * scene_.dt;
  const std::size_t n = p_.size();
  bool finite = true;
  if (defer_kick_) {
    finite = finished_finite_;  // the last step's kick, finished in kick_drift; this one's comes next step
  } else if (kick_balls_here()) {
    finite = balls_finite_ && finished_finite_;  // the balls were kicked in wall_contacts
  } else {
    with_flags(
        [&]<bool Rotation>() {
          auto one = [this, h](std::size_t i, bool& finite) BAGDEM_INLINE_LAMBDA {
            finite = kick_ball(i, p_.f[i], p_.t[i], h, Rotation) && finite;
          };
          for_ranges(balance_, n, finite, one, [](bool& a, bool b) { a = a && b; });
        },
        scene_.models.rotation);
  }
  const std::size_t nn = film_.size();
  finite = parallel_fold(nn, finite, [&](std::size_t k) {
    film_.v[k] += h * film_.inv_mass[k] * film_.f[k];
    return std::isfinite(film_.v[k].squaredNorm());
  }, [](bool a, bool b) { return a && b; });
  if (couple_) {
    structure_kick();
    for (double v : structure_.v) finite = finite && std::isfinite(v);
  }
  all_finite_ = finite;
  kick_pending_ = defer_kick_;
}

}  // namespace bagdem
