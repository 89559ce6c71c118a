// The walls stage (stage.hpp): the balls against the cavity's walls (planes, cylinders), in batches of
// contacts through the same lane-wise law as the pairs (pair_kernel.hpp), with the balls' kick
// where no later stage adds to their forces. Each configuration of the model switches is compiled
// as its own loop (with_flags).
#include "stepper.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "bagdem/contact/surface_law.hpp"
#include "loops.hpp"

namespace bagdem {

// ---- wall_contacts ---------------------------------------------------------------------------
void Stepper::wall_contacts() {
  StageFold fold;
  fold.excess = guard_.overlap_excess;  // the pair stage's
  over_balls(wall_stage(), fold);
  end_walls(fold);
}

Stepper::BallSpan Stepper::wall_stage() const {
  BallSpan span = nullptr;
  with_flags([&span]<bool T, bool R, bool E>() { span = &Stepper::wall_span<T, R, E>; }, scene_.models.tangential,
             scene_.models.rolling, scene_.models.energy);
  return span;
}

void Stepper::end_walls(const StageFold& fold) {
  guard_.overlap_excess = fold.excess;
  guard_.min_boundary_distance = fold.min_dist;
  guard_.balls_finite = fold.kicked_finite;
}

namespace {

// The walls stage's work on a span of balls. A ball whose wall contacts are closed waits in `held`
// while the law runs on the contacts of a batch of balls, kLanes at a time (surface_contact_lanes);
// the others are done at once. Each ball's sums are then added in wall order, as one contact at a
// time adds them, so the results are the same bits (a lane gives the scalar law's bits,
// ContactLanes). Every piece is inlined into wall_span.
template <bool Tangential, bool Rolling, bool Energy>
struct WallKernel {
  static constexpr std::size_t kBatch = 64;  // wall contacts per batch
  struct Held {
    Vec3 F, T, diss, x_local, c_step;
    double d_min, d_bounds;
    std::uint32_t p, touched, end;  // end: one past its last contact in the batch
  };
  struct alignas(32) Contact {
    double row[4][4];  // (n, overlap), (v_rel, R*), (v_half, m*), (w_half, arm_i): the law's geometry
    double d;          // the centre's distance from the wall
    std::size_t slot;  // wall_slot(p, w): its histories
    const PairLaw* law;
  };
  struct alignas(32) Out {
    double F[4], nxFt[4], roll[4], diss[4];
  };

  // The view's components, held directly (one indirection fewer per access than through the view).
  const Scene& scene;
  const CavityFrame& frame;
  Balls& balls;
  WallContacts& walls;
  std::vector<Vec3>& cavity_load;
  const bool couple, tilt;  // the structure feels the load; the cavity follows its slope
  const std::size_t nballs;
  const WallMotion& rigid;  // the walls' motion over the step (per ball with a slope: motion_at)
  StageFold& ext;
  const double dt, frac, h;
  const Vec3 lo, hi;  // the cavity's bounds
  const PairLawTable& laws;
  // The kick stage's kick of the balls, done here while the ball's force and torque are at hand
  // when no later stage adds to them (kick_balls_here; the same operations as kick()).
  const bool kick, rotation;
  Held held[kBatch];
  Contact list[kBatch];
  Out out[kBatch + kLanes];
  std::size_t nh = 0, nc = 0;

  WallKernel(const WallStage& st, const WallMotion& motion, StageFold& fold)
      : scene(st.scene), frame(st.frame), balls(st.balls), walls(st.walls), cavity_load(st.cavity_load),
        couple(st.frame.structure.couple), tilt(st.frame.structure.tilt), nballs(st.balls.size()), rigid(motion), ext(fold), dt(st.ctx.dt), frac(st.scene.max_overlap_fraction), h(0.5 * st.ctx.dt),
        lo(st.scene.cavity_lo), hi(st.scene.cavity_hi), laws(st.scene.laws), kick(st.kick), rotation(st.scene.models.rotation) {}

