// Physics of the bag (docs/reference-study.md, section 6; docs/case-schema.md [bag]): energy budget with the
// film and strings, the bag's restitution against a single ball's, the strings (static extension,
// tension only), balls kept inside under strong shaking, and the ball-film law reducing to the
// ball-wall law for a stiff, heavy film (the film-crossing guard: test_bag_guard.cpp).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "bag_support.hpp"
#include "bagdem/run/bag_report.hpp"
#include "bagdem/io/bag_file.hpp"
#include "bagdem/contact/hertz.hpp"
#include "bagdem/contact/sphere_triangle.hpp"
#include "bagdem/error.hpp"

using namespace bagdem;
using namespace bagdem::testing;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Softened steel (2 GPa) balls of 4 mm (40) in an LDPE film bag (50 um, 200 triangles, capsule of
// radius 7 mm, 36 mm long) tied by two soft strings (20 N/m, head and tail) to the end walls of a
// box shaken along the bag's axis (2 mm, 40 Hz: 13 g; 0.5 mm of clearance at each end, so the bag
// hits the end walls), gravity on (the bag falls 5 mm onto the floor first); 75 ms = 3 cycles.
std::string shaken_bag_toml(double restitution, double friction, double film_damping, double string_damping) {
  return bag_scene("0.075 s", 3)
      .interactions(restitution, friction)
      .box("steel", vec("-18.5 mm", "-12 mm", "-12 mm"), vec("18.5 mm", "12 mm", "12 mm"))
      .harmonic("2 mm", "40 Hz", "[1, 0, 0]")
      .capsule_bag("7 mm", 200, 40)
      .set("bag.film", "damping_ratio", film_damping)
      .bag_string("tail", vec("-18.5 mm", 0, 0), "20 N/m", string_damping)
      .bag_string("head", vec("18.5 mm", 0, 0), "20 N/m", string_damping);
}

struct BudgetRun {
  double max_residual = 0;   // max over samples of |W_in - dE - D| (unit: J)
  double max_scale = 0;      // max over samples of the balance scale (unit: J)
  double final_error = 0;    // the run loop's balance_error at the end
  EnergySample end;
  std::size_t end_wall_steps = 0, floor_steps = 0;  // steps with a film node on an end wall / the floor
  std::uint64_t steps = 0;
  double wall_s = 0;
};

BudgetRun run_budget(const Scene& s) {
  const auto t0 = std::chrono::steady_clock::now();
  Simulation sim(s);
  BudgetRun r;
  const double stored0 = sim.initial_stored_energy();
  const double reach = 0.5 * s.bag->film.thickness;
  r.steps = s.total_steps();
  for (std::uint64_t k = 1; k <= r.steps; ++k) {
    sim.step();
    bool end = false, floor = false;
    const Vec3 c = sim.cavity().position;
    for (const Vec3& x : sim.film().x) {
      const Vec3 l = x - c;
      end = end || l.x() > s.cavity_hi.x() - reach || l.x() < s.cavity_lo.x() + reach;
      floor = floor || l.z() < s.cavity_lo.z() + reach;
    }
    r.end_wall_steps += end;
    r.floor_steps += floor;
    if (k % 100 == 0 || k == r.steps) {
      const Balance b = energy_balance(sim.energy(), stored0);
      r.max_residual = std::max(r.max_residual, std::abs(b.residual));
      r.max_scale = std::max(r.max_scale, b.scale);
    }
  }
  r.end = sim.energy();
  r.final_error = energy_balance(r.end, stored0).relative();
  r.wall_s = seconds_since(t0);
  return r;
}

}  // namespace

// Energy budget of a bag (film kinetic and elastic energy, strings, film-wall and ball-film
// contacts): W_cavity + W_gravity = (K + U) - (K0 + U0) + D, as the run loop checks it
// (runner.cpp balance_error). Reference: exact closure of velocity Verlet's discrete work tallies
// (docs/contact-model.md, Energy budget), ~1e-4 on the default case. Measure: the largest residual over samples
// every 100 steps divided by the largest scale over the run, and the final balance_error.
// Undamped (the check): every restitution 1, no friction, no film damping, no string
// damping, linear membrane (tension field off).
void expect_undamped_budget(bool tension_field, double tolerance, const std::string& timestep = "\"auto\"") {
  LoadedCase c(shaken_bag_toml(1.0, 0.0, 0.0, 0.0),
               {"bag.film.tension_field=" + std::string(tension_field ? "true" : "false"), "simulation.timestep=" + timestep});
  ASSERT_TRUE(c.scene.bag);
  ASSERT_EQ(c.scene.bag->film.tension_field, tension_field);
  const BudgetRun r = run_budget(c.scene);
  std::printf("BagEnergy: undamped, tension field %s: %llu steps, dt %.3g s, %.2f s wall; max residual %.3e J / max "
              "scale %.3e J = %.3e; final balance_error %.3e; W_cavity %.3e W_gravity %.3e K %.3e U %.3e D %.3e; steps "
              "with film on an end wall %zu, on the floor %zu\n",
              tension_field ? "on" : "off", static_cast<unsigned long long>(r.steps), c.scene.dt, r.wall_s, r.max_residual,
              r.max_scale, r.max_residual / r.max_scale, r.final_error, r.end.work_cavity, r.end.work_gravity,
              r.end.kinetic, r.end.elastic, r.end.dissipated(), r.end_wall_steps, r.floor_steps);
  EXPECT_GT(r.end_wall_steps, 0u) << "the bag never hit an end wall: the scene does not test impacts";
  EXPECT_GT(r.floor_steps, 0u);
  EXPECT_EQ(r.end.dissipated(), 0.0) << "nothing may dissipate without damping and friction";
  EXPECT_LT(r.max_residual / r.max_scale, tolerance);
  EXPECT_LT(r.final_error, tolerance);
}

