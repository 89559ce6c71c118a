// `bagdem predict CASE --map DIR` (study/characterize.hpp): the case's structure with the damper of
// an effective-field map, by single-harmonic balance (reduce/predict.hpp), at one or several force
// levels. Writes OUT/predict.csv (every solution at every frequency) and OUT/predict_peaks.csv (per
// level and mode the bare and damped peaks and the reduction with its interval), each to a
// temporary name and renamed.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/atomic_file.hpp"
#include "bagdem/io/output_lock.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/reduce/predict.hpp"
#include "bagdem/structure/response.hpp"
#include "bagdem/study/characterize.hpp"
#include "bagdem/study/damper_record.hpp"
#include "bagdem/study/study.hpp"
#include "bagdem/units.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;

namespace {
std::string short_force(double F) { return short_text(F) + " N"; }


// A force given as --vary and calibrate's --bounds take values: "0.2 N" quoted as TOML or 0.2 N bare.
double force_of(const std::string& option, const std::string& text) {
  std::string why;
  const auto F = parse_quantity(parse_value(text).given, dim::force, &why);
  if (!F || !(*F > 0)) throw InputError(option, "", text, why.empty() ? "a force above 0, e.g. \"0.2 N\"" : why);
  return *F;
}

// The command that characterizes damper k of the case (characterize maps a case of one damper).
std::string characterize_command(const std::string& case_dir, const std::vector<std::string>& names, std::size_t k) {
  if (names.size() == 1) return "bagdem characterize " + case_dir;
  return "bagdem characterize " + case_dir + " --set 'dampers=[]'" +
         (k == 0 ? "" : " with damper " + names[k] + "'s keys of [[dampers]] (each as --set KEY=VALUE)");
}

fs::path map_file(const std::string& given, const std::string& characterize) {
  fs::path map_csv = given;
  if (fs::is_directory(map_csv)) map_csv /= "map.csv";
  if (!fs::exists(map_csv)) throw InputError("--map", "", given, "holds no map.csv: run " + characterize + " first");
  return map_csv;
}

// The map's damper must be the case's (study/damper_record.hpp): refused, naming the keys, when
// it is not; a map that does not record its damper (not made by bagdem characterize) is said so.
// `whose`: "the case's" or "damper NAME's".
void require_same_damper(const fs::path& map_csv, const Scene& scene, const std::string& characterize, const std::string& whose = "the case's") {
  const fs::path record = map_csv.parent_path() / "damper.toml";
  const std::optional<DamperRecord> map = read_damper_record(record);
  if (!map) {
    std::fprintf(stderr, "warning: %s records no damper (no damper.toml beside it, as bagdem characterize writes): it is not checked "
                 "against the case's\n", map_csv.string().c_str());
    return;
  }
  const std::vector<std::string> diff = damper_differences(*map, damper_record(scene));
  if (diff.empty()) return;
  std::string list;
  for (std::size_t k = 0; k < diff.size() && k < 8; ++k) list += (k ? "; " : "") + diff[k];
  if (diff.size() > 8) list += "; and " + std::to_string(diff.size() - 8) + " more";
  throw InputError("--map", "", map_csv.parent_path().string(),
                   "characterised another damper than " + whose + " (" + record.string() + "): " + list + ". Characterize it (" +
                       characterize + "), or give its map");
}

// Predict's directory, before anything is computed: a directory (or none yet), whose predict
// tables are bagdem's own (an earlier predict's), never a file of the user's.
void check_predict_out(const fs::path& out) {
  refuse_a_file(out);
  for (const char* f : {"predict.csv", "predict_peaks.csv", "predict_random.csv"})
    check_output_target(out / f, "--out", [](const fs::path&, const std::string& head) { return is_bagdem_table_head(head); },
                        "a table of bagdem predict");
}

// After a prediction: the other kind's tables of an earlier predict go (a stepped sine's beside a
// random force's would read as one answer).
void remove_other_predict_tables(const fs::path& out, bool random) {
  for (const char* f : random ? std::vector<const char*>{"predict.csv", "predict_peaks.csv"} : std::vector<const char*>{"predict_random.csv"})
    if (fs::remove(out / f)) std::printf("removed %s: an earlier prediction's, of the other kind\n", (out / f).string().c_str());
}

// A prediction's interval over the map's interval corners, or why it is not known.
std::string interval_text(double lo, double hi, int corners, const char* format, const char* unit) {
  if (!std::isfinite(lo) || !std::isfinite(hi))
    return "its interval not known (" + std::to_string(4 - corners) +
           " of the four corners of the map's intervals leave the map, or its cells have one start: widen --gamma or give --seeds)";
  char text[96];
  const std::string f = std::string(format) + "%s to " + format + "%s over the map's intervals";
  std::snprintf(text, sizeof text, f.c_str(), lo, unit, hi, unit);
  return text;
}

// The resolution check of a mode's prediction (reduce/predict.hpp): printed, and a warning when the
// map is too coarse for the answer or too coarse to check it.
void report_resolution(const PredictedMode& m, double F) {
  const std::string where = short_force(F) + ", mode " + std::to_string(m.mode) + ": ";
  if (!std::isfinite(m.interpolation_db)) {
    std::printf("  interpolation error: not checked (the map is too coarse to estimate it)\n");
    std::fprintf(stderr,
                 "warning: %sthe map is too coarse to check its own interpolation at this answer (3 amplitudes and 3 frequencies a "
                 "band at least, with figures around the answer): the figure may be off by more than its interval; characterize with "
                 "more --amplitudes and --frequencies\n", where.c_str());
    return;
  }
  std::printf("  interpolation error: up to %.2f dB (the map's curvature between its lines, beyond its cells' scatter)\n", m.interpolation_db);
  if (m.interpolation_db > kInterpolationWarning)
    std::fprintf(stderr,
                 "warning: %sthe map is too coarse for this answer: interpolating between its lines may move the reduction by up to "
                 "%.2f dB (above %.1f dB); characterize with more --amplitudes and --frequencies around Gamma %.3g, %.4g Hz\n",
                 where.c_str(), m.interpolation_db, kInterpolationWarning, m.peak_cavity_gamma, m.peak_frequency);
}

// The case's dampers with their maps, its own first (reduce/predict.hpp's MappedDamper): `--map DIR`
// serves every damper not named, `--map NAME=DIR` the damper NAME; each map is checked against its
// damper. `maps` holds the maps the result points into.
std::vector<MappedDamper> damper_maps(const PredictArgs& a, const Scene& scene, std::vector<EffectiveMap>& maps) {
  std::vector<const Scene*> scenes{&scene};
  std::vector<std::string> names{scene.damper_name};
  for (const Damper& d : scene.more_dampers) scenes.push_back(d.scene.get()), names.push_back(d.name);
  std::string all;
  for (const std::string& n : names) all += (all.empty() ? "" : ", ") + n;
  std::vector<std::string> given(names.size());
  std::string every;
  for (const std::string& m : a.maps) {
    const std::size_t eq = m.find('=');
    const auto named = eq == std::string::npos ? names.end() : std::find(names.begin(), names.end(), m.substr(0, eq));
    if (named == names.end() && eq != std::string::npos && !fs::exists(m))
      throw InputError("--map", "", m, "names no damper of the case (its dampers: " + all + "): give NAME=DIR or a map's directory");
    std::string& slot = named == names.end() ? every : given[static_cast<std::size_t>(named - names.begin())];
    if (!slot.empty())
      throw InputError("--map", "", m, named == names.end() ? "is a second map for every damper: give one --map DIR, and NAME=DIR for a damper with its own"
                                                            : "is a second map for damper " + *named);
    slot = named == names.end() ? m : m.substr(eq + 1);
  }
  if (!every.empty() && std::none_of(given.begin(), given.end(), [](const std::string& g) { return g.empty(); }))
    throw InputError("--map", "", every, "serves no damper: every damper has its map (NAME=DIR); leave it out");
  maps.clear();
  maps.reserve(names.size());
  std::vector<MappedDamper> out;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string& dir = given[k].empty() ? every : given[k];
    if (dir.empty())
      throw InputError("--map", "", "", "damper " + names[k] + " has no map: give --map " + names[k] + "=DIR (or one --map DIR for every damper)");
    const std::string characterize = characterize_command(a.dir, names, k);
    const fs::path map_csv = map_file(dir, characterize);
    maps.push_back(read_recorded_map(map_csv));
    require_same_damper(map_csv, *scenes[k], characterize, names.size() == 1 ? "the case's" : "damper " + names[k] + "'s");
    out.push_back({&maps.back(), scenes[k]->primary->at_cavity, names[k]});
  }
  return out;
}

