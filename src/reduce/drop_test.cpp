// Drop test of the bag (reduce/drop_test.hpp).
#include "bagdem/reduce/drop_test.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "bagdem/error.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/motion/motion.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "bagdem/stepper.hpp"

namespace bagdem {

DropResult run_drop_test(const Scene& scene, double speed, const std::filesystem::path& out_dir, bool quiet) {
  const Vec3 e = excitation_direction(scene);
  if (e.norm() == 0)
    throw InputError(scene.case_file, "cavity.motion", "", "a drop test needs an excitation direction: harmonic cavity motion or a primary structure");
  if (scene.particles.empty()) throw InputError(scene.case_file, "particles", "", "a drop test needs contents (balls or a bag)");
  if (speed <= 0) speed = scene.primary ? scene.primary->expected_cavity_speed : scene.motion->max_speed();
  if (!(speed > 0) || !std::isfinite(speed))
    throw InputError(scene.case_file, "--speed", std::to_string(speed), "must be a positive launch speed (m/s)");

  // The case's contents in its cavity, held still; no primary structure.
  Scene s = scene;
  s.primary.reset();
  s.motion = make_fixed_motion();
  Simulation sim(s);
  const auto settle = static_cast<std::uint64_t>(std::llround(s.settle / s.dt));
  while (sim.steps_done() < settle) sim.step();
  sim.take_cavity_sample();  // start the force sums afresh

  // Launch across the larger gap.
  const ContentsGaps g = contents_gaps(s, sim, e);
  const bool plus = !(g.minus > g.plus);  // NaN gaps (triangulated walls): along +e
  const Vec3 u = plus ? e : Vec3(-e);
  DropResult r;
  r.speed = speed;
  r.gap = plus ? g.plus : g.minus;
  if (r.gap <= 0) throw InputError(scene.case_file, "", "", "the contents touch the walls on both sides along the excitation: no room for a drop test");
  double mass = 0;
  for (double m : sim.particles().mass) mass += m;
  for (double m : sim.film().mass) mass += m;
  sim.add_contents_velocity(speed * u);

  // Contact: the wall force along u above a threshold far below the impact's scale M V / t.
  const double threshold = 1e-3 * mass * speed / (100 * s.dt);
  const double flight = std::isfinite(r.gap) ? r.gap / speed : 0.0;
  const auto quiet_steps = std::max<std::uint64_t>(100, static_cast<std::uint64_t>(0.01 * flight / s.dt));
  const auto max_steps = static_cast<std::uint64_t>((5 * flight + 0.05) / s.dt);
  std::vector<double> t, F, v;
  bool touched = false;
  std::uint64_t off = 0, first = 0, last = 0;
  double v_before = speed;
  double v_prev = sim.contents_relative_velocity().dot(u);
  for (std::uint64_t n = 0; n < max_steps; ++n, v_prev = v.back()) {
    sim.step();
    const Simulation::CavitySample c = sim.take_cavity_sample();  // one step: this step's force, the velocity after it
    const double f = c.force.dot(u), vn = c.contents_velocity.dot(u);
    t.push_back(sim.time()), F.push_back(f), v.push_back(vn);
    if (f > threshold) {
      if (!touched) v_before = v_prev, first = n;
      touched = true, off = 0, last = n;
      r.peak_force = std::max(r.peak_force, f);
    } else if (touched && ++off >= quiet_steps) {
      r.v_before = v_before;
      r.v_after = -vn;
      r.restitution = r.v_after / r.v_before;
      r.duration = static_cast<double>(last - first + 1) * s.dt;
      break;
    }
  }
  if (!touched || r.v_before == 0)
    throw RunError("drop test: the contents did not " + std::string(touched ? "leave" : "reach") + " the wall within " +
                   std::to_string(max_steps * s.dt) + " s; give a larger --speed");
  // drop.csv: at most about 20000 rows.
  const std::size_t every = std::max<std::size_t>(1, t.size() / 20000);
  std::vector<std::vector<double>> rows;
  for (std::size_t k = 0; k < t.size(); k += every) rows.push_back({t[k], F[k], v[k]});
  std::filesystem::create_directories(out_dir);
  write_table_csv(out_dir / "drop.csv", {{"time", "s"}, {"wall_force", "N"}, {"approach_velocity", "m/s"}}, rows);
  if (!quiet)
    std::fprintf(stderr, "drop test: %.4g m/s across a gap of %.3g mm: rebound %.4g m/s, e_drop = %.4f, peak force %.4g N, contact %.4g ms\n",
                 r.v_before, 1e3 * r.gap, r.v_after, r.restitution, r.peak_force, 1e3 * r.duration);
  return r;
}

void write_drop_result(const std::filesystem::path& path, const DropResult& r) {
  write_table_csv(path,
                  {{"speed", "m/s"}, {"v_before", "m/s"}, {"v_after", "m/s"}, {"restitution", "1"}, {"peak_force", "N"},
                   {"duration", "s"}, {"gap", "m"}},
                  {{r.speed, r.v_before, r.v_after, r.restitution, r.peak_force, r.duration, r.gap}});
}

}  // namespace bagdem