// Measured (auto step 8.2e-7 s; docs/bag.md): 2.8e-3. The residual depends on the trajectory
// (which film-wall impacts happen): seeds 1-5 gave 2.3e-4 to 2.8e-3 of the scale. Tolerance 3e-3.
TEST(BagEnergy, BudgetClosesUndamped) { expect_undamped_budget(false, 3e-3); }

// With the tension field on (the default), the membrane's energy is only once differentiable where
// a triangle passes between slack, wrinkled and taut, which an undamped film at rest does all the
// time (its stress-free state lies on the slack boundary). Measured: 4.6e-4 at the auto step (8.2e-7
// s), 2.2e-5 at 2e-7 s. Counting the ball-film contacts' energy per contact (the joined patches
// before the Euler sum, surface_features.hpp) left a floor of 0.4e-3 to 1.2e-3 at 2e-7 s over seeds
// 1-5, lost where a valley's hit was dropped. Tolerances 5e-3 and 2e-4.
TEST(BagEnergy, BudgetWithTensionFieldCloses) {
  expect_undamped_budget(true, 5e-3);
  expect_undamped_budget(true, 2e-4, "\"0.2 us\"");
}

// Same scene with damping and friction everywhere: e = 0.5, mu = 0.3, film damping ratio 0.05,
// string damping 0.05 N s/m, tension field on, auto step. Measured: 9.8e-4 (8.6e-4 keeping only a
// patch's deepest hit); tolerance 5e-3.
TEST(BagEnergy, BudgetClosesWithDampingAndFriction) {
  LoadedCase c(shaken_bag_toml(0.5, 0.3, 0.05, 0.05));
  const BudgetRun r = run_budget(c.scene);
  std::printf("BagEnergy: damped: %llu steps, dt %.3g s, %.2f s wall; max residual %.3e J / max scale %.3e J = %.3e; "
              "final balance_error %.3e; W_cavity %.3e W_gravity %.3e K %.3e U %.3e D %.3e (normal %.3e tangential "
              "%.3e damping %.3e); steps with film on an end wall %zu, on the floor %zu\n",
              static_cast<unsigned long long>(r.steps), c.scene.dt, r.wall_s, r.max_residual, r.max_scale,
              r.max_residual / r.max_scale, r.final_error, r.end.work_cavity, r.end.work_gravity, r.end.kinetic,
              r.end.elastic, r.end.dissipated(), r.end.dissipated_normal, r.end.dissipated_tangential,
              r.end.dissipated_damping, r.end_wall_steps, r.floor_steps);
  EXPECT_GT(r.end_wall_steps, 0u);
  EXPECT_GT(r.end.dissipated_damping, 0.0);
  EXPECT_GT(r.end.dissipated_tangential, 0.0);
  EXPECT_LT(r.max_residual / r.max_scale, 5e-3);
  EXPECT_LT(r.final_error, 5e-3);
}


