// summary.json, written and read by the same code (run/summary.hpp). Each section is one pair of
// functions here, so that a key is spelled once for both directions. A NaN is written as null.
#include "bagdem/reduce/summary.hpp"

#include "bagdem/error.hpp"
#include "bagdem/io/atomic_file.hpp"
#include "bagdem/io/json.hpp"

namespace bagdem {
namespace {

using Json = nlohmann::ordered_json;

// Reads the keys of one document, naming the file and the key in every refusal.
struct Keys {
  const std::string& file;
  const Json& at(const Json& j, const char* key) const {
    if (!j.is_object() || !j.contains(key)) throw InputError(file, key, "", "missing from summary.json");
    return j.at(key);
  }
  // A number; null reads as NaN.
  double number(const Json& j, const char* key) const {
    const Json& v = at(j, key);
    if (v.is_null()) return NAN;
    if (!v.is_number()) throw InputError(file, key, v.dump(), "is not a number");
    return v.get<double>();
  }
  template <class Int>
  Int count(const Json& j, const char* key) const {
    const Json& v = at(j, key);
    if (!v.is_number_integer() || v.get<long long>() < 0) throw InputError(file, key, v.dump(), "is not a count");
    return v.get<Int>();
  }
  std::string text(const Json& j, const char* key) const {
    const Json& v = at(j, key);
    if (!v.is_string()) throw InputError(file, key, v.dump(), "is not a string");
    return v.get<std::string>();
  }
  bool flag(const Json& j, const char* key) const {
    const Json& v = at(j, key);
    if (!v.is_boolean()) throw InputError(file, key, v.dump(), "is not true or false");
    return v.get<bool>();
  }
  // An optional section: absent or null reads as nullopt.
  const Json* section(const Json& j, const char* key) const {
    return j.contains(key) && !j.at(key).is_null() ? &j.at(key) : nullptr;
  }
};

Json number(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }

const char* kind_name(SummaryKind k) { return k == SummaryKind::stepped_sine ? "stepped-sine" : "run"; }

Json energy_json(const EnergySample& e) {
  return {{"kinetic", e.kinetic},
          {"elastic", e.elastic},
          {"work_cavity", e.work_cavity},
          {"work_gravity", e.work_gravity},
          {"dissipated_normal", e.dissipated_normal},
          {"dissipated_tangential", e.dissipated_tangential},
          {"dissipated_rolling", e.dissipated_rolling},
          {"dissipated_damping", e.dissipated_damping}};
}
EnergySample energy_of(const Keys& k, const Json& j) {
  EnergySample e;
  e.kinetic = k.number(j, "kinetic"), e.elastic = k.number(j, "elastic");
  e.work_cavity = k.number(j, "work_cavity"), e.work_gravity = k.number(j, "work_gravity");
  e.dissipated_normal = k.number(j, "dissipated_normal"), e.dissipated_tangential = k.number(j, "dissipated_tangential");
  e.dissipated_rolling = k.number(j, "dissipated_rolling"), e.dissipated_damping = k.number(j, "dissipated_damping");
  return e;
}

Json bag_json(const SummaryBag& b) {
  return {{"balls", b.balls},
          {"film_triangles", b.film_triangles},
          {"packing_fraction", number(b.packing_fraction)},
          {"outer_m", {b.outer.x(), b.outer.y(), b.outer.z()}},
          {"film_self_steps", b.self_steps},
          {"film_self_pairs_max", b.self_pairs_max},
          {"film_wall_stops", b.wall_stops}};
}
SummaryBag bag_of(const Keys& k, const Json& j) {
  SummaryBag b;
  b.balls = k.count<std::size_t>(j, "balls"), b.film_triangles = k.count<std::size_t>(j, "film_triangles");
  b.packing_fraction = k.number(j, "packing_fraction");
  const Json& o = k.at(j, "outer_m");
  if (!o.is_array() || o.size() != 3) throw InputError(k.file, "outer_m", o.dump(), "is not 3 numbers");
  for (int c = 0; c < 3; ++c) b.outer[c] = o[c].is_number() ? o[c].get<double>() : NAN;
  if (j.contains("film_self_steps")) b.self_steps = k.count<std::uint64_t>(j, "film_self_steps");
  if (j.contains("film_self_pairs_max")) b.self_pairs_max = k.count<std::uint64_t>(j, "film_self_pairs_max");
  if (j.contains("film_wall_stops")) b.wall_stops = k.count<std::uint64_t>(j, "film_wall_stops");
  return b;
}

Json decay_json(const DecayFit& d) {
  return {{"peaks", d.peaks},
          {"rate_1_s", number(d.rate)},
          {"damped_frequency_Hz", number(d.damped_frequency)},
          {"damping_ratio", number(d.zeta)},
          {"decay_time_20dB_s", number(d.decay_time)},
          {"measured_decay_time_20dB_s", number(d.measured_decay_time)}};
}
DecayFit decay_of(const Keys& k, const Json& j) {
  DecayFit d;
  d.peaks = k.count<std::size_t>(j, "peaks"), d.rate = k.number(j, "rate_1_s");
  d.damped_frequency = k.number(j, "damped_frequency_Hz"), d.zeta = k.number(j, "damping_ratio");
  d.decay_time = k.number(j, "decay_time_20dB_s"), d.measured_decay_time = k.number(j, "measured_decay_time_20dB_s");
  return d;
}

Json structure_json(const SummaryStructure& s) {
  Json j = {{"kind", s.kind},
            {"response_at_m", s.response_at},
            {"response_rms_m", number(s.response_rms)},
            {"acceleration_rms_m_s2", number(s.acceleration_rms)}};
  if (s.band) {
    j["band_response_rms_m"] = number(s.band->response_rms);
    j["band_Hz"] = {s.band->lo, s.band->hi};
    j["band_from_s"] = s.band->from;
  }
  j["work_external_J"] = number(s.work_external), j["work_contents_J"] = number(s.work_contents);
  j["dissipated_J"] = number(s.dissipated), j["energy_J"] = number(s.energy);
  if (s.decay) j["decay"] = decay_json(*s.decay);
  return j;
}
SummaryStructure structure_of(const Keys& k, const Json& j) {
  SummaryStructure s;
  s.kind = k.text(j, "kind"), s.response_at = k.number(j, "response_at_m");
  s.response_rms = k.number(j, "response_rms_m"), s.acceleration_rms = k.number(j, "acceleration_rms_m_s2");
  if (j.contains("band_response_rms_m")) {
    const Json& band = k.at(j, "band_Hz");
    if (!band.is_array() || band.size() != 2 || !band[0].is_number() || !band[1].is_number())
      throw InputError(k.file, "band_Hz", band.dump(), "is not 2 numbers");
    s.band = SummaryBand{k.number(j, "band_response_rms_m"), band[0].get<double>(), band[1].get<double>(), k.number(j, "band_from_s")};
  }
  s.work_external = k.number(j, "work_external_J"), s.work_contents = k.number(j, "work_contents_J");
  s.dissipated = k.number(j, "dissipated_J"), s.energy = k.number(j, "energy_J");
  if (const Json* d = k.section(j, "decay")) s.decay = decay_of(k, *d);
  return s;
}

Json peak_json(const ModePeak& m) {
  return {{"mode", m.name},
          {"mode_number", m.mode},
          {"bare_frequency_Hz", number(m.bare_frequency)},
          {"bare_peak_m_per_N", number(m.bare_peak)},
          {"frequency_Hz", number(m.frequency)},
          {"peak_m_per_N", number(m.peak)},
          {"simulated_frequency_Hz", number(m.simulated_frequency)},
          {"simulated_peak_m_per_N", number(m.simulated_peak)},
          {"peak_ci95_m_per_N", number(m.peak_ci95)},
          {"reduction_dB", number(m.reduction_db)},
          {"reduction_dB_ci95", number(m.reduction_db_ci95)},
          {"reduction_percent", number(m.reduction_percent)},
          {"at_band_edge", m.at_band_edge},
          {"unsteady_points", m.unsteady_points}};
}
ModePeak peak_of(const Keys& k, const Json& j) {
  ModePeak m;
  m.name = k.text(j, "mode");
  if (j.contains("mode_number")) m.mode = k.count<std::size_t>(j, "mode_number");  // (older summaries lack it)
  m.bare_frequency = k.number(j, "bare_frequency_Hz"), m.bare_peak = k.number(j, "bare_peak_m_per_N");
  m.frequency = k.number(j, "frequency_Hz"), m.peak = k.number(j, "peak_m_per_N");
  m.simulated_frequency = k.number(j, "simulated_frequency_Hz"), m.simulated_peak = k.number(j, "simulated_peak_m_per_N");
  m.peak_ci95 = k.number(j, "peak_ci95_m_per_N");
  m.reduction_db = k.number(j, "reduction_dB"), m.reduction_db_ci95 = k.number(j, "reduction_dB_ci95");
  m.reduction_percent = k.number(j, "reduction_percent");
  m.at_band_edge = k.flag(j, "at_band_edge"), m.unsteady_points = k.count<std::size_t>(j, "unsteady_points");
  return m;
}

Json summary_json(const Summary& s) {
  Json j = {{"status", "complete"}, {"case", s.case_file}, {"kind", kind_name(s.kind)}, {"particles", s.particles}};
  if (!s.damper.empty()) j["damper"] = s.damper;
  if (s.kind == SummaryKind::run) {
    j["steps"] = s.steps, j["dt"] = s.dt, j["dt_reason"] = s.dt_reason, j["threads"] = s.threads;
    j["wall_time_s"] = s.wall_time, j["particle_steps_per_second"] = s.particle_steps_per_second;
    j["ns_per_particle_step"] = s.ns_per_particle_step, j["neighbour_builds"] = s.neighbour_builds;
    j["energy_balance_error"] = number(s.energy_balance_error);
    if (s.energy) j["energy"] = energy_json(*s.energy);
    else j["energy"] = nullptr, j["note"] = "output.energy = false: no energy budget was tallied";
    if (s.bag) j["bag"] = bag_json(*s.bag);
    if (s.structure) j["structure"] = structure_json(*s.structure);
    j["cycles_measured"] = s.cycles_measured, j["dissipated_per_cycle_J"] = number(s.dissipated_per_cycle);
    return j;
  }
  j["dt"] = s.dt, j["threads"] = s.threads, j["chains"] = s.chains, j["wall_time_s"] = s.wall_time;
  j["points"] = s.points, j["not_steady"] = s.not_steady, j["force_amplitude_N"] = s.force_amplitude;
  j["peaks_missing"] = s.peaks_missing;
  j["peaks"] = Json::array();
  for (const ModePeak& m : s.peaks) j["peaks"].push_back(peak_json(m));
  return j;
}

Summary summary_of(const Keys& k, const Json& j) {
  Summary s;
  if (k.text(j, "status") != "complete") throw InputError(k.file, "status", k.text(j, "status"), "is not \"complete\"");
  // Runs of bagdem before this type wrote no kind; a stepped sine always did.
  const std::string kind = j.contains("kind") ? k.text(j, "kind") : "run";
  if (kind != "run" && kind != "stepped-sine") throw InputError(k.file, "kind", kind, "is not \"run\" or \"stepped-sine\"");
  s.kind = kind == "run" ? SummaryKind::run : SummaryKind::stepped_sine;
  s.case_file = k.text(j, "case"), s.particles = k.count<std::size_t>(j, "particles");
  if (j.contains("damper")) s.damper = k.text(j, "damper");
  s.dt = k.number(j, "dt"), s.threads = k.count<int>(j, "threads"), s.wall_time = k.number(j, "wall_time_s");
  if (s.kind == SummaryKind::run) {
    s.steps = k.count<std::uint64_t>(j, "steps"), s.dt_reason = k.text(j, "dt_reason");
    s.particle_steps_per_second = k.number(j, "particle_steps_per_second");
    s.ns_per_particle_step = k.number(j, "ns_per_particle_step");
    s.neighbour_builds = k.count<std::uint64_t>(j, "neighbour_builds");
    s.energy_balance_error = k.number(j, "energy_balance_error");
    if (const Json* e = k.section(j, "energy")) s.energy = energy_of(k, *e);
    if (const Json* b = k.section(j, "bag")) s.bag = bag_of(k, *b);
    if (const Json* st = k.section(j, "structure")) s.structure = structure_of(k, *st);
    s.cycles_measured = k.number(j, "cycles_measured"), s.dissipated_per_cycle = k.number(j, "dissipated_per_cycle_J");
    return s;
  }
  s.chains = k.count<std::size_t>(j, "chains"), s.points = k.count<std::size_t>(j, "points");
  s.not_steady = k.count<std::size_t>(j, "not_steady"), s.force_amplitude = k.number(j, "force_amplitude_N");
  const Json& missing = k.at(j, "peaks_missing");
  if (!missing.is_array()) throw InputError(k.file, "peaks_missing", missing.dump(), "is not a list");
  for (const Json& m : missing) s.peaks_missing.push_back(m.is_string() ? m.get<std::string>() : m.dump());
  const Json& peaks = k.at(j, "peaks");
  if (!peaks.is_array()) throw InputError(k.file, "peaks", peaks.dump(), "is not a list");
  for (const Json& p : peaks) s.peaks.push_back(peak_of(k, p));
  return s;
}

}  // namespace

void write_summary(const std::filesystem::path& path, const Summary& s) { write_atomically(path, summary_json(s).dump(2) + "\n"); }

Summary read_summary(const std::filesystem::path& path) {
  const std::string file = path.string();
  return summary_of(Keys{file}, read_json(path));
}

}  // namespace bagdem