// --random: the RMS response to each level, with its range over the map's interval corners;
// OUT/predict_random.csv.
int predict_random_command(const PredictArgs& a, const Scene& scene, const fs::path& out) {
  if (!scene.primary) throw InputError(scene.case_file, "primary", "", "predict needs a structure ([primary])");
  if (a.band.size() != 2 || !(a.band[0] > 0) || !(a.band[1] > a.band[0]))
    throw InputError("--band", "", "", "--random needs the force's band lo,hi in Hz with 0 < lo < hi");
  if (!scene.more_dampers.empty())
    throw InputError("--random", "", "", "predicts the random response with one damper; the case holds " +
                                             std::to_string(1 + scene.more_dampers.size()) + ": predict their stepped sine without --random");
  std::vector<EffectiveMap> maps;
  damper_maps(a, scene, maps);
  const EffectiveMap& map = maps.front();
  const std::string map_csv = map.source;
  std::vector<std::vector<double>> rows;
  for (const std::string& t : a.random) {
    const double F = force_of("--random", t);
    const RandomPredictionRange range = predict_random_range(*scene.primary, map, F, a.band[0], a.band[1], a.lines);
    const RandomPrediction& r = range.mean;
    if (!r.outside.empty() || !r.converged)
      throw InputError("--map", "", map_csv,
                       "does not cover the random response at " + short_force(F) + " RMS (" +
                           (r.outside.empty() ? std::string("the iteration did not converge") : r.outside) +
                           "). Extend the map: bagdem characterize " + a.dir + " with --band covering the force's and --gamma covering "
                           "the cavity's RMS amplitude (nothing is extrapolated)");
    const double lo = range.response_rms_lo, hi = range.response_rms_hi;
    const double db = 20 * std::log10(r.bare_response_rms / r.response_rms);
    rows.push_back({F, a.band[0], a.band[1], r.bare_response_rms, r.response_rms, lo, hi, r.cavity_rms, db});
    std::printf("%s RMS over %.6g-%.6g Hz: response RMS %.4g m (%s), bare %.4g m: %.2f dB lower\n", short_force(F).c_str(), a.band[0],
                a.band[1], r.response_rms, interval_text(lo, hi, range.corners, "%.4g", "").c_str(), r.bare_response_rms, db);
  }
  fs::create_directories(out);
  write_table_csv(out / "predict_random.csv",
                  {{"force_rms", "N"}, {"band_lo", "Hz"}, {"band_hi", "Hz"}, {"bare_response_rms", "m"}, {"response_rms", "m"},
                   {"response_rms_lo", "m"}, {"response_rms_hi", "m"}, {"cavity_rms", "m"}, {"reduction_dB", "dB"}},
                  rows);
  remove_other_predict_tables(out, true);
  std::printf("prediction complete -> %s/predict_random.csv\n", out.string().c_str());
  return 0;
}

}  // namespace