namespace {

// A box 60 x 40 x 60 mm (floor at z = 0) with steel (2 GPa) walls; `contents` adds the bag or the
// single ball (added by the caller). Every pair has restitution `e` and friction 0.3.
CaseText drop_toml(double e) {
  return bag_scene("0.1 s", 5)
      .interactions(e, 0.3)
      .box("steel", vec("-30 mm", "-20 mm", 0), vec("30 mm", "20 mm", "60 mm"));
}

struct Bounce {
  double v_down = 0, v_up = 0;  // downward speed just before the first impact, largest upward speed after (unit: m/s)
  double t_impact = 0;
};

struct DropResult {
  Bounce bag, ball;
  double dt = 0, wall_s = 0;
  std::size_t balls_on_floor_max = 0;  // most bag balls at once whose centre is nearer the floor than their radius
  std::size_t outside_at_worst = 0;    // balls_outside_bag() at that moment
  double deepest = 0;                  // largest (radius - centre height) of a bag ball (unit: m)
  double e_bag() const { return bag.v_up / bag.v_down; }
  double e_ball() const { return ball.v_up / ball.v_down; }
};

// The drop of a settled bag of 50 balls (4 mm, 2 GPa steel, LDPE film of 50 um, 200 triangles,
// damping ratio 0.05) from 9.8 mm above the floor of a box, no strings, and the drop of one ball
// from about the same height; measured e_bag = 0.037, e_ball = 0.80; every pair (ball-ball, ball-wall, ball-film, film-wall) has e = 0.8, mu 0.3.
// Run once, shared by the BagDrop tests.
const DropResult& drop_result() {
  static const DropResult r = [] {
    DropResult out;
    const double e = 0.8;
    // A bean bag is a settled pack: the bag first settles for 60 ms on the floor (its bottom 0.2 mm
    // above it), is saved (bag.h5) and reloaded 9.8 mm higher (bag.from, bag.centre), then dropped.
    const std::string bag_drop = drop_toml(e).capsule_bag("7 mm", 200, 50);
    LoadedCase settle_case(bag_drop, {"bag.centre=[0, 0, 0.0072]"});
    Simulation settling(settle_case.scene);
    while (settling.time() < 0.06) settling.step();
    const std::string saved = (settle_case.dir.path / "bag.h5").string();
    save_bag(saved, saved_bag(settle_case.scene, settling));
    LoadedCase bag_case(bag_drop, {"bag.from=\"" + saved + "\"", "bag.centre=[0, 0, 0.017]"});
    const Scene& s = bag_case.scene;
    const Bag& bag = *s.bag;
    Simulation sim(s);
    out.dt = s.dt;
    const double reach = 0.5 * bag.film.thickness;
    auto film_on_floor = [&] {
      for (const Vec3& x : sim.film().x)
        if (x.z() - sim.cavity().position.z() < s.cavity_lo.z() + reach) return true;
      return false;
    };
    if (film_on_floor()) throw std::runtime_error("the bag starts on the floor");
    double vz_prev = bag_com(sim).v.z();
    const auto t0 = std::chrono::steady_clock::now();
    std::uint64_t impact_step = 0;
    const std::uint64_t window = static_cast<std::uint64_t>(0.04 / s.dt);
    for (std::uint64_t k = 1; k <= s.total_steps(); ++k) {
      sim.step();
      const double vz = bag_com(sim).v.z();
      if (impact_step == 0 && film_on_floor()) {
        impact_step = k;
        out.bag.v_down = -vz_prev;
        out.bag.t_impact = sim.time();
      } else if (impact_step > 0) {
        out.bag.v_up = std::max(out.bag.v_up, vz);
        std::size_t on_floor = 0;
        for (std::size_t i = bag.ball_first; i < bag.ball_first + bag.balls; ++i) {
          const double depth = sim.particles().radius[i] - (sim.particles().x[i].z() - sim.cavity().position.z() - s.cavity_lo.z());
          out.deepest = std::max(out.deepest, depth);
          on_floor += depth > 0;
        }
        if (on_floor > out.balls_on_floor_max) {
          out.balls_on_floor_max = on_floor;
          out.outside_at_worst = sim.balls_outside_bag().size();
        }
        if (k > impact_step + window) break;
      }
      vz_prev = vz;
    }
    if (impact_step == 0 || sim.steps_done() <= impact_step + window)
      throw std::runtime_error("the bag did not reach the floor in time for the rebound window");
    out.wall_s = seconds_since(t0);

    LoadedCase ball_case(drop_toml(e).placed("ball", "steel", "4 mm", "[" + vec(0, 0, "12 mm") + "]"));
    Simulation one(ball_case.scene);
    double v_prev = 0;
    bool touched = false;
    for (std::uint64_t k = 1; k <= ball_case.scene.total_steps(); ++k) {
      one.step();
      const double vz = one.particles().v[0].z();
      if (!touched && one.contact_count() > 0) {
        touched = true;
        out.ball.v_down = -v_prev;
        out.ball.t_impact = one.time();
      }
      if (touched) {
        out.ball.v_up = std::max(out.ball.v_up, vz);
        if (one.contact_count() == 0 && vz < out.ball.v_up) break;  // rising freely: the rebound is over
      }
      v_prev = vz;
    }
    if (!touched) throw std::runtime_error("the single ball never reached the floor");
    std::printf("BagDrop: bag (50 balls, dt %.3g s, %.2f s wall): first film-floor contact at t = %.4f s, v_down %.4f m/s, "
                "v_up %.4f m/s, e_bag = %.4f; single ball: v_down %.4f m/s, v_up %.4f m/s, e_ball = %.4f; e_bag / e_ball = "
                "%.3f; bag balls touching the floor directly: up to %zu at once (balls_outside_bag() then: %zu), deepest "
                "%.2f um into the floor\n",
                out.dt, out.wall_s, out.bag.t_impact, out.bag.v_down, out.bag.v_up, out.e_bag(), out.ball.v_down,
                out.ball.v_up, out.e_ball(), out.e_bag() / out.e_ball(), out.balls_on_floor_max, out.outside_at_worst,
                1e6 * out.deepest);
    return out;
  }();
  return r;
}

}  // namespace

// The bag's restitution against a single ball's (issue requirement: a bean bag bounces at most half
// as much as one of its balls). Scene: drop_result(). e_bag = largest upward velocity of the centre
// of mass (balls + film nodes, mass-weighted) within 40 ms after the first film-floor contact / its
// downward velocity at the step before; e_ball likewise for one ball from the same height.
// Requirement: e_bag <= 0.5 e_ball. Also checked: the bag's impact speed is the free-fall speed over
// 10 mm (sqrt(2 g h) = 0.443 m/s, +-0.02 m/s: the film's lowest node sags a little before the
// contact), and e_ball is the requested 0.8 within 2% (docs/contact-model.md: the restitution is returned within 1%).
// Measured (this build): v_down 0.442 m/s, v_up 0.265 m/s, e_bag = 0.598; e_ball = 0.801;
// e_bag / e_ball = 0.75: FAILS the requirement (the bag's balls hit the floor through the film
// together, see the next test).
// Requirement: e_bag <= e_ball / 2. (An unsettled bag, its balls still on their filling lattice,
// rebounds like a Newton's cradle: e_bag = 0.60 with e = 0.8; a settled bag is what a bean bag is.)
TEST(BagDrop, BagBouncesLessThanHalfAsMuchAsABall) {
  const DropResult& r = drop_result();
  EXPECT_NEAR(r.bag.v_down, std::sqrt(2 * 9.81 * 0.010), 0.02);
  EXPECT_NEAR(r.e_ball(), 0.8, 0.02 * 0.8);
  EXPECT_LE(r.e_bag(), 0.5 * r.e_ball()) << "e_bag = " << r.e_bag() << ", e_ball = " << r.e_ball();
}

