// `bagdem drop`: the drop test of a case's contents (command.hpp).
#include "bagdem/case/load_case.hpp"
#include "bagdem/io/output_lock.hpp"
#include "bagdem/run/drop_test.hpp"
#include "command.hpp"

namespace bagdem::cli {

CLI::App* add_drop(CLI::App& app, Args& a) {
  CLI::App* drop = app.add_subcommand("drop", "Drop test of the case's bag: its contents, settled as in the case, are launched against a wall of the "
                                        "resting cavity along the excitation direction; prints e_drop = rebound / approach speed of their "
                                        "centre of mass (in [0, 1], or an error that says why) and writes OUT/drop.csv and OUT/drop_result.csv; "
                                        "`bagdem reduce` then reports it beside the other two estimates (a run does the same by itself when a "
                                        "row has neither of the others).");
  drop->add_option("case_dir", a.case_dir, "Case directory (holds case.toml)")->required();
  drop->add_option("--out", a.out_dir, "Output directory (default CASE_DIR/out)");
  drop->add_option("--set", a.sets, "Override a key of case.toml (repeatable)");
  add_fidelity(drop, a.fidelity);
  drop->add_option("--speed", a.drop_speed,
                   "Launch speed in m/s, > 0 and at most 20 (default: the case's expected impact speed; where the impact at that speed does not "
                   "stand out of the sliding friction, twice as fast, up to 16 times, said in the output)")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            char* end = nullptr;
            const double x = std::strtod(v.c_str(), &end);
            if (!(end != v.c_str() && *end == '\0' && x > 0 && std::isfinite(x)))
              return "'" + v + "' is not a launch speed: give a number > 0 (m/s)";
            return x <= 20 ? std::string()
                           : "'" + v + "' m/s is faster than a damper's contents meet a wall (a cavity at Gamma 100 and 20 Hz moves at 7.8 m/s): "
                                       "give at most 20 m/s";
          },
          "SPEED > 0"));
  drop->add_option("--threads", a.threads, "OpenMP threads")->check(CLI::Range(1, 1024));
  return drop;
}

int run_drop(Args& a) {
  apply_fidelity(a);
  if (a.threads > 0) warn_threads_above_cores({a.threads});
  if (a.threads > 0) omp_set_num_threads(a.threads);
  const Scene s = load_case(a.case_dir, a.sets);
  const OutputLock lock(a.out());
  const DropResult d = run_drop_test(s, a.drop_speed, a.out(), false);
  write_drop_result(std::filesystem::path(a.out()) / "drop_result.csv", d, s);
  std::printf("e_drop = %.4f (launched at %.4g m/s: approach %.4g m/s, rebound %.4g m/s, peak force %.4g N, contact %.4g ms)\n",
              d.restitution, d.speed, d.v_before, d.v_after, d.peak_force, 1e3 * d.duration);
  return 0;
}

}  // namespace bagdem::cli
