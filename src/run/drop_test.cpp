// Drop test of the bag (run/drop_test.hpp).
#include "bagdem/run/drop_test.hpp"
#include "bagdem/reduce/drop_record.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <variant>

#include "bagdem/contact/law.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/motion/motion.hpp"
#include "bagdem/reduce/impacts.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "bagdem/run/clearance.hpp"
#include "bagdem/step/simulation.hpp"

namespace bagdem {

namespace {

// A launch that gave no figure, and whether a faster one could (the impact did not stand out of
// the sliding friction, or the contents did not reach the wall in time).
struct DropFailure {
  std::string why;
  bool faster_helps = false;
};

// Whether a contact law of the scene pulls at the end of an impact (contact/law.hpp).
bool contact_pulls(const Scene& s) {
  return std::any_of(s.laws.laws.begin(), s.laws.laws.end(), [](const PairLaw& l) { return contact_law(l.kind).pulls; });
}

// A launch too slow to cross the gap within a second means no impact to measure (and a run of
// ever more steps): refused, naming the least speed.
void refuse_too_slow(const Scene& s, double speed, double gap) {
  constexpr double kLongestFlight = 1.0;  // (unit: s) a launch too slow to cross the gap within it means no impact
  if (const double flight = gap / speed; flight > kLongestFlight) {
    char why[256];
    std::snprintf(why, sizeof why, "is too slow: the contents would take %.3g s to cross the gap of %.3g m (at most %.3g s); give at least %.3g m/s",
                  flight, gap, kLongestFlight, gap / kLongestFlight);
    char given[32];
    std::snprintf(given, sizeof given, "%.6g", speed);
    throw InputError(s.case_file, "--speed", given, why);
  }
}

// The settled contents launched at `speed` along u across `gap` (scene `s`, state `settled`).
// Returns the figures, or a DropFailure; RunError when the run goes unstable.
std::variant<DropResult, DropFailure> drop_once(const Scene& s, const std::vector<char>& settled, double speed, const Vec3& u,
                                               double gap) {
  Simulation sim(s);
  sim.load_state(settled);
  sim.take_cavity_sample();  // start the force sums afresh
  DropResult r;
  r.speed = speed;
  r.gap = gap;
  sim.add_contents_velocity(speed * u);

  // Sliding on the floor under gravity pulls on the cavity along u too, up to mu M g: the impact is
  // the force above a quarter of its peak (the friction stays below it or the test fails), and its
  // feet (reduce/impacts.hpp) reach down from there to where the pulse rises out of the sliding.
  constexpr double kThreshold = 0.25;
  double mass = 0, mu = 0;
  for (double m : sim.particles().mass) mass += m;
  for (double m : sim.film().mass) mass += m;
  for (const PairLaw& law : s.laws.laws) mu = std::max(mu, law.friction);
  const double g_across = (s.gravity - s.gravity.dot(u) * u).norm(), friction = mu * mass * g_across;
  // Step until the impact on the wall ahead is over: its force (along u) has stayed below the
  // threshold for a settling span (100 steps and 1% of the flight: a bag's contents arrive in
  // waves) and the contents no longer approach it, or until, on the way back, another wall pushes
  // them (force against u): the rebound must be measured before it meets another wall.
  const double flight = std::isfinite(gap) ? gap / speed : 0.0;
  const auto quiet_steps = std::max<std::uint64_t>(100, static_cast<std::uint64_t>(0.01 * flight / s.dt));
  const auto max_steps = static_cast<std::uint64_t>((5 * flight + 0.05) / s.dt);
  std::vector<double> t{sim.time()}, F{0.0}, v{sim.contents_relative_velocity().dot(u)};
  double peak = 0;
  std::uint64_t calm = 0;
  bool ended = false;
  // A law that pulls at the end of an impact (contact_pulls): the wall ahead pulls back on the
  // contents then, against u as another wall would push; another wall is taken for one only once
  // that pull is over (the force back to >= 0 after it).
  const bool pulls = contact_pulls(s);
  bool pulling = false, pull_over = !pulls;
  for (std::uint64_t n = 0; n < max_steps && !ended; ++n) {
    sim.step();
    const CavitySample c = sim.take_cavity_sample();  // one step: this step's force, the velocity after it
    const double f = c.force.dot(u), vn = c.contents_velocity.dot(u);
    t.push_back(sim.time()), F.push_back(f), v.push_back(vn);
    peak = std::max(peak, f);
    calm = f > kThreshold * peak ? 0 : calm + 1;
    if (pulls && peak > 0) {
      if (f < 0) pulling = true;
      else if (pulling) pull_over = true;
    }
    ended = peak > 0 && ((calm >= quiet_steps && vn < 0.01 * speed) || (pull_over && vn < 0 && f < -kThreshold * peak));
  }
  // The impact: the pulses on the wall ahead, merged (one side, every wave), foot to foot.
  const std::vector<Impact> pulses = find_impacts(t, F, 0.0, kThreshold, 2 * (t.back() - t.front()));  // merge every wave
  const auto hit = std::find_if(pulses.begin(), pulses.end(), [](const Impact& i) { return i.side > 0; });
  std::ostringstream at;
  at << "at " << speed << " m/s ";
  if (!ended || hit == pulses.end())
    return DropFailure{at.str() + "the contents did not " + (peak > 0 ? "leave" : "reach") + " the wall within " +
                           std::to_string(max_steps * s.dt) + " s", true};
  if (!(hit->peak_force > 2 * friction))
    return DropFailure{at.str() + "the impact's peak force (" + std::to_string(hit->peak_force) +
                           " N) does not stand out of the sliding friction on the floor (up to " + std::to_string(friction) +
                           " N): the contents barely reach the wall", true};
  // v_before before the pulse's first foot; v_after the fastest rebound from its centroid on (a
  // bag's contents leave the wall in waves, and what pushes them back ends at different times:
  // afterwards only friction acts, which slows them).
  const auto index = [&](double time) { return static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), time - 1e-6 * s.dt) - t.begin()); };
  r.v_before = v[index(hit->t_foot_start)];
  if (!(r.v_before > 0)) return DropFailure{at.str() + "no clean impact (the contents did not approach the wall when it began)", true};
  r.v_after = -v[index(hit->t_foot_end)];
  std::size_t from = index(hit->t_centroid);
  if (contact_pulls(s)) {
    // A law whose force pulls at the end of an impact (Hooke): the contents are fastest where the
    // force crosses zero and leave the wall, slower, when the pull is over. The rebound is taken
    // from there (a pull: the force against u beyond what the sliding friction gives).
    const double pull = std::max(friction, 1e-6 * hit->peak_force);
    std::size_t k = from;
    while (k < F.size() && F[k] >= -pull) ++k;
    while (k < F.size() && F[k] < -pull) ++k;
    if (k < F.size()) from = k, r.v_after = -v[k];
  }
  for (std::size_t k = from; k < v.size(); ++k) r.v_after = std::max(r.v_after, -v[k]);
  r.restitution = r.v_after / r.v_before;
  r.peak_force = hit->peak_force;
  r.duration = hit->t_foot_end - hit->t_foot_start;
  // A contents that comes to rest against the wall may keep a creep towards it of a hundredth of
  // the launch speed (where the run's end takes it as at rest): that is e = 0.
  if (r.restitution < 0 && -r.v_after <= 0.01 * speed) r.restitution = 0, r.v_after = 0;
  if (r.restitution < 0)
    return DropFailure{at.str() + "the contents did not rebound: after the impact they still moved towards the wall at " +
                       std::to_string(-r.v_after) + " m/s (approach " + std::to_string(r.v_before) + " m/s)", true};
  // An elastic impact returns its approach speed only to the integration's accuracy: velocity
  // Verlet's energy error over a contact resolved in N = t_c/dt steps is of order 1/N^2.
  r.tolerance = std::pow(s.dt / std::max(r.duration, s.dt), 2);
  if (r.restitution > 1 && r.restitution <= 1 + r.tolerance) r.restitution = 1;
  if (r.restitution > 1)
    throw RunError("drop test: e_drop = " + std::to_string(r.restitution) + " > 1 + " + std::to_string(r.tolerance) + " (approach " +
                   std::to_string(r.v_before) + " m/s, rebound " + std::to_string(r.v_after) +
                   " m/s; the integration's tolerance (dt/t_c)^2 is " + std::to_string(r.tolerance) +
                   "): the contents gained energy in the impact; lower the time step (simulation.timestep_safety)");
  r.series = {std::move(t), std::move(F), std::move(v)};
  return r;
}

}  // namespace