// The film is between the bag's balls and the floor: a ball of the bag must not touch a cavity wall
// directly while it is inside the film (src/step/film.cpp: "what the balls feel through the film is
// the ball-film law"). Reference: a ball resting on the film on the floor has its centre r + t/2 +
// t/2 above the floor less the ball-film and film-floor overlaps; it may reach the floor only if
// those overlaps exceed the film thickness. Tolerance: no ball centre nearer the floor than its
// radius at any step of the impact (same scene as above). Measured: up to 11 balls at once reach
// the floor directly, 9.9 um deep (ball-steel law), while balls_outside_bag() is empty: FAILS.
// A design question, not settled: a ball pressing the 50 um film onto a wall reaches the wall (the
// film is then squashed through, as a real thin film is under a steel ball), so ball-wall contacts
// are kept for the bag's balls. Measured: up to 11 balls at once, 10 um deep. Disabled; kept as the
// probe for the BagDrop investigation.
TEST(BagDrop, BallsDoNotTouchTheFloorThroughTheFilm) {
  const DropResult& r = drop_result();
  EXPECT_EQ(r.balls_on_floor_max, 0u) << r.balls_on_floor_max << " balls of the bag (still inside the film: "
                                      << r.outside_at_worst << " outside) touched the floor directly, up to "
                                      << 1e6 * r.deepest << " um deep";
}

// The force on the cavity includes the film's: a bag settling on the floor of a fixed box presses
// on it through balls on the film and film nodes on the floor (film-wall contacts), and through
// balls reaching the floor through the film. Reference: the momentum balance of the contents,
// mean force on the cavity = M g - dP/dt over the window (P: momentum of balls and film nodes),
// which is about (0, 0, -M g) as the bag comes to rest. Tolerance 1% of M g (the impulse is
// tallied with the step's end forces, the velocities change with the mean of two steps' forces).
TEST(BagDrop, ForceOnTheCavityBalancesTheBagsMomentum) {
  LoadedCase c(drop_toml(0.8).capsule_bag("7 mm", 200, 50).set("bag", "centre", vec(0, 0, "7.2 mm")));
  Simulation sim(c.scene);
  auto momentum = [&] {
    Vec3 p(0, 0, 0);
    for (std::size_t i = 0; i < sim.particles().size(); ++i) p += sim.particles().mass[i] * sim.particles().v[i];
    for (std::size_t k = 0; k < sim.film().size(); ++k) p += sim.film().mass[k] * sim.film().v[k];
    return p;
  };
  while (sim.time() < 0.06) sim.step();
  sim.take_cavity_sample();  // the sums restart here
  const Vec3 p0 = momentum();
  const double t0 = sim.time();
  while (sim.time() < 0.08) sim.step();
  const CavitySample f = sim.take_cavity_sample();
  const double M = bag_mass(sim), weight = M * 9.81;
  const Vec3 expected = M * c.scene.gravity - (momentum() - p0) / (sim.time() - t0);
  std::printf("BagDrop: settling bag: mean force on the cavity (%.5g, %.5g, %.5g) N, M g - dP/dt (%.5g, %.5g, %.5g) N, "
              "weight %.5g N\n", f.force.x(), f.force.y(), f.force.z(), expected.x(), expected.y(), expected.z(), weight);
  EXPECT_LT((f.force - expected).norm(), 0.01 * weight);
  EXPECT_GT(-f.force.z(), 0.5 * weight);  // the bag does press on the floor
}

namespace {

// A capsule bag (40 balls of 4 mm, 2 GPa steel; LDPE film 50 um, 200 triangles) with its axis
// vertical, head up, hanging from one string tied at the head to the ceiling of a tall box
// (anchor ~8 mm above the head, rest length auto = the initial distance), gravity on, nothing else
// touching.
CaseText hanging_toml() {
  return bag_scene("0.12 s", 11)
      .box("steel", vec("-20 mm", "-20 mm", "-60 mm"), vec("20 mm", "20 mm", "25 mm"))
      .capsule_bag("7 mm", 200, 40)
      .set("bag", {{"axis", "[0, 0, 1]"}, {"centre", "[0, 0, 0]"}})
      .set("bag.film", {{"damping_ratio", 0.05}, {"mass_scaling", 3}})
      .add("bag.strings", {{"at", quoted("head")}, {"tie_radius", "4.5 mm"}, {"anchor", vec(0, 0, "25 mm")},
                           {"stiffness", "500 N/m"}, {"damping", "3 N s/m"}});
}

double string_length(const Simulation& sim, const BagString& st) {
  Vec3 c(0, 0, 0);
  for (std::uint32_t k : st.nodes) c += sim.film().x[k];
  c /= static_cast<double>(st.nodes.size());
  return (st.anchor + sim.cavity().position - c).norm();
}

}  // namespace

