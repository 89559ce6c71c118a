// The balls' integration (stages kick_drift and kick, stage.hpp): velocity Verlet's two half
// kicks and the drift, with the film nodes' and the structure's, and the skin check that decides
// when the pair list is renewed.
#include <omp.h>

#include <algorithm>
#include <cmath>

#include "loops.hpp"
#include "stepper.hpp"

namespace bagdem {

// ---- kick_drift ---------------------------------------------------------------------------------
// Also predicts the end-of-step velocities the contact law uses, v(n+1/2) + dt/2 F(n)/m: with the
// half-step velocity alone (as LAMMPS and LIGGGHTS do) the damping force lags by dt/2, a first-order
// error in the restitution (-26% at e = 0.01 with 40 steps per contact); the prediction makes it
// second order. Also finds the largest step a ball took (nb_.travel; end_drift).
namespace {
template <bool Finish, bool Rotation, bool Gravity, bool Energy>
void drift_span(const Scene& scene, Balls& state, std::size_t b0, std::size_t b1, StageFold& fold) {
  const double dt = scene.dt, h = 0.5 * dt;
  const Vec3 g = scene.gravity;
  // The arrays and the folds in locals, and every ball's values read before any is written: the
  // compiler then keeps them in registers (through the members, each store would make it reload
  // them, as a store may alias).
  Vec3 *x = state.x.data(), *v = state.v.data(), *w = state.w.data(), *v_pred = state.v_pred.data(), *w_pred = state.w_pred.data();
  Vec3 *f = state.f.data(), *t = state.t.data(), *diss = state.tally.step_dissipation.data();
  const double *mass = state.mass.data(), *inv_mass = state.inv_mass.data(), *inv_inertia = state.inv_inertia.data();
  bool finite = fold.finished_finite;
  double step2 = fold.step2;
  // Balls all alike (state.uniform): their mass and inertia are the first ball's (the same values, so
  // the same results), and the loop reads three arrays fewer.
  auto balls = [&](auto mass_of, auto inv_mass_of, auto inv_inertia_of) BAGDEM_INLINE_LAMBDA {
    for (std::size_t i = b0; i < b1; ++i) {
      const Vec3 dv = h * inv_mass_of(i) * f[i];
      const Vec3 x0 = x[i];
      Vec3 vi = v[i];
      if constexpr (Finish) {
        vi = vi + dv;  // the last step's kick (kick_ball's operations on the same force)
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
  if (state.uniform) {
    const double m = mass[0], im = inv_mass[0], ii = inv_inertia[0];
    balls([m](std::size_t) { return m; }, [im](std::size_t) { return im; }, [ii](std::size_t) { return ii; });
  } else {
    balls([mass](std::size_t i) { return mass[i]; }, [inv_mass](std::size_t i) { return inv_mass[i]; },
          [inv_inertia](std::size_t i) { return inv_inertia[i]; });
  }
  fold.finished_finite = finite, fold.step2 = step2;
}
}  // namespace

// The span the threads' schedules run (BallSpan).
template <bool Finish, bool Rotation, bool Gravity, bool Energy>
void Stepper::drift_span(std::size_t b0, std::size_t b1, const WallMotion&, StageFold& fold) {
  bagdem::drift_span<Finish, Rotation, Gravity, Energy>(scene_, p_, b0, b1, fold);
}

Stepper::BallSpan Stepper::drift_stage(bool finish) const {
  BallSpan span = nullptr;
  with_flags([&span]<bool Finish, bool Rotation, bool Gravity, bool Energy>() { span = &Stepper::drift_span<Finish, Rotation, Gravity, Energy>; },
             finish, scene_.models.rotation, scene_.models.gravity, scene_.models.energy);
  return span;
}

void Stepper::over_balls(BallSpan span, StageFold& fold) {
  const WallMotion cavity = rigid_motion();
  for_range_spans(balance_, p_.size(), fold, [this, span, &cavity](std::size_t b0, std::size_t b1, StageFold& f) { (this->*span)(b0, b1, cavity, f); },
                  [](StageFold& a, const StageFold& b) { a.merge(b); });
}

void StageFold::merge(const StageFold& o) {
  excess = std::max(excess, o.excess);
  min_dist = std::min(min_dist, o.min_dist);
  kicked_finite = kicked_finite && o.kicked_finite;
  step2 = std::max(step2, o.step2);
  finished_finite = finished_finite && o.finished_finite;
}

void Stepper::end_drift(const StageFold& fold) {
  guard_.finished_finite = fold.finished_finite;
  nb_.largest_step = std::sqrt(fold.step2);
  // Rounded up twice over (the square root and the sum): nb_.travel never falls short of the true
  // sum of the steps, which the pair stage's skipping relies on (PairState::wake).
  nb_.travel = std::nextafter(nb_.travel + nb_.largest_step * (1.0 + 1e-14), HUGE_VAL);
  // The list is renewed a step ahead (kSkinStep): before the pairs at these positions when a ball
  // was near the skin's edge at the last ones.
  nb_.needs_rebuild = nb_.near_edge;
  nb_.near_edge = nb_.travel > nb_.far_check_at && near_skin_edge();
}

// Whether a ball is more than skin/2 - kSkinStep x skin from where it was at the last build.
// Asked only when it could be (end_drift): a ball moved at most nb_.travel - t since nb_.travel was t,
// so after a check found them all within d of their place at the build, none can pass the edge
// before nb_.travel has grown by edge - d. The same steps rebuild as with the test at every step, and
// the drift does not read nb_.x_at_build. In the shaken PD-box bed the check runs a few times per
// rebuild (the slack shrinks by a fraction each time).
bool Stepper::near_skin_edge() {
  const Vec3 *x = p_.x.data(), *at_build = nb_.x_at_build.data();
  const double d2 = parallel_fold(p_.size(), 0.0, [=](std::size_t i) { return (x[i] - at_build[i]).squaredNorm(); },
                                  [](double a, double b) { return std::max(a, b); });
  return near_edge(d2, nb_.travel, nb_.far_check_at);
}

bool Stepper::near_edge(double d2, double travel, double& far) const {
  const double edge = (0.5 - kSkinStep) * scene_.skin;
  if (d2 > edge * edge) return true;
  // Rounded down by far more than the rounding of these few operations (1e-16 of skin).
  far = travel + (edge - std::nextafter(std::sqrt(d2), HUGE_VAL)) - 1e-12 * scene_.skin;
  return false;
}

void Stepper::kick_drift() {
  const double dt = scene_.dt;
  if (ctx_.balls != BallKick::drifted) {
    StageFold fold;
    over_balls(drift_stage(ctx_.balls == BallKick::pending), fold);
    end_drift(fold);
  }
  ctx_.balls = BallKick::due;
  const double node_step2 = film_.drift(dt);
  if (!mesh_.wake.empty()) {
    // Rounded up as nb_.travel is (end_drift): never short of the true distances.
    mesh_.travel = std::nextafter(mesh_.travel + (nb_.largest_step + std::sqrt(node_step2)) * (1.0 + 1e-14), HUGE_VAL);
  }
  if (structure_.couple) structure_.drift(scene_.dt);
}


// ---- kick ----------------------------------------------------------------------------------------
// Also checks that every velocity is a number (a diverged integration shows there first).
void Stepper::kick() {
  const double h = 0.5 * scene_.dt;
  const std::size_t n = p_.size();
  bool finite = true;
  if (ctx_.defer_kick) {
    finite = guard_.finished_finite;  // the last step's kick, finished in kick_drift; this one's comes next step
  } else if (kick_balls_here()) {
    finite = guard_.balls_finite && guard_.finished_finite;  // the balls were kicked in wall_contacts
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
  finite = film_.kick(scene_.dt) && finite;
  if (structure_.couple) {
    structure_.kick(scene_.dt);
    for (double v : structure_.v) finite = finite && std::isfinite(v);
  }
  guard_.all_finite = finite;
  if (ctx_.balls != BallKick::drifted) ctx_.balls = ctx_.defer_kick ? BallKick::pending : BallKick::due;
}

}  // namespace bagdem