  // The rest of ball b's wall stage, once its wall contacts are in b.F, b.T and b.diss: F_wall and
  // T_cavity are their force on the ball and torque on the cavity, load their load_moments.
  BAGDEM_INLINE void complete(const Held& b, const Vec3& F_wall, const Vec3& T_cavity, const Vec3& load) {
    const std::size_t p = b.p;
    const Vec3 &F = b.F, &T = b.T;
    if (couple) cavity_load[p] = load;
    balls.f[p] = F;
    balls.t[p] = T;
    walls.touch[p] = b.touched;
    ext.min_dist = std::min({ext.min_dist, b.d_min, b.d_bounds});
    ext.excess = std::max(ext.excess, balls.radius[p] - b.d_min - frac * balls.radius[p]);  // the deepest wall contact
    if (kick) ext.kicked_finite = balls.kick(p, F, T, h, rotation) && ext.kicked_finite;
    // Tallies: the load on the cavity (always) and the energy budget (when asked). A ball with no
    // wall contact adds zero to its impulses (a sum that starts at +0 is never -0, so adding +0
    // changes no bit): skipped, as for the balls far from the walls.
    if (b.touched != 0) {
      balls.tally.wall_impulse[p] -= dt * F_wall;
      balls.tally.wall_ang_impulse[p] += dt * T_cavity;
    }
    if constexpr (Energy) {
      // Work of the walls on the contents: trapezoidal rule over the cavity's displacement.
      balls.tally.work_cavity[p] += 0.5 * (F_wall + balls.tally.wall_force_prev[p]).dot(b.c_step);
      balls.tally.wall_force_prev[p] = F_wall;
      balls.tally.diss_normal[p] += b.diss.x();
      balls.tally.diss_tangential[p] += b.diss.y();
      balls.tally.diss_rolling[p] += b.diss.z();
    }
  }

  // The law on the batch's contacts, then the held balls done.
  BAGDEM_INLINE void flush() {
    for (std::size_t a = 0; a < nc; a += kLanes) {
      const Contact* e[kLanes];
      for (std::size_t l = 0; l < kLanes; ++l) e[l] = &list[std::min(a + l, nc - 1)];
      ContactGeometryT<Lanes> g;
      const double* rows[kLanes];
      auto load_row = [&](int r, Lanes3& v, Lanes& w) BAGDEM_INLINE_LAMBDA {
        for (std::size_t l = 0; l < kLanes; ++l) rows[l] = e[l]->row[r];
        gather4(rows, v, w);
      };
      load_row(0, g.n, g.overlap);
      load_row(1, g.v_rel, g.R_eff);
      load_row(2, g.v_half, g.m_eff);
      load_row(3, g.w_half, g.arm_i);
      g.arm_j = splat<Lanes>(0);
      double* damping[kLanes];
      TangentialHistory* th[kLanes];
      RollingHistory* rh[kLanes];
      for (std::size_t l = 0; l < kLanes; ++l) {
        damping[l] = Energy ? &walls.hist.damping_prev[e[l]->slot] : nullptr;
        th[l] = Tangential ? &walls.hist.tangential[e[l]->slot] : nullptr;
        rh[l] = Rolling ? &walls.hist.rolling[e[l]->slot] : nullptr;
      }
      auto with_law = [&](const auto& law) BAGDEM_INLINE_LAMBDA {
        const SurfaceLanes c = surface_contact_lanes<Tangential, Rolling, Energy>(g, law, dt, damping, th, rh);
        Out* o = out + a;
        auto rows_of = [o](double (Out::*m)[4]) BAGDEM_INLINE_LAMBDA {
          return std::array<double*, kLanes>{o[0].*m, o[1].*m, o[2].*m, o[3].*m};
        };
        to_rows(c.F, splat<Lanes>(0), rows_of(&Out::F).data());
        if constexpr (Tangential) to_rows(c.nxFt, splat<Lanes>(0), rows_of(&Out::nxFt).data());
        if constexpr (Rolling) to_rows(c.roll, splat<Lanes>(0), rows_of(&Out::roll).data());
        if constexpr (Energy) to_rows(c.diss, splat<Lanes>(0), rows_of(&Out::diss).data());
      };
      if (e[0]->law == e[1]->law && e[0]->law == e[2]->law && e[0]->law == e[3]->law) {
        with_law(*e[0]->law);
      } else {
        const PairLaw* four[kLanes] = {e[0]->law, e[1]->law, e[2]->law, e[3]->law};
        with_law(four);
      }
    }
    auto vec = [](const double* row) BAGDEM_INLINE_LAMBDA { return Vec3(row[0], row[1], row[2]); };
    for (std::size_t k = 0, c = 0; k < nh; ++k) {
      Held& b = held[k];
      Vec3 F_wall(0, 0, 0), T_cavity(0, 0, 0), load(0, 0, 0);
      for (; c < b.end; ++c) {
        // As surface_contact adds them: F, then -arm_i (n x F_t) and the rolling torque to T.
        const Contact& ct = list[c];
        const Vec3 Fc = vec(out[c].F);
        if constexpr (Tangential) b.T -= ct.row[3][3] * vec(out[c].nxFt);
        if constexpr (Rolling) b.T += vec(out[c].roll);
        if constexpr (Energy) b.diss += vec(out[c].diss);
        b.F += Fc;
        F_wall += Fc;
        // Torque on the cavity about its reference point, from the contact point on the wall.
        const Vec3 at = b.x_local - ct.d * vec(ct.row[0]);
        T_cavity -= cross(Vec3(at - scene.cavity_reference), Fc);
        if (couple) load += frame.load_moments(at, -Fc);
      }
      complete(b, F_wall, T_cavity, load);
    }
    nh = nc = 0;
  }