// Static extension of a string holding the whole bag: at rest the string's tension k (L - L0)
// carries the bag's weight, so L - L0 = M g / k with M = balls + film nodes (Simulation::film().mass,
// particle masses; film node masses x3 by bag.film.mass_scaling, a documented speed knob, which
// also makes the settle faster). String k = 500 N/m, damping 3 N s/m (damping ratio ~0.65 on the
// bag's vertical mode), tie radius 4.5 mm (6 nodes), film damping ratio 0.05, ball restitution 0.5
// and friction 0.3. The empty upper part of the bag collapses first (tension field: ~30 ms of free
// fall before the string takes the load), then the bag settles by ~0.1 s (measured: the 10 ms means
// of L - L0 are within 0.6% of M g / k from 0.09 s on). Measured: L - L0 averaged over the last
// 20 ms of the 120 ms run. Tolerance 2% of M g / k. Also: no wall is touched (the bag hangs free).
// Measured (this build): M g / k = 0.2091 mm, mean extension 0.2097 mm (+0.31%).
TEST(BagStrings, HangingBagStretchesTheStringByItsWeight) {
  LoadedCase c(hanging_toml());
  const Scene& s = c.scene;
  ASSERT_EQ(s.bag->strings.size(), 1u);
  const BagString& st = s.bag->strings[0];
  Simulation sim(s);
  const double M = bag_mass(sim);
  const double g = 9.81, expected = M * g / st.stiffness;
  const std::uint64_t steps = s.total_steps(), avg_from = steps - static_cast<std::uint64_t>(0.02 / s.dt);
  ASSERT_EQ(st.nodes.size(), 6u);
  const auto t0 = std::chrono::steady_clock::now();
  double sum = 0, lo = 1e300, hi = -1e300;
  std::uint64_t n = 0;
  bool touched_wall = false;
  const double reach = 0.5 * s.bag->film.thickness;
  for (std::uint64_t k = 1; k <= steps; ++k) {
    sim.step();
    if (k % 50 == 0)
      for (const Vec3& x : sim.film().x) {
        const Vec3 l = x - sim.cavity().position;
        touched_wall = touched_wall || (l - s.cavity_lo).minCoeff() < reach || (s.cavity_hi - l).minCoeff() < reach;
      }
    if (k > avg_from) {
      const double ext = string_length(sim, st) - st.rest_length;
      sum += ext;
      lo = std::min(lo, ext);
      hi = std::max(hi, ext);
      ++n;
    }
  }
  const double mean = sum / static_cast<double>(n);
  const double last = string_length(sim, st) - st.rest_length;
  std::printf("BagStrings: M = %.6g kg (film %.3g kg), k = %g N/m, M g / k = %.5g m; extension mean over the last 20 ms "
              "%.5g m (range %.5g .. %.5g), at the end %.5g m; error of the mean %.3f%%; %llu steps, dt %.3g s, %.2f s wall\n",
              M, M - [&] { double b = 0; for (std::size_t i = s.bag->ball_first; i < s.bag->ball_first + s.bag->balls; ++i) b += sim.particles().mass[i]; return b; }(),
              st.stiffness, expected, mean, lo, hi, last, 100 * (mean - expected) / expected,
              static_cast<unsigned long long>(steps), s.dt, seconds_since(t0));
  EXPECT_FALSE(touched_wall) << "the bag must hang free";
  EXPECT_NEAR(mean, expected, 0.02 * expected);
}

// A string never pushes: with its anchor nearer the tie than its rest length (here a second string
// tied at the tail, anchored at the bag's centre, rest length 40 mm, while the tail is ~18 mm from
// the centre) it exerts no force, so the run is identical to the run without it. Both runs use the
// same explicit time step (the auto step depends on the strings). Reference: exact equality of
// every ball and film node position and velocity after 6000 steps (a push of k (L - L0) ~ 11 N on
// the tail would move the bag at once).
TEST(BagStrings, SlackStringExertsNoForce) {
  const std::string slack = hanging_toml().add("bag.strings", {{"at", quoted("tail")}, {"tie_radius", "4.5 mm"}, {"anchor", "[0, 0, 0]"},
                                                                {"stiffness", "500 N/m"}, {"damping", "2 N s/m"},
                                                                {"rest_length", "40 mm"}});
  LoadedCase one(hanging_toml(), {"simulation.timestep=1.2e-6", "simulation.duration=0.0072"});
  LoadedCase two(slack, {"simulation.timestep=1.2e-6", "simulation.duration=0.0072"});
  ASSERT_EQ(two.scene.bag->strings.size(), 2u);
  const BagString& st = two.scene.bag->strings[1];
  Simulation a(one.scene), b(two.scene);
  double max_length = 0;
  for (std::uint64_t k = 1; k <= one.scene.total_steps(); ++k) {
    a.step();
    b.step();
    max_length = std::max(max_length, string_length(b, st));
  }
  std::printf("BagStrings: slack string: longest distance tie-anchor %.4g m (rest length %.4g m), %llu steps\n",
              max_length, st.rest_length, static_cast<unsigned long long>(one.scene.total_steps()));
  ASSERT_LT(max_length, st.rest_length) << "the second string must stay slack for the comparison to mean anything";
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.particles().size(); ++i)
    differ += !(a.particles().x[i] == b.particles().x[i] && a.particles().v[i] == b.particles().v[i]);
  for (std::size_t k = 0; k < a.film().size(); ++k) differ += !(a.film().x[k] == b.film().x[k] && a.film().v[k] == b.film().v[k]);
  EXPECT_EQ(differ, 0u) << "balls or film nodes differ between the runs with and without the slack string";
  EXPECT_GT((b.film().x[st.nodes[0]] - two.scene.bag->x0[st.nodes[0]]).norm(), 1e-5) << "the bag should have moved (fallen)";
}

