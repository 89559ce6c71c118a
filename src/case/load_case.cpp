// Case directory -> resolved Scene. The order of resolution matters only where a step reads what an
// earlier one decided: materials -> interactions -> simulation -> cavity -> motion -> particles ->
// models -> time step -> output. The full schema is in docs/case-schema.md.
#include "bagdem/case/load_case.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <sstream>

#include "bagdem/case/case_reader.hpp"
#include "bagdem/case/overrides.hpp"
#include "bagdem/contact/law.hpp"
#include "bagdem/contact/pair_laws.hpp"
#include "bagdem/error.hpp"
#include "bagdem/neighbour/broad_phase.hpp"

namespace bagdem {
namespace {

std::vector<std::string> resolve_materials(const CaseReader& in, Scene& s) {
  const auto names = in.keys("materials");
  if (names.empty()) in.fail("materials", "needs at least one [materials.<name>] table");
  for (const auto& name : names) {
    const std::string m = "materials." + name;
    Material mat;
    mat.name = name;
    mat.density = in.quantity(m + ".density", dim::density);
    mat.youngs_modulus = in.quantity(m + ".youngs_modulus", dim::pressure);
    mat.poisson_ratio = in.quantity(m + ".poisson_ratio", dim::none);
    if (!(mat.density > 0)) in.fail(m + ".density", "must be > 0 (kg/m^3)");
    if (!(mat.youngs_modulus > 0)) in.fail(m + ".youngs_modulus", "must be > 0 (Pa)");
    if (!(mat.poisson_ratio > -1 && mat.poisson_ratio < 0.5))
      in.fail(m + ".poisson_ratio", "must be in (-1, 0.5)");
    s.materials.push_back(mat);
  }
  return names;
}

// interactions.NAME.law: a name from the table of contact laws (contact/law.hpp), `base`'s if absent.
LawKind read_law(const CaseReader& in, const std::string& key, LawKind base) {
  if (!in.has(key + ".law")) return base;
  const std::string name = in.string(key + ".law");
  const ContactLawRow* row = find_contact_law(name);
  if (!row) in.fail(key + ".law", "must be one of " + contact_law_names());
  return row->kind;
}

Interaction read_interaction(const CaseReader& in, const std::string& key, const Interaction& base) {
  Interaction it = base;
  it.law = read_law(in, key, base.law);
  it.restitution = in.quantity(key + ".restitution", dim::none, base.restitution);
  it.friction = in.quantity(key + ".friction", dim::none, base.friction);
  it.rolling_friction = in.quantity(key + ".rolling_friction", dim::none, base.rolling_friction);
  if (!restitution_in_range(it.restitution)) in.fail(key + ".restitution", std::string("must be in ") + kRestitutionRange);
  if (!(it.friction >= 0)) in.fail(key + ".friction", "must be >= 0");
  if (!(it.rolling_friction >= 0)) in.fail(key + ".rolling_friction", "must be >= 0");
  // The linear spring's constants: a pair that changes law does not inherit them.
  const bool inherits = it.law == base.law;
  if (it.law == LawKind::Hooke) {
    const bool given = in.has(key + ".stiffness");
    if (!given && !(inherits && base.stiffness > 0))
      in.fail(key + ".stiffness", "is required with law = \"hooke\": the normal spring k_n (N/m), > 0");
    it.stiffness = given ? in.quantity(key + ".stiffness", dim::stiffness) : base.stiffness;
    it.stiffness_ratio = in.quantity(key + ".stiffness_ratio", dim::none, inherits ? base.stiffness_ratio : Interaction{}.stiffness_ratio);
    if (!(it.stiffness > 0)) in.fail(key + ".stiffness", "must be > 0 (N/m)");
    // Elastic spheres have k_t / k_n = 2 (1 - nu) / (2 - nu): 2/3 to 1 for nu in [0, 0.5].
    if (!(it.stiffness_ratio > 0 && it.stiffness_ratio <= 1))
      in.fail(key + ".stiffness_ratio", "must be in (0, 1] (k_t / k_n; 2/7 by default; elastic spheres have 2/3 to 1)");
  } else {
    for (const char* k : {".stiffness", ".stiffness_ratio"})
      if (in.has(key + k))
        in.fail(key + k, "is read with law = \"hooke\" only; this pair's law is \"" +
                             std::string(contact_law(it.law).name) + "\" (whose stiffness follows the materials' moduli)");
    it.stiffness = 0, it.stiffness_ratio = Interaction{}.stiffness_ratio;
  }
  return it;
}

// [interactions.default] for every pair, [interactions.A-B] (A, B material names) for one pair.
std::vector<Interaction> resolve_interactions(const CaseReader& in, const std::vector<std::string>& names) {
  const std::size_t n = names.size();
  if (!in.has("interactions.default.restitution"))
    in.fail("interactions.default.restitution", "is required: the restitution of every pair not named otherwise");
  const Interaction def = read_interaction(in, "interactions.default", Interaction{});
  std::vector<Interaction> table(n * n, def);
  std::vector<std::string> named(n * n);  // the table that set each pair: one per pair ([a-b] and [b-a] would overwrite each other)
  for (const auto& key : in.keys("interactions")) {
    if (key == "default") continue;
    bool found = false;
    for (std::size_t cut = key.find('-'); cut != std::string::npos && !found; cut = key.find('-', cut + 1)) {
      const auto a = std::find(names.begin(), names.end(), key.substr(0, cut));
      const auto b = std::find(names.begin(), names.end(), key.substr(cut + 1));
      if (a == names.end() || b == names.end()) continue;
      const auto ia = static_cast<std::size_t>(a - names.begin()), ib = static_cast<std::size_t>(b - names.begin());
      if (!named[ia * n + ib].empty())
        in.fail("interactions." + key, "sets the pair " + *a + "-" + *b + " again (also [interactions." + named[ia * n + ib] +
                                           "]): give one table per pair of materials");
      table[ia * n + ib] = table[ib * n + ia] = read_interaction(in, "interactions." + key, def);
      named[ia * n + ib] = named[ib * n + ia] = key;
      found = true;
    }
    if (!found) in.fail("interactions." + key, "must be named \"<material>-<material>\" with materials from [materials], or \"default\"");
  }
  return table;
}

void resolve_output(const CaseReader& in, Scene& s) {
  const double total = s.settle + s.duration;
  double period = 0;
  if (in.string("cavity.motion.kind", "fixed") == "harmonic")
    period = 1.0 / in.quantity("cavity.motion.frequency", dim::frequency);
  OutputSettings& o = s.output;
  o.frame_interval = in.quantity("output.frame_interval", dim::time, total / 50);
  // With a primary structure the samples (its /structure table, and the response that the decay fit
  // and RMS of the summary use) resolve the oscillation it responds with.
  const double response_period = s.primary && s.primary->response_frequency > 0 ? 1 / s.primary->response_frequency : 0.0;
  const double sample = period > 0 ? period / 100 : response_period > 0 ? std::min(100 * s.dt, response_period / 40) : 100 * s.dt;
  o.cavity_interval = in.quantity("output.cavity_interval", dim::time, std::max(sample, s.dt));
  if (response_period > 0 && o.cavity_interval > response_period / 20) {
    std::ostringstream w;
    w << "output.cavity_interval = " << o.cavity_interval << " s samples the structure's response at "
      << s.primary->response_frequency << " Hz fewer than 20 times per period: its RMS and decay fit lose accuracy; "
      << "use at most " << response_period / 20 << " s (the default samples 40 times)";
    s.warnings.push_back(w.str());
  }
  o.energy_interval = in.quantity("output.energy_interval", dim::time, o.cavity_interval);
  o.checkpoint_interval = in.quantity("output.checkpoint_interval", dim::time, 0.0);
  o.skip_cycles = in.quantity("output.skip_cycles", dim::none, 1.0);
  if (!(o.skip_cycles >= 0)) in.fail("output.skip_cycles", "must be >= 0");
  if (!(o.frame_interval > 0)) in.fail("output.frame_interval", "must be > 0");
  if (!(o.cavity_interval >= s.dt))
    in.fail("output.cavity_interval", "must be at least one time step (" + short_text(s.dt) + " s, " + s.dt_reason + ")");
  if (!(o.energy_interval >= s.dt)) in.fail("output.energy_interval", "must be at least one time step");
  if (!(o.checkpoint_interval >= 0)) in.fail("output.checkpoint_interval", "must be >= 0 (0 = no checkpoints)");
}

// Values that each pass their own check can still combine into a run that cannot be made: an
// infinite Young's modulus or impact speed gives a step of 0, a huge one a step count past any
// machine. A run of more than this many steps is refused, naming the step and how it was chosen.
constexpr double kMaxSteps = 1e12;

void refuse_impossible_run(const CaseReader& in, const Scene& s) {
  const std::string key = "simulation.timestep";
  const std::string value = in.has(key) ? in.value_text(key) : "\"auto\" (the default)";
  const double steps = (s.settle + s.duration) / s.dt;
  if (std::isfinite(s.dt) && s.dt > 0 && steps <= kMaxSteps) return;
  std::ostringstream m;
  m << "resolves to a step of " << s.dt << " s (" << s.dt_reason << "), which makes " << steps << " steps over settle + duration = "
    << s.settle + s.duration << " s; a run must have a step > 0 and at most " << kMaxSteps
    << " steps: check the values that set the step (the materials' youngs_modulus and density, the particles' size, "
       "the expected impact speed from the cavity's motion or the initial velocities) and simulation.duration";
  throw InputError(in.file(), key, value, m.str());
}

// A cavity whose bounding box is more than 100 times the size of its contents (10^6 times their
// volume) is most often a length in the wrong unit, typically an STL file in millimetres read as
// metres: warned about, since it is not impossible.
void warn_oversized_cavity(Scene& s) {
  double contents = 0;
  for (const auto& p : s.particles) contents += 4.0 / 3.0 * std::numbers::pi * p.radius * p.radius * p.radius;
  if (s.bag) contents = std::max(contents, s.bag->size.x() * s.bag->size.y() * s.bag->size.z());
  const Vec3 ext = s.cavity_hi - s.cavity_lo;
  const double cavity = ext.x() * ext.y() * ext.z();
  if (!(contents > 0) || !(cavity > 1e6 * contents)) return;
  std::ostringstream w;
  w << "the cavity (" << ext.x() << " x " << ext.y() << " x " << ext.z() << " m) is " << std::cbrt(cavity / contents)
    << " times the size of its contents (the cube root of its volume over theirs, " << contents << " m^3): ";
  if (s.cavity_kind == "stl")
    w << "is the STL file in millimetres? Set cavity.scale = \"1 mm\" (the length of one unit of the file; default 1 m)";
  else
    w << "check the units of the cavity's keys (cavity.min, cavity.max, cavity.radius, cavity.length): a plain number is in "
         "metres, write \"20 mm\" for millimetres";
  s.warnings.push_back(w.str());
}

}  // namespace

void decide_models(Scene& s) {
  // Model only what the scene requires: look at the pairs that can occur (particle materials
  // against particle and wall materials).
  const std::size_t nm = s.materials.size();
  std::vector<bool> particle(nm, false), touched(nm, false);
  for (const auto& p : s.particles) particle[static_cast<std::size_t>(p.material)] = touched[static_cast<std::size_t>(p.material)] = true;
  for (const auto& w : s.walls) touched[static_cast<std::size_t>(w.material)] = true;
  for (const auto& w : s.mesh_walls) touched[static_cast<std::size_t>(w.material)] = true;
  if (s.bag) {
    // The film touches the balls and the walls: it counts as both a touched and a touching material.
    particle[static_cast<std::size_t>(s.bag->material)] = touched[static_cast<std::size_t>(s.bag->material)] = true;
  }
  s.models.tangential = s.models.rolling = false;
  for (std::size_t a = 0; a < nm; ++a) {
    if (!particle[a]) continue;
    for (std::size_t b = 0; b < nm; ++b) {
      if (!touched[b]) continue;
      const PairLaw& law = s.laws(static_cast<int>(a), static_cast<int>(b));
      s.models.tangential = s.models.tangential || law.friction > 0;
      s.models.rolling = s.models.rolling || law.rolling > 0;
    }
  }
  s.models.rotation = s.models.tangential || s.models.rolling;
  s.models.gravity = s.gravity.norm() > 0;
}

std::uint64_t Scene::total_steps() const {
  return static_cast<std::uint64_t>(std::ceil((settle + duration) / dt - 1e-9));
}

namespace {
// The case as one damper; the other dampers' keys ([[dampers]]) into *dampers when asked for.
Scene load_one(const std::string& case_dir, const std::vector<std::string>& overrides, std::vector<DamperKeys>* dampers) {
  namespace fs = std::filesystem;
  const fs::path file = fs::path(case_dir) / "case.toml";
  if (!fs::is_regular_file(file))
    throw InputError(file.string(), "", "", "no case.toml here: a case is a directory holding case.toml");
  CaseReader in(file.string(), overrides);
  Scene s;
  s.case_dir = case_dir;
  s.case_file = file.string();

  const auto names = resolve_materials(in, s);
  s.laws = make_pair_laws(s.materials, resolve_interactions(in, names));

  s.gravity = in.vector("simulation.gravity", dim::acceleration, Vec3(0, 0, -9.81));
  s.duration = in.quantity("simulation.duration", dim::time);
  s.settle = in.quantity("simulation.settle", dim::time, 0.0);
  if (!(s.duration > 0)) in.fail("simulation.duration", "must be > 0 (s)");
  if (!(s.settle >= 0)) in.fail("simulation.settle", "must be >= 0 (s)");
  s.seed = static_cast<std::uint64_t>(in.integer("simulation.seed", 1, 0, kMaxSeed));
  std::vector<std::string> kinds;
  for (const auto& k : broad_phase_kinds()) kinds.emplace_back(k.name);
  s.broad_phase = in.choice("simulation.neighbour", kinds, "hash");
  s.max_overlap_fraction = in.quantity("simulation.max_overlap", dim::none, 0.1);
  if (!(s.max_overlap_fraction > 0 && s.max_overlap_fraction < 1)) in.fail("simulation.max_overlap", "must be in (0, 1)");
  s.max_energy_error = in.quantity("simulation.max_energy_error", dim::none, 0.05);
  if (!(s.max_energy_error >= 0 && s.max_energy_error < 1)) in.fail("simulation.max_energy_error", "must be in [0, 1) (0: never stop on it)");

  const std::string cav_mat = in.string("cavity.material");
  const auto cm = std::find(names.begin(), names.end(), cav_mat);
  if (cm == names.end()) in.fail("cavity.material", "must name a material defined under [materials]");
  resolve_cavity(in, s, static_cast<int>(cm - names.begin()));
  resolve_motion(in, s);
  resolve_primary(in, s);
  resolve_particles(in, s, names);
  resolve_bag(in, s, names);
  if (s.particles.empty()) in.fail("particles", "needs at least one group [particles.<name>] or a [bag]");

  decide_models(s);
  s.models.energy = in.boolean("output.energy", true);

  double dmax = 0;
  for (const auto& p : s.particles) dmax = std::max(dmax, 2 * p.radius);
  s.skin = in.quantity_or_auto("simulation.skin", dim::length).value_or(0.2 * dmax);
  if (!(s.skin > 0)) in.fail("simulation.skin", "must be > 0 or \"auto\"");

  warn_oversized_cavity(s);
  resolve_timestep(in, s);
  resolve_bending_clock(in, s);
  refuse_impossible_run(in, s);
  resolve_output(in, s);
  const std::vector<DamperKeys> more = read_dampers(in);
  s.damper_name = in.string("damper.name", "1");
  if (dampers) *dampers = more;
  in.reject_unknown_keys();
  s.resolved = in.text();
  s.files = in.files();
  s.defaults = in.defaults();
  return s;
}
}  // namespace

Scene load_case(const std::string& case_dir, const std::vector<std::string>& overrides) {
  std::vector<DamperKeys> keys;
  Scene s = load_one(case_dir, overrides, &keys);
  if (keys.empty()) return s;
  if (!s.primary)
    throw InputError(s.case_file, "dampers", "", "several dampers share one structure ([primary]); under prescribed motion (a case "
                                                  "without [primary], or a command that shakes the cavity itself: characterize, drop) "
                                                  "give each damper as its own case");
  // Each damper: the case with its keys changed; an error there names the damper.
  auto load_damper = [&](std::size_t k, const std::vector<std::string>& extra) {
    std::vector<std::string> o = overrides;
    o.insert(o.end(), keys[k].set.begin(), keys[k].set.end());
    o.insert(o.end(), extra.begin(), extra.end());
    try {
      return load_one(case_dir, o, nullptr);
    } catch (const InputError& e) {
      throw InputError(std::string("damper '") + keys[k].name + "' (dampers." + std::to_string(k) + ".set): " + e.what());
    }
  };
  std::vector<Scene> others;
  for (std::size_t k = 0; k < keys.size(); ++k) others.push_back(load_damper(k, {}));
  // One step for all: the smallest; resolved again at it where a damper's own differs, and each
  // says whose it is.
  double dt = s.dt;
  std::string whose = s.damper_name + ": " + s.dt_reason;
  for (std::size_t k = 0; k < keys.size(); ++k)
    if (others[k].dt < dt) dt = others[k].dt, whose = keys[k].name + ": " + others[k].dt_reason;
  const std::vector<std::string> at_dt = {"simulation.timestep=" + exact_text(dt)};
  bool differ = false;
  if (s.dt != dt) {
    std::vector<std::string> o = overrides;
    o.insert(o.end(), at_dt.begin(), at_dt.end());
    s = load_one(case_dir, o, nullptr);
    differ = true;
  }
  for (std::size_t k = 0; k < keys.size(); ++k)
    if (others[k].dt != dt) others[k] = load_damper(k, at_dt), differ = true;
  if (differ) {
    const std::string reason = "the smallest of the dampers' steps, damper " + whose;
    s.dt_reason = reason;
    for (Scene& d : others) d.dt_reason = reason;
  }
  // The files each damper reads are the case's too (its resolved text is what a resume, a study's
  // points and the reading commands compare): those a damper's keys name beside the case's own.
  for (std::size_t k = 0; k < keys.size(); ++k)
    for (const auto& [key, print] : others[k].files)
      if (const auto it = s.files.find(key); it == s.files.end() || it->second != print) {
        const std::string name = "dampers." + keys[k].name + "." + key;
        s.files[name] = print;
        s.resolved += "\n# reads " + name + " = " + print;
      }
  join_dampers(s, others, keys);
  return s;
}

namespace {
// The "# reads KEY = FINGERPRINT" lines of a resolved case (CaseReader::text), by key.
std::map<std::string, std::string> files_read(const std::string& text) {
  std::map<std::string, std::string> files;
  std::istringstream in(text);
  const std::string tag = "# reads ";
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(tag, 0) != 0) continue;
    const std::size_t eq = line.find(" = ", tag.size());
    if (eq != std::string::npos) files[line.substr(tag.size(), eq - tag.size())] = line.substr(eq + 3);
  }
  return files;
}
}  // namespace

