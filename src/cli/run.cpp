// `bagdem run`: a case run (a frequency sweep for a stepped-sine excitation), or an ensemble of starts (command.hpp).
#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/reduce/compare.hpp"
#include "bagdem/run/stepped_sine.hpp"
#include "bagdem/run/runner.hpp"
#include "command.hpp"

namespace bagdem::cli {

CLI::App* add_run(CLI::App& app, Args& a) {
  CLI::App* run = app.add_subcommand("run", "Run a case: writes results.h5 (+ results.xmf for ParaView) and, when complete, summary.json. "
                                      "A case with a primary structure ([primary]: sdof, beam, fe-beam) driven by a stepped-sine "
                                      "[excitation] runs a frequency sweep instead: sweep.csv, the table /sweep in results.h5, and "
                                      "each mode's peak reduction (dB, %) against the bare structure in summary.json. A run that goes "
                                      "unstable leaves its record as results.failed.h5 and an earlier complete results.h5 as it was. A case of several "
                                      "dampers on its structure ([[dampers]]) writes each other damper's record in OUT/dampers/NAME "
                                      "(a run's results.h5 and summary.json, a sweep's reduced.csv).");
  run->add_option("case_dir", a.case_dir, "Case directory (holds case.toml)")->required();
  run->add_option("--out", a.out_dir, "Output directory (default CASE_DIR/out)");
  run->add_option("--threads", a.threads, "OpenMP threads (default: all cores; results are identical for any count; the balls' stages use several threads from 2048 balls, below that one (the fork and join would cost more than they save), and each thread's share of the balls follows its measured speed; a stepped-sine sweep runs its chains, excitation.chains, side by side on them)")->check(CLI::Range(1, 1024));
  run->add_option("--set", a.sets, "Override a key of case.toml, dotted path: --set particles.balls.count=200 (repeatable)");
  add_fidelity(run, a.fidelity);
  run->add_flag("--quiet", a.quiet, "No progress line");
  run->add_flag("--resume", a.resume, "Continue an interrupted run from OUT/checkpoint.bin (left by output.checkpoint_interval > 0, and by SIGINT or SIGTERM, which stop a run with exit code 130 or 143); OUT/results.h5.part must hold the data the checkpoint recorded (verified), or the resume is refused");
  run->add_option("--seeds", a.seeds,
                  "An ensemble of N perturbed starts (simulation.seed = 1..N, each in OUT/point-NNN, resumable, as bagdem sweep runs "
                  "them; --threads is then per start): every table with its mean and 95% interval over the starts "
                  "(OUT/<table>_ensemble.csv), the peak reduction among them. A chaotic bed's figure from one start is not a measurement")
      ->check(CLI::Range(1, 100000));
  return run;
}

namespace {

// The balls of every damper.
std::size_t balls(const Scene& s) {
  std::size_t n = s.particles.size();
  for (const Damper& d : s.more_dampers) n += d.scene->particles.size();
  return n;
}

// A run that did not finish: its message and exit code (128 + the signal that stopped it, or the
// run error's); 0 for a finished run.
int unfinished(bool complete, int signal, const std::string& message) {
  if (signal) {
    std::cerr << "interrupted: " << message << "\n";
    return 128 + signal;
  }
  if (!complete) {
    std::cerr << "error: " << message << "\n";
    return kExitRunError;
  }
  return 0;
}

// `bagdem run` of a case with a stepped-sine excitation: the frequency sweep.
int stepped_sine_case(const Args& a, const Scene& s, const RunOptions& o) {
  if (!a.quiet) std::cerr << "bagdem run " << a.case_dir << ": stepped-sine sweep, " << s.primary->stepped_sine->frequencies.size()
                        << " frequencies, N = " << balls(s) << ", dt = " << s.dt << " s -> " << o.out_dir << "\n";
  const SteppedSineReport r = run_stepped_sine(s, o);
  if (const int code = unfinished(r.complete, r.signal, r.message)) return code;
  std::printf("sweep complete: %zu frequencies, %.1f s wall\n", r.points.size(), r.wall_seconds);
  for (const ModePeak& m : r.peaks) std::printf("%s\n", describe_peak(m).c_str());
  for (const std::string& why : missing_peaks(*s.primary, r.points)) std::printf("%s\n", why.c_str());
  std::printf("the bag's effective parameters per frequency (reduced.csv):\n%s", describe_reduced(r.reduced).c_str());
  std::printf("%s", describe_compare(r.compare, continuum::Form::consistent).c_str());
  for (const Damper& d : s.more_dampers)
    std::printf("damper %s: its effective parameters per frequency in %s/dampers/%s/reduced.csv\n", d.name.c_str(), o.out_dir.c_str(), d.name.c_str());
  return 0;
}

// `bagdem run` of any other case.
int run_case(const Args& a, const Scene& s, const RunOptions& o) {
  if (!a.quiet) std::cerr << "bagdem run " << a.case_dir << ": N = " << balls(s) << ", dt = " << s.dt
                        << " s, " << s.total_steps() << " steps -> " << o.out_dir << "\n";
  const RunReport r = run_scene(s, o);
  if (const int code = unfinished(r.complete, r.signal, r.message)) return code;
  if (!r.reduced.empty()) std::printf("the contents' effective parameters (reduced.csv):\n%s", describe_reduced(r.reduced).c_str());
  if (!r.reduce_message.empty())
    std::fprintf(stderr, "%s%s\n", r.reduced.empty() ? "reduction skipped: " : "note: ", r.reduce_message.c_str());
  if (s.models.energy)
    std::printf("run complete: %.2f s wall, %.1f ns per particle-step, energy balance error %.2e\n", r.wall_seconds,
                r.ns_per_particle_step, r.energy_balance_error);
  else
    std::printf("run complete: %.2f s wall, %.1f ns per particle-step (energy budget off: output.energy = false)\n",
                r.wall_seconds, r.ns_per_particle_step);
  if (r.cycles > 0)
    std::printf("energy dissipated per cycle: %.4e J (over %.1f measured cycles)\n", r.dissipated_per_cycle, r.cycles);
  if (r.bag && r.film_self_steps > 0)
    std::printf("bag: its film met itself at %llu steps, at most %llu node pairs at once (bag.film.self_contact)\n",
                static_cast<unsigned long long>(r.film_self_steps), static_cast<unsigned long long>(r.film_self_pairs_max));
  if (r.bag && r.film_wall_stops > 0)
    std::printf("bag: the walls' stop held a film node at %llu steps (the film-wall contact alone would have let it go deeper "
                "than simulation.max_overlap x bag.film.contact_radius; docs/bag.md, Guards)\n",
                static_cast<unsigned long long>(r.film_wall_stops));
  for (const RunReport::DamperOutput& d : r.dampers) std::printf("damper %s: its results.h5 and summary.json in %s\n", d.name.c_str(), d.dir.c_str());
  if (r.structure) {
    std::printf("structure: RMS response %.4e m, RMS acceleration %.4e m/s^2 at response_at\n", r.response_rms,
                r.acceleration_rms);
    if (r.decay_time > 0)
      std::printf("decay: damping ratio %.4g, time to fall by 20 dB %.4g s\n", r.decay_zeta, r.decay_time);
    if (s.primary->random_hi > 0)
      std::printf("structure: RMS response in the force's band %.4e m (after %.4g s; the RMS above holds every frequency, a hung "
                  "structure's swing too)\n", r.band_response_rms, s.primary->random_skip);
  }
  return 0;
}

}  // namespace

int run_run(Args& a) {
  apply_fidelity(a);
  if (a.threads > 0) warn_threads_above_cores({a.threads});
  if (a.seeds > 1) {
    if (a.resume) throw InputError("--resume", "", "", "an ensemble resumes by itself: run the same command again (done starts are kept)");
    return study::holding_interrupts("bagdem run --seeds", [&] { return study::run_ensemble(a.case_dir, a.sets, a.seeds, a.out_dir, a.threads); });
  }
  const Scene s = load_case(a.case_dir, a.sets);
  for (const auto& w : s.warnings) std::cerr << "warning: " << w << "\n";
  RunOptions o;
  o.out_dir = a.out();
  o.threads = a.threads;
  o.quiet = a.quiet;
  o.resume = a.resume;
  return s.primary && s.primary->stepped_sine ? stepped_sine_case(a, s, o) : run_case(a, s, o);
}

}  // namespace bagdem::cli