// The auto time step must keep a string's damper stable. A string's damping c acts on its tie's
// nodes (mass m_tie); an explicit step is stable only for c dt / m_tie below ~2 (and the step
// rule, src/case/timestep.cpp, takes only the string's stiffness into account: 2 / sqrt(k / m_tie)).
// Scene: the hanging bag above with the default tie radius (one node of 4.4e-7 kg, no mass scaling)
// and c = 2 N s/m, so c dt / m_tie = 3.5 at the auto step (7.66e-7 s, which check accepts). Reference: the string holds the bag;
// while the bag falls and its empty part collapses (first 12 ms), L - L0 stays within
// [-0.1 mm, +1 mm] (the tie must not be flung towards the anchor), and no RunError.
// Measured (this build): c dt / m_tie = 3.5; the tie oscillates with growing amplitude, is flung
// 6.8 mm up and the run stops at 7.5 ms ("a node of the bag's film is pressed 0.000668 m into a
// cavity wall", a guard the walls' stop has since replaced): FAILS. With c = 1.0 N s/m (c dt / m_tie = 1.7) it is stable, with 1.2 (2.1) not.
TEST(BagStrings, StringDampingIsStableAtTheAutoStep) {
  LoadedCase c(hanging_toml(), {"bag.strings.0.tie_radius=\"auto\"", "bag.strings.0.damping=2", "bag.film.mass_scaling=1",
                                  "simulation.duration=0.012"});
  const Scene& s = c.scene;
  const BagString& st = s.bag->strings[0];
  Simulation sim(s);
  double m_tie = 0;
  for (std::uint32_t k : st.nodes) m_tie += sim.film().mass[k];
  double lo = 0, hi = 0;
  std::string error;
  try {
    for (std::uint64_t k = 1; k <= s.total_steps(); ++k) {
      sim.step();
      const double ext = string_length(sim, st) - st.rest_length;
      lo = std::min(lo, ext);
      hi = std::max(hi, ext);
    }
  } catch (const RunError& e) {
    error = e.what();
  }
  std::printf("BagStrings: damped string on a tie of %zu node(s), m_tie %.3g kg, c %.3g N s/m, dt %.3g s: c dt / m_tie = %.3g; "
              "L - L0 in [%.3g, %.3g] m over %.3g s%s%s\n",
              st.nodes.size(), m_tie, st.damping, s.dt, st.damping * s.dt / m_tie, lo, hi, sim.time(),
              error.empty() ? "" : "; stopped: ", error.c_str());
  EXPECT_TRUE(error.empty()) << error;
  EXPECT_GT(lo, -1e-4) << "the tie was flung towards the anchor (unstable string damping)";
  EXPECT_LT(hi, 1e-3);
}

// Balls stay in the bag under violent shaking. A full bag (60 balls of 4 mm, 2 GPa steel; LDPE film
// 50 um, 150 triangles, capsule of radius 7 mm, no strings) in a closed box shaken obliquely
// (direction (1, 0, 1)) at 100 Hz with X w^2 = 50 g (X = 1.2425 mm), gravity on, for 1e5 steps.
// Reference: no ball ever leaves the film. Checked with Simulation::balls_outside_bag() (winding
// number, independent of the stepper's side bookkeeping) every 1e4 steps and at the end, and no
// RunError (which would also catch a ball crossing the film: the stepper's guard). Tolerance: zero
// balls outside. Measured (this build): 0 outside at every check; 1e5 steps of 8.85e-7 s (88.5 ms,
// 8.9 cycles) in ~3.8 s on one thread.
TEST(BagEscape, FullBagHoldsItsBallsAt50g) {
  const double w = 2 * 3.14159265358979323846 * 100.0, X = 50 * 9.81 / (w * w);
  const std::string toml = bag_scene("1 s", 17)
                               .box("steel", vec("-32 mm", "-11 mm", "-11 mm"), vec("32 mm", "11 mm", "11 mm"))
                               .harmonic(X, "100 Hz", "[1, 0, 1]")
                               .capsule_bag("7 mm", 150, 60);
  LoadedCase c(toml);
  const Scene& s = c.scene;
  ASSERT_NEAR(s.motion->max_speed() * w / 9.81, 50.0, 1e-9 * 50);  // peak acceleration X w^2 = 50 g
  Simulation sim(s);
  const std::uint64_t steps = 100000;
  ASSERT_GE(s.total_steps(), steps);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::size_t> outside_counts;
  std::string error;
  std::uint64_t k = 0;
  try {
    for (k = 1; k <= steps; ++k) {
      sim.step();
      if (k % 10000 == 0) {
        const auto out = sim.balls_outside_bag();
        outside_counts.push_back(out.size());
        EXPECT_TRUE(out.empty()) << out.size() << " balls outside the bag at step " << k << " (t = " << sim.time() << " s)";
      }
    }
  } catch (const RunError& e) {
    error = e.what();
  }
  const double wall = seconds_since(t0);
  std::string counts;
  for (std::size_t n : outside_counts) counts += std::to_string(n) + " ";
  std::printf("BagEscape: %zu balls, %zu film triangles, X = %.4g mm at 100 Hz (50 g), dt %.3g s: %llu steps (%.3g s "
              "simulated, %.1f cycles) in %.2f s wall; balls outside at each 1e4 steps: %s; film-ball contacts at the end "
              "%zu%s%s\n",
              s.bag->balls, s.bag->rest.triangles.size(), 1e3 * X, s.dt, static_cast<unsigned long long>(sim.steps_done()),
              sim.time(), sim.time() * 100, wall, counts.c_str(), sim.mesh_contact_count(), error.empty() ? "" : "; stopped: ",
              error.c_str());
  EXPECT_TRUE(error.empty()) << error;
  EXPECT_EQ(sim.steps_done(), steps);
  EXPECT_TRUE(sim.balls_outside_bag().empty());
}