int predict_command(const PredictArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  return reporting_errors([&] {
    const Scene scene = load_case(a.dir, a.sets);
    const fs::path out = a.out.empty() ? fs::path(a.dir) / "predict" : fs::path(a.out);
    check_predict_out(out);
    const OutputLock lock(out);  // two predicts into one directory would mix their tables
    if (!a.random.empty()) return predict_random_command(a, scene, out);
    if (!scene.primary || !scene.primary->stepped_sine)
      throw InputError(scene.case_file, "excitation.kind", "", "predict needs a structure ([primary]) and a stepped-sine sweep: its band is predicted");
    const Primary& P = *scene.primary;
    std::vector<EffectiveMap> maps;
    const std::vector<MappedDamper> dampers = damper_maps(a, scene, maps);
    const bool several = dampers.size() > 1;
    std::vector<double> forces;
    for (const std::string& t : a.amplitudes) forces.push_back(force_of("--amplitude", t));
    if (forces.empty()) forces.push_back(P.amplitude);
    std::vector<std::vector<double>> rows, peaks;
    for (double F : forces) {
      const std::vector<PredictedMode> modes = predict_modes(P, dampers, F, P.stepped_sine->frequencies, a.points);
      if (modes.empty())
        throw InputError(scene.case_file, "excitation", "",
                         "the sweep's band holds no natural frequency of the structure (bagdem check lists them): no peak to predict; set "
                         "excitation.around_modes, or the frequencies around one");
      for (const PredictedMode& m : modes) {
        if (!m.outside.empty()) {
          char range[200];
          std::snprintf(range, sizeof range, "%.6g-%.6g Hz", m.outside.front(), m.outside.back());
          const MappedDamper& d = dampers[m.outside_damper];
          const std::string whose = several ? "damper " + d.name + "'s " : "the ";
          const std::string why = m.outside_why == "band"     ? "the frequency is outside " + whose + "map's band"
                                  : m.outside_why == "below"  ? whose + "cavity's amplitude is below its map's"
                                  : m.outside_why == "above"  ? whose + "cavity's amplitude is above its map's"
                                  : m.outside_why == "unsolved" ? "the dampers' balance found no steady solution (Newton's method did not converge)"
                                                              : whose + "map's cells there have no figures (no steady start)";
          const std::string hint = m.outside_why == "band"     ? "--band covering " + std::string(range)
                                   : m.outside_why == "below"  ? "--gamma with a smaller lower end"
                                   : m.outside_why == "above"  ? "--gamma with a larger upper end"
                                   : m.outside_why == "unsolved" ? "more --amplitudes and --frequencies (a smoother map)"
                                                               : "more --cycles or --skip (or --seeds)";
          std::vector<std::string> names;
          for (const MappedDamper& x : dampers) names.push_back(x.name);
          throw InputError("--map", "", d.map->source,
                           "does not cover the response of mode " + std::to_string(m.mode) + " at " + short_force(F) + ": at " +
                               std::to_string(m.outside.size()) + " of its frequencies (" + range + ") " + why + ". Extend the map: " +
                               characterize_command(a.dir, names, m.outside_damper) + " " + hint + " (nothing is extrapolated)");
        }
        for (std::size_t k = 0; k < m.points.size(); ++k)
          for (std::size_t b = 0; b < m.points[k].solutions.size(); ++b) {
            const HarmonicSolution& h = m.points[k].solutions[b];
            rows.push_back({F, double(m.mode), m.points[k].frequency, double(b), h.cavity_amplitude, h.response, m.bare[k]});
            for (std::size_t d = 1; d < h.cavities.size(); ++d) rows.back().push_back(h.cavities[d]);
          }
        const double pct = reduction_percent(m.reduction_db);
        peaks.push_back({F, double(m.mode), m.bare_frequency, m.bare_peak, m.peak_frequency, m.peak, m.reduction_db, pct, m.reduction_db_lo,
                         m.reduction_db_hi, m.at_band_edge ? 1.0 : 0.0, m.interpolation_db});
        std::printf("%s, mode %zu: %speak reduction %s%.2f dB (%.1f%%), %s; damped peak %.4g m at %.2f Hz (bare %.4g m at %.2f Hz)\n",
                    short_force(F).c_str(), m.mode, m.at_band_edge ? "AT THE BAND'S EDGE: " : "", m.at_band_edge ? "at most " : "",
                    m.reduction_db, pct, interval_text(m.reduction_db_lo, m.reduction_db_hi, m.corners, "%.2f", " dB").c_str(), m.peak,
                    m.peak_frequency, m.bare_peak, m.bare_frequency);
        report_resolution(m, F);
        if (m.at_band_edge)
          std::fprintf(stderr,
                       "warning: %s, mode %zu: the damped peak lies at the band's edge (%.4g Hz of %.4g-%.4g Hz): it may lie beyond the "
                       "band, and the reduction is then only a bound; widen excitation.span\n",
                       short_force(F).c_str(), m.mode, m.peak_frequency, m.lo, m.hi);
      }
    }
    fs::create_directories(out);
    std::vector<TableColumn> columns = {{"force", "N"},           {"mode", "1"},     {"frequency", "Hz"},     {"branch", "1"},
                                        {"cavity_amplitude", "m"}, {"response", "m"}, {"bare_response", "m"}};
    std::vector<std::string> names;  // TableColumn holds the names' characters
    for (std::size_t d = 1; d < dampers.size(); ++d) names.push_back("cavity_amplitude_" + dampers[d].name);
    for (const std::string& n : names) columns.push_back({n.c_str(), "m"});
    write_table_csv(out / "predict.csv", columns, rows);
    write_table_csv(out / "predict_peaks.csv",
                    {{"force", "N"}, {"mode", "1"}, {"bare_frequency", "Hz"}, {"bare_peak", "m"}, {"frequency", "Hz"}, {"peak", "m"},
                     {"reduction_dB", "dB"}, {"reduction_percent", "%"}, {"reduction_dB_lo", "dB"}, {"reduction_dB_hi", "dB"},
                     {"at_band_edge", "1"}, {"interpolation_dB", "dB"}},
                    peaks);
    remove_other_predict_tables(out, false);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("prediction complete: %.2f s wall -> %s/predict.csv, predict_peaks.csv\n", wall, out.string().c_str());
    return 0;
  });
}

}  // namespace bagdem::study
