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
// second order. Also finds the largest step a ball took (Neighbours::travel, end_drift).
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
        vi = vi + dv;  // the last step's kick (Balls::kick's operations on the same force)
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


// The drift over balls [b0, b1) for the scene's models (Finish: the last step's kick first).
using DriftSpan = void (*)(const Scene& scene, Balls& state, std::size_t b0, std::size_t b1, StageFold& fold);
DriftSpan drift_span_for(const Scene& scene, bool finish) {
  DriftSpan span = nullptr;
  with_flags([&span]<bool Finish, bool Rotation, bool Gravity, bool Energy>() { span = &drift_span<Finish, Rotation, Gravity, Energy>; },
             finish, scene.models.rotation, scene.models.gravity, scene.models.energy);
  return span;
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

void end_drift(const StageFold& fold, const Balls& balls, double skin, Neighbours& nb, GuardValues& guard) {
  guard.finished_finite = fold.finished_finite;
  nb.end_drift(fold.step2, balls.x, skin);
}

void kick_drift_stage(const DriftStage& s) {
  const Scene& scene = s.scene;
  if (s.ctx.balls != BallKick::drifted) {
    const DriftSpan span = drift_span_for(scene, s.ctx.balls == BallKick::pending);
    StageFold fold;
    Balls& balls = s.balls;
    for_range_spans(s.balance, balls.size(), fold, [span, &scene, &balls](std::size_t b0, std::size_t b1, StageFold& f) { span(scene, balls, b0, b1, f); },
                    [](StageFold& a, const StageFold& b) { a.merge(b); });
    end_drift(fold, balls, scene.skin, s.nb, s.guard);
  }
  s.ctx.balls = BallKick::due;
  const double node_step2 = s.film.drift(scene.dt);
  if (!s.surfaces.wake.empty()) {
    // Rounded up as the balls' travel is (Neighbours::end_drift): never short of the true distances.
    s.surfaces.travel = std::nextafter(s.surfaces.travel + (s.nb.largest_step + std::sqrt(node_step2)) * (1.0 + 1e-14), HUGE_VAL);
  }
  if (s.structure.couple) s.structure.drift(scene.dt);
}


// ---- kick ----------------------------------------------------------------------------------------
// Also checks that every velocity is a number (a diverged integration shows there first).
void kick_stage(const KickStage& s) {
  const Scene& scene = s.scene;
  const double h = 0.5 * scene.dt;
  Balls& balls = s.balls;
  bool finite = true;
  if (s.ctx.defer_kick) {
    finite = s.guard.finished_finite;  // the last step's kick, finished in kick_drift; this one's comes next step
  } else if (s.kicked_in_walls) {
    finite = s.guard.balls_finite && s.guard.finished_finite;  // the balls were kicked in the wall stage
  } else {
    with_flags(
        [&]<bool Rotation>() {
          auto one = [&balls, h](std::size_t i, bool& finite) BAGDEM_INLINE_LAMBDA {
            finite = balls.kick(i, balls.f[i], balls.t[i], h, Rotation) && finite;
          };
          for_ranges(s.balance, balls.size(), finite, one, [](bool& a, bool b) { a = a && b; });
        },
        scene.models.rotation);
  }
  finite = s.film.kick(scene.dt) && finite;
  if (s.structure.couple) {
    s.structure.kick(scene.dt);
    for (double v : s.structure.v) finite = finite && std::isfinite(v);
  }
  s.guard.all_finite = finite;
  if (s.ctx.balls != BallKick::drifted) s.ctx.balls = s.ctx.defer_kick ? BallKick::pending : BallKick::due;
}

}  // namespace bagdem
