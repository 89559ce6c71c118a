// `bagdem predict`: a structure's response with a map's damper, without DEM (command.hpp).
#include "bagdem/study/characterize.hpp"
#include "command.hpp"

namespace bagdem::cli {

CLI::App* add_predict(CLI::App& app, Args& args) {
  auto& a = args.predict;
  auto* c = app.add_subcommand(
      "predict",
      "The steady response of the case's structure with the damper of an effective-field map (bagdem characterize), "
      "without DEM: per frequency the single-harmonic balance with the map's M_eff and C_eff at the cavity's own amplitude "
      "and frequency, every solution where the response folds; per evaluated mode the peak reduction against the bare "
      "structure in dB and %, with its range over the map's 95% intervals, a peak at the band's edge marked, and the map's "
      "interpolation error at the answer (a warning when the map is too coarse for it). Writes OUT/predict.csv and OUT/predict_peaks.csv. "
      "The map must be of the case's damper (its damper.toml; another damper is refused, naming the keys). "
      "A case of several dampers ([[dampers]]) takes a map per damper and solves their balances together. "
      "A response outside the map is refused (exit 2) with the characterize command that would cover it. See docs/characterize.md.");
  c->add_option("dir", a.dir, "CASE_DIR (holds case.toml): the structure and its sweep's band")->required();
  c->add_option("--map", a.maps,
                "The map: a directory holding map.csv (bagdem characterize's OUT), or the file; with several dampers NAME=DIR for "
                "damper NAME (repeatable), DIR alone for every damper not named")
      ->required()
      ->allow_extra_args(false);
  c->add_option("--amplitude", a.amplitudes, "Force amplitude, e.g. \"0.2 N\" (repeatable; default the case's excitation.amplitude)")
      ->allow_extra_args(false);
  c->add_option("--points", a.points, "Frequencies per mode's band (default 400)")->check(CLI::Range(2, 1000000));
  c->add_option("--random", a.random,
                "RMS of a band-limited random force, e.g. \"0.05 N\" (repeatable): the RMS response by the equivalent-linear "
                "iteration on the cavity's RMS amplitude, instead of the sweep; needs --band")
      ->allow_extra_args(false);
  c->add_option("--band", a.band, "lo,hi in Hz: the random force's band")->delimiter(',')->expected(2);
  c->add_option("--lines", a.lines, "The random force's lines, evenly over the band, its ends included (default 201: excitation.kind = \"random\"'s 200 intervals)")
      ->check(CLI::Range(1, 10000000));
  c->add_option("--set", a.sets, "Override a key of case.toml (repeatable)")->allow_extra_args(false);
  c->add_option("--out", a.out, "Output directory (default CASE_DIR/predict)");
  return c;
}

int run_predict(Args& a) { return study::predict_command(a.predict); }

}  // namespace bagdem::cli