std::string case_differences(const std::string& was, const std::string& now, const std::vector<std::string>& ignore) {
  // By key: each differing key with its two values as written (TOML), the first few.
  try {
    const toml::table a = toml::parse(was), b = toml::parse(now);
    std::map<std::string, std::string> va, vb;
    auto text = [](const toml::node& n) {
      std::ostringstream o;
      n.visit([&](const auto& x) { o << x; });
      return o.str();
    };
    for (const auto& [k, n] : toml_leaves(a, "", ignore)) va[k] = text(*n);
    for (const auto& [k, n] : toml_leaves(b, "", ignore)) vb[k] = text(*n);
    std::vector<std::string> diff;
    for (const auto& [k, x] : va)
      if (const auto it = vb.find(k); it == vb.end() || it->second != x) diff.push_back(k + ": was " + x + ", now " + (it == vb.end() ? "not set" : it->second));
    for (const auto& [k, y] : vb)
      if (!va.count(k)) diff.push_back(k + ": was not set, now " + y);
    // The files the case reads (CaseReader::text's "# reads KEY = FINGERPRINT" lines, which TOML skips).
    const std::map<std::string, std::string> fa = files_read(was), fb = files_read(now);
    for (const auto& [k, x] : fa)
      if (const auto it = fb.find(k); it == fb.end() || it->second != x)
        diff.push_back("the file at " + k + ": was " + x + ", now " + (it == fb.end() ? "not read" : "edited (" + it->second + ")"));
    for (const auto& [k, y] : fb)
      if (!fa.count(k)) diff.push_back("the file at " + k + ": was not fingerprinted (a bagdem before file fingerprints), now " + y);
    std::string list;
    for (std::size_t k = 0; k < diff.size() && k < 4; ++k) list += (k ? "; " : "") + diff[k];
    if (diff.size() > 4) list += "; and " + std::to_string(diff.size() - 4) + " more";
    return list;
  } catch (const toml::parse_error&) {
  }
  // Not TOML (an old file): the first differing line.
  std::istringstream sa(was), sb(now);
  std::string la, lb;
  while (true) {
    const bool ga = static_cast<bool>(std::getline(sa, la)), gb = static_cast<bool>(std::getline(sb, lb));
    if (!ga && !gb) return "";
    if (!ga) la = "(nothing)";
    if (!gb) lb = "(nothing)";
    if (la != lb || !ga || !gb) return "was '" + la + "', now '" + lb + "'";
  }
}

}  // namespace bagdem