namespace {

// Zero gravity; balls of 4 mm, 2 GPa steel; a capsule bag (radius 7 mm, length 40 mm, 200 triangles,
// one ball inside) whose film is as stiff as the balls (E 2 GPa, nu 0.3) and very heavy (density
// 1e9 kg/m^3: film nodes of 0.6 kg or more, >2000 x a ball); the cavity walls are of the same
// material; ball-film (= ball-wall) restitution 0.7, no friction. `positions`, `velocities`: the
// [particles.probe] balls (none when empty).
std::string stiff_film_toml(const std::string& positions, const std::string& velocities) {
  CaseText c = CaseText()
                   .simulation("0.006 s", kNoGravity)
                   .set("simulation", "seed", 2)
                   .steel("2 GPa")
                   .material("heavy", "1e9 kg/m^3", "2 GPa", 0.3)
                   .interactions(0.5)
                   .interactions("steel-heavy", 0.7, "")
                   .box("heavy", vec("-30 mm", "-20 mm", "-20 mm"), vec("30 mm", "20 mm", "20 mm"))
                   .capsule_bag("7 mm", 200, 1)
                   .set("bag", {{"length", "40 mm"}, {"centre", vec(0, 0, "-5 mm")}})
                   .set("bag.film", "material", quoted("heavy"));
  if (!positions.empty()) c.placed("probe", "steel", "4 mm", "[" + positions + "]", "[" + velocities + "]");
  return c;
}

std::string vec_toml(const Vec3& v) {
  char b[128];
  std::snprintf(b, sizeof b, "[%.17g, %.17g, %.17g]", v.x(), v.y(), v.z());
  return b;
}

struct StiffFilmResult {
  // Normal restitution of the balls sent onto: a face's centroid, the midpoint of a convex edge (a
  // ridge seen from outside), a vertex, the midpoint of a concave edge (a shallow valley seen from
  // outside: the staggered rings of the capsule mesh make every ring chord one), and the ceiling.
  double face = 0, ridge = 0, vertex = 0, valley = 0, wall = 0;
  double valley_angle_deg = 0;            // angle between the valley's two face normals
  std::size_t most_contacts[5] = {};      // most ball-film contacts of each probe at once
  double film_speed = 0;                  // largest film node speed (unit: m/s)
};

// The balls' contacts with the film now, per probe (brute force over the film's triangles, with the
// stepper's one-contact-per-feature rule).
std::size_t film_contacts(const Simulation& sim, std::size_t ball) {
  const Bag& bag = *sim.scene().bag;
  const double reach = sim.particles().radius[ball] + 0.5 * bag.film.thickness;
  std::vector<MeshHit> hits;
  for (std::uint32_t t = 0; t < bag.rest.triangles.size(); ++t) {
    const auto& tri = bag.rest.triangles[t];
    const TriangleHit h = closest_point_on_triangle(sim.particles().x[ball], sim.film().x[tri[0]], sim.film().x[tri[1]], sim.film().x[tri[2]]);
    if (h.distance2 < reach * reach) hits.push_back({t, 0, h});
  }
  select_mesh_contacts(bag.rest, hits);
  return hits.size();
}

const StiffFilmResult& stiff_film_result() {
  static const StiffFilmResult r = [] {
    StiffFilmResult out;
    LoadedCase probe_free(stiff_film_toml("", ""));
    const TriangleMesh& mesh = probe_free.scene.bag->rest;
    const double gap = 2e-3 + 25e-6 + 1e-3;  // reach (r + t/2) + 1 mm of free flight
    auto face_normal = [&](std::uint32_t t) {
      const auto& tri = mesh.triangles[t];
      const Vec3 a = mesh.vertices[tri[0]], b = mesh.vertices[tri[1]], c = mesh.vertices[tri[2]];
      return Vec3((b - a).cross(c - a).normalized());
    };
    auto centroid = [&](std::uint32_t t) {
      const auto& tri = mesh.triangles[t];
      return Vec3((mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3);
    };
    // Convex (ridge) or concave (valley) seen from outside: the far vertex of the second triangle
    // below or above the first one's plane.
    auto is_ridge = [&](std::uint32_t e) {
      const auto& et = mesh.edge_triangles[e];
      const auto& t1 = mesh.triangles[et[1]];
      Vec3 far = Vec3::Zero();
      for (std::uint32_t v : t1)
        if (v != mesh.edge_vertices[e][0] && v != mesh.edge_vertices[e][1]) far = mesh.vertices[v];
      return (far - mesh.vertices[mesh.edge_vertices[e][0]]).dot(face_normal(et[0])) < 0;
    };
    // On the upper side of the cylinder, each near its own x so that the probes do not meet.
    auto score = [](const Vec3& p, double x) { return p.z() - 0.3 * std::abs(p.x() - x); };
    std::uint32_t face = 0, ridge = 0, valley = 0, vertex = 0;
    double bf = -1e300, br = -1e300, bv = -1e300, bx = -1e300;
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
      if (score(centroid(t), -12e-3) > bf) bf = score(centroid(t), -12e-3), face = t;
    for (std::uint32_t e = 0; e < mesh.edge_vertices.size(); ++e) {
      const Vec3 m = 0.5 * (mesh.vertices[mesh.edge_vertices[e][0]] + mesh.vertices[mesh.edge_vertices[e][1]]);
      if (is_ridge(e) && score(m, -4e-3) > br) br = score(m, -4e-3), ridge = e;
      if (!is_ridge(e) && score(m, 12e-3) > bv) bv = score(m, 12e-3), valley = e;
    }
    for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v)
      if (score(mesh.vertices[v], 4e-3) > bx) bx = score(mesh.vertices[v], 4e-3), vertex = v;
    auto edge_point = [&](std::uint32_t e) {
      return Vec3(0.5 * (mesh.vertices[mesh.edge_vertices[e][0]] + mesh.vertices[mesh.edge_vertices[e][1]]));
    };
    auto edge_normal = [&](std::uint32_t e) {
      return Vec3((face_normal(mesh.edge_triangles[e][0]) + face_normal(mesh.edge_triangles[e][1])).normalized());
    };
    Vec3 vertex_n(0, 0, 0);
    for (std::uint32_t k = mesh.vertex_triangle_begin[vertex]; k < mesh.vertex_triangle_begin[vertex + 1]; ++k)
      vertex_n += face_normal(mesh.vertex_triangles[k]);
    vertex_n.normalize();
    out.valley_angle_deg = std::acos(std::min(1.0, face_normal(mesh.edge_triangles[valley][0]).dot(face_normal(mesh.edge_triangles[valley][1])))) * 180 / 3.14159265358979323846;
    const Vec3 targets[4] = {centroid(face), edge_point(ridge), mesh.vertices[vertex], edge_point(valley)};
    const Vec3 normals[4] = {face_normal(face), edge_normal(ridge), vertex_n, edge_normal(valley)};
    std::string pos, vel;
    for (int k = 0; k < 4; ++k) {
      pos += vec_toml(targets[k] + gap * normals[k]) + ", ";
      vel += vec_toml(-1.0 * normals[k]) + ", ";
    }
    pos += vec_toml(Vec3(20e-3, 10e-3, 20e-3 - gap));  // towards the ceiling (z = 20 mm)
    vel += vec_toml(Vec3(0, 0, 1));

    LoadedCase c(stiff_film_toml(pos, vel));
    const Scene& s = c.scene;
    if (s.bag->ball_first != 5) throw std::runtime_error("expected 5 probes before the bag's ball");
    Simulation sim(s);
    std::vector<Vec3> v0(sim.particles().v.begin(), sim.particles().v.begin() + 5);
    for (std::uint64_t k = 1; k <= s.total_steps(); ++k) {
      sim.step();
      if (k % 2 == 0)
        for (std::size_t b = 0; b < 4; ++b) out.most_contacts[b] = std::max(out.most_contacts[b], film_contacts(sim, b));
      for (const Vec3& v : sim.film().v) out.film_speed = std::max(out.film_speed, v.norm());
    }
    if (sim.mesh_contact_count() != 0) throw std::runtime_error("the run ended before the balls left the film");
    double e[5];
    for (int k = 0; k < 5; ++k) {
      const Vec3 v1 = sim.particles().v[k];
      if ((v1 - v0[k]).norm() < 1.0) throw std::runtime_error("probe " + std::to_string(k) + " did not bounce");
      const Vec3 n = (v1 - v0[k]).normalized();
      e[k] = -v1.dot(n) / v0[k].dot(n);
    }
    out.face = e[0], out.ridge = e[1], out.vertex = e[2], out.valley = e[3], out.wall = e[4];
    std::printf("BagStiffFilm: requested e = 0.7; measured on the film: face %.5f, ridge (convex edge) %.5f, vertex %.5f, "
                "valley (concave edge, normals %.1f deg apart) %.5f; on the wall %.5f; film / wall: %.4f %.4f %.4f %.4f; "
                "most film contacts at once (face, ridge, vertex, valley): %zu %zu %zu %zu; largest film node speed %.3g m/s; "
                "lightest node %.3g kg vs ball %.3g kg; dt %.3g s\n",
                out.face, out.ridge, out.vertex, out.valley_angle_deg, out.valley, out.wall, out.face / out.wall,
                out.ridge / out.wall, out.vertex / out.wall, out.valley / out.wall, out.most_contacts[0],
                out.most_contacts[1], out.most_contacts[2], out.most_contacts[3], out.film_speed, s.bag->min_node_mass,
                sim.particles().mass[0], s.dt);
    return out;
  }();
  return r;
}

}  // namespace