  BAGDEM_INLINE void fetch_ball(std::size_t p) const {
    for (const Vec3* a : {&balls.x[p], &balls.v[p], &balls.w[p], &balls.f[p], &balls.t[p]}) prefetch_object(a);
    prefetch_object(&walls.near[p]);
  }

  BAGDEM_INLINE void ball(std::size_t p) {
    // Gravity (kick_drift) and the pairs (pair_contacts).
    Vec3 F = balls.f[p];
    Vec3 T = balls.t[p];
    [[maybe_unused]] Vec3 diss(0, 0, 0);
    if constexpr (Energy) diss = balls.tally.step_dissipation[p];

    // Walls: the pair law with R_j = m_j = infinity; the wall moves with the cavity.
    const WallMotion wm = tilt ? frame.at(balls.x[p]) : rigid;
    const Vec3 &c_vel = wm.vel, &c_half = wm.half;  // c_half: mean over the step
    const Vec3 x_local = balls.x[p] - wm.pos;
    const double r = balls.radius[p];
    // The cavity's bounds: a centre outside them has left the cavity (for "planes" cavities the
    // planes need not enclose anything).
    const double d_bounds = std::min((x_local - lo).minCoeff(), (hi - x_local).minCoeff());
    const std::uint32_t near = walls.near[p];
    if (near == 0) {
      // No wall can touch this ball (find_near_walls): only the sums and the bounds. What it adds
      // to its tallies this step is zero and is skipped (its last wall force was zero too).
      if (couple) cavity_load[p].setZero();
      if constexpr (Energy) {
        balls.tally.diss_normal[p] += diss.x();
        balls.tally.diss_tangential[p] += diss.y();
        balls.tally.diss_rolling[p] += diss.z();
      }
      ext.min_dist = std::min(ext.min_dist, d_bounds);
      if (kick) ext.kicked_finite = balls.kick(p, F, T, h, rotation) && ext.kicked_finite;
      return;
    }
    if (nc + static_cast<std::size_t>(std::popcount(near)) > kBatch) flush();
    double d_min = 1e300;  // nearest wall
    const std::uint32_t touched_before = walls.touch[p];
    std::uint32_t touched = 0;
    const std::size_t first = nc;
    for (std::uint32_t bits = near; bits != 0; bits &= bits - 1) {
      const auto w = static_cast<std::size_t>(std::countr_zero(bits));
      const Wall& wall = scene.walls[w];
      ContactGeometry g;
      const double d = wall_distance(wall, x_local, g.n);
      d_min = std::min(d_min, d);
      g.overlap = r - d;
      if (g.overlap <= 0) {
        // A contact that just opened: tally what it still held, clear its history (walls not
        // touched cost no memory access).
        if (touched_before & (1u << w)) {
          const Vec3 d = walls.hist.open<Tangential, Rolling, Energy>(walls.slot(p, w, nballs), dt, [&] {
            return OpeningMotion{g.n, balls.v[p] - c_half - r * balls.w[p].cross(g.n), balls.w[p]};
          });
          if constexpr (Energy) diss += d;
        }
        continue;
      }
      touched |= 1u << w;
      g.R_eff = wall_effective_radius(wall, r);
      g.m_eff = balls.mass[p];
      g.arm_i = r - 0.5 * g.overlap;
      g.arm_j = 0;
      // The wall's velocity at the end of the step is exact (prescribed); at the half step it is
      // the mean over the step.
      balls.motion_against_surface<Tangential || Rolling>(p, c_vel, c_half, g);
      Contact& ct = list[nc++];
      auto put = [&ct](int r, const Vec3& v, double w) BAGDEM_INLINE_LAMBDA {
        ct.row[r][0] = v.x(), ct.row[r][1] = v.y(), ct.row[r][2] = v.z(), ct.row[r][3] = w;
      };
      put(0, g.n, g.overlap);
      put(1, g.v_rel, g.R_eff);
      put(2, g.v_half, g.m_eff);
      put(3, g.w_half, g.arm_i);
      ct.d = d;
      ct.slot = walls.slot(p, w, nballs);
      // Its histories fetched now, to be in cache when the batch's law reads them (flush).
      if constexpr (Tangential) prefetch_object(&walls.hist.tangential[ct.slot], kTangentialBytes<Energy>);
      if constexpr (Rolling) prefetch_object(&walls.hist.rolling[ct.slot]);
      ct.law = &laws(balls.material[p], wall.material);
    }
    const Held b{F, T, diss, x_local, wm.step, d_min, d_bounds, static_cast<std::uint32_t>(p), touched, static_cast<std::uint32_t>(nc)};
    if (nc == first) {
      const Vec3 zero(0, 0, 0);
      complete(b, zero, zero, zero);  // no wall contact closed
    } else {
      held[nh++] = b;
    }
  }
};

// Balls [b0, b1) against the walls: the walls stage's work, a free function of its view.
template <bool Tangential, bool Rolling, bool Energy>
void wall_span(const WallStage& st, std::size_t b0, std::size_t b1, const WallMotion& rigid, StageFold& ext) {
  WallKernel<Tangential, Rolling, Energy> kernel(st, rigid, ext);
  // In advance, a ball with no wall or bound near has nothing to do here: its kick is deferred, its
  // sums stay in its force and torque, and its tallies are zero (Energy tallies its pair dissipation here).
  const std::vector<std::uint32_t>& near = st.walls.near_balls;
  if (st.ctx.defer_kick && !Energy) {
    const auto* it = std::lower_bound(near.data(), near.data() + near.size(), b0);
    // The near balls are a sparse subset, whose state the hardware prefetchers do not follow:
    // the state of the ball kAhead places on is fetched while this one is done.
    constexpr std::ptrdiff_t kAhead = 8;
    const auto* end = near.data() + near.size();
    for (; it != end && *it < b1; ++it) {
      if (end - it > kAhead) kernel.fetch_ball(it[kAhead]);
      kernel.ball(*it);
    }
  } else {
    for (std::size_t p = b0; p < b1; ++p) kernel.ball(p);
  }
  kernel.flush();
}

}  // namespace

// The span the threads' schedules run (BallSpan): the view of this step, then the work.
template <bool Tangential, bool Rolling, bool Energy>
void Stepper::wall_span(std::size_t b0, std::size_t b1, const WallMotion& rigid, StageFold& ext) {
  const CavityFrame f = frame();
  bagdem::wall_span<Tangential, Rolling, Energy>({ctx_, scene_, f, p_, walls_, structure_.cavity_load, kick_balls_here() && !ctx_.defer_kick},
                                                 b0, b1, rigid, ext);
}

}  // namespace bagdem