DropResult run_drop_test(const Scene& scene, double speed, const std::filesystem::path& out_dir, bool quiet) {
  const Vec3 e = excitation_direction(scene);
  if (e.norm() == 0)
    throw InputError(scene.case_file, "cavity.motion", "", "a drop test needs an excitation direction: harmonic cavity motion or a primary structure");
  if (scene.particles.empty()) throw InputError(scene.case_file, "particles", "", "a drop test needs contents (balls or a bag)");
  const bool asked = speed > 0;
  if (!asked) speed = scene.primary ? scene.primary->expected_cavity_speed : scene.motion->max_speed();
  if (!(speed > 0) || !std::isfinite(speed))
    throw InputError(scene.case_file, "--speed", std::to_string(speed), "must be a positive launch speed (m/s)");

  // The case's contents in its cavity, held still; no primary structure.
  Scene s = scene;
  s.primary.reset();
  s.motion = make_fixed_motion();
  Simulation sim(s);
  const auto settle = static_cast<std::uint64_t>(std::llround(s.settle / s.dt));
  while (sim.steps_done() < settle) sim.step();
  const std::vector<char> settled = sim.save_state();

  // Launch across the larger gap.
  const ContentsGaps g = contents_gaps(s, sim, e);
  const bool plus = !(g.minus > g.plus);  // NaN gaps (triangulated walls): along +e
  const Vec3 u = plus ? e : Vec3(-e);
  const double gap = plus ? g.plus : g.minus;
  if (gap <= 0) throw InputError(scene.case_file, "", "", "the contents touch the walls on both sides along the excitation: no room for a drop test");
  if (std::isfinite(gap)) refuse_too_slow(s, speed, gap);

  // At the case's own speed the impact may not stand out of the sliding friction (a bag's contents
  // under a gentle drive): without --speed, the launch is repeated twice as fast, up to 16 times.
  std::string tried;
  for (int k = 0;; ++k, speed *= 2) {
    std::variant<DropResult, DropFailure> once = drop_once(s, settled, speed, u, gap);
    if (DropResult* r = std::get_if<DropResult>(&once)) {
      std::ostringstream note;
      if (!tried.empty()) note << tried << "; launched at " << speed << " m/s instead";
      if (r->v_after > r->v_before)
        note << (tried.empty() ? "" : "; ") << "the rebound exceeds the approach by " << r->v_after / r->v_before - 1
             << ", within the integration's tolerance (dt/t_c)^2 = " << r->tolerance << ": an elastic impact, e_drop = 1";
      r->note = note.str();
      write_drop_series(out_dir / "drop.csv", r->series);
      if (!quiet)
        std::fprintf(stderr, "drop test: %.4g m/s across a gap of %.3g mm: rebound %.4g m/s, e_drop = %.4f, peak force %.4g N, contact %.4g ms%s%s\n",
                     r->v_before, 1e3 * r->gap, r->v_after, r->restitution, r->peak_force, 1e3 * r->duration, r->note.empty() ? "" : "\n  ",
                     r->note.c_str());
      return std::move(*r);
    }
    const DropFailure& f = std::get<DropFailure>(once);
    tried += (tried.empty() ? "" : "; ") + f.why;
    if (asked || !f.faster_helps || k == 4)
      throw RunError("drop test: " + tried + "; give a larger --speed" + (asked ? "" : " (the default tried up to 16 times the case's speed)"));
  }
}