// With a film much heavier than the balls and as stiff, the ball-film law is the ball-wall law
// (src/step/surfaces.cpp: R* = the ball's radius, m* -> the ball's mass as the film's nodes get heavy).
// Balls outside the bag are sent at 1 m/s along the film's outward normal onto its upper side: at
// the centroid of a face, the midpoint of a convex edge (ridge) and a vertex (the one-contact-per-
// feature rule must give one contact each); another hits the box's ceiling (same material pair).
// Normal restitution e = -(v1 . n) / (v0 . n), n the direction of the velocity change (no friction:
// the impulse is normal). Reference: the requested 0.7 (docs/contact-model.md: the clamped law returns e within 1%)
// and the measured ball-wall value. Tolerance 2% for each. Also: one film contact per ball, and the
// film barely moves (largest node speed < 1% of the impact speed).
// Measured (this build): face 0.6982, ridge 0.6981, vertex 0.6979, wall 0.6986 (film / wall 0.9991
// to 0.9995); one contact each; film nodes at most 5.2e-4 m/s.
TEST(BagStiffFilm, BallFilmLawReducesToBallWallLaw) {
  const StiffFilmResult& r = stiff_film_result();
  EXPECT_NEAR(r.wall, 0.7, 0.02 * 0.7);
  const double film[3] = {r.face, r.ridge, r.vertex};
  const char* where[3] = {"face", "ridge", "vertex"};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(film[k], 0.7, 0.02 * 0.7) << where[k];
    EXPECT_NEAR(film[k], r.wall, 0.02 * r.wall) << where[k] << " against the wall's";
    EXPECT_EQ(r.most_contacts[k], 1u) << where[k];
  }
  EXPECT_LT(r.film_speed, 0.01);
}

// The same on a shallow valley of the film (a concave edge seen from the ball: the two faces' normals
// ~10 degrees apart at 200 triangles; the capsule's staggered rings make every ring chord such a
// valley from outside and every diagonal one from inside). The film stands for a smooth membrane,
// so the ball should meet the ball-wall law here too. Reference: the measured ball-wall e and the
// requested 0.7; tolerance 2%. (The ball touches both faces at once: two hits, one contact
// joining them, PatchBlend, whose damping takes the joined overlap's own m*.)
// Measured (this build): 2 hits at once, e = 0.6976 (film / wall 0.9986); with the joined contact's
// m* the ball's own (scale^2 too heavy), 0.678.
TEST(BagStiffFilm, ImpactOnAShallowValleyOfTheFilmMatchesTheWallLaw) {
  const StiffFilmResult& r = stiff_film_result();
  EXPECT_NEAR(r.valley, r.wall, 0.02 * r.wall) << "valley " << r.valley_angle_deg << " degrees, " << r.most_contacts[3]
                                               << " contacts at once";
  EXPECT_NEAR(r.valley, 0.7, 0.02 * 0.7);
}