void write_drop_series(const std::filesystem::path& path, const DropSeries& d) {
  // At most about 20000 rows.
  const std::size_t every = std::max<std::size_t>(1, d.time.size() / 20000);
  std::vector<std::vector<double>> rows;
  for (std::size_t k = 0; k < d.time.size(); k += every) rows.push_back({d.time[k], d.wall_force[k], d.approach_velocity[k]});
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  write_table_csv(path, {{"time", "s"}, {"wall_force", "N"}, {"approach_velocity", "m/s"}}, rows);
}

// The table is written under a temporary name, its record (reduce/drop_record.hpp) beside the final
// name, then the table renamed: a write stopped between them leaves a record that refuses the table
// there, never a table without its record.
void write_drop_result(const std::filesystem::path& path, const DropResult& r, const Scene& scene) {
  const std::filesystem::path part = path.string() + ".new";
  write_table_csv(part,
                  {{"speed", "m/s"}, {"v_before", "m/s"}, {"v_after", "m/s"}, {"restitution", "1"}, {"peak_force", "N"},
                   {"duration", "s"}, {"gap", "m"}},
                  {{r.speed, r.v_before, r.v_after, r.restitution, r.peak_force, r.duration, r.gap}});
  write_drop_record(part, path, scene);
  std::filesystem::rename(part, path);
}

}  // namespace bagdem
