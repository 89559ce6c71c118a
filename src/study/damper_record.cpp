// The damper a map characterises (study/damper_record.hpp).
#include "bagdem/study/damper_record.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "bagdem/case/case_reader.hpp"
#include "bagdem/contact/law.hpp"
#include "bagdem/error.hpp"
#include "bagdem/fingerprint.hpp"
#include "bagdem/io/atomic_file.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "bagdem/units.hpp"

namespace bagdem::study {
namespace {

const std::string kDefault = "(default) ";
// Keys recorded since defaults were: a map whose record lacks one was made before, and is not
// compared on it (its maps of the shipped cases stay theirs).
const std::set<std::string> kRecordedLater = {"simulation.timestep_safety", "simulation.steps_per_contact", "simulation.expected_speed"};

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::string number(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.12g", x);
  return b;
}

// An axis as recorded ("x", "[2, 0, 0]", either as a default "(default) ..."), as its unit vector's
// text; any other text as it is.
std::string unit_axis(const std::string& recorded) {
  const bool by_default = recorded.rfind(kDefault, 0) == 0;
  const std::string v = by_default ? recorded.substr(kDefault.size()) : recorded;
  Vec3 u = Vec3::Zero();
  if (v == "x" || v == "y" || v == "z") u[v[0] - 'x'] = 1;
  if (u.norm() == 0) {
    double a = 0, b = 0, c = 0;
    int end = 0;
    if (std::sscanf(v.c_str(), "[%lf, %lf, %lf]%n", &a, &b, &c, &end) != 3 || end != static_cast<int>(v.size())) return recorded;
    u = Vec3(a, b, c);
    if (!(u.norm() > 0) || !u.allFinite()) return recorded;
    u.normalize();
  }
  return (by_default ? kDefault : "") + "[" + number(u.x()) + ", " + number(u.y()) + ", " + number(u.z()) + "]";
}

// Two laws of one pair (model.pair.A/B: damper_record's "LAW, e E, damping D, ..."), as the parts
// that differ: "model.pair.A/B (the law of A on B, from [interactions] and [materials]): e 0.3 in the
// map, e 0.35 in the case".
std::string law_difference(const std::string& key, const std::string& map, const std::string& case_law) {
  auto parts = [](const std::string& law) {
    std::vector<std::string> p;
    for (std::size_t at = 0; at <= law.size();) {
      const std::size_t cut = std::min(law.find(", ", at), law.size());
      p.push_back(law.substr(at, cut - at));
      at = cut + 2;
    }
    return p;
  };
  const std::vector<std::string> a = parts(map), b = parts(case_law);
  const std::string pair = key.substr(std::string("model.pair.").size());
  const std::size_t slash = pair.find('/');
  std::string text = key + " (the law of " + pair.substr(0, slash) + " on " + pair.substr(slash + 1) + ", from [interactions] and [materials])";
  if (a.size() != b.size()) return text + " is " + map + " in the map, " + case_law + " in the case";
  for (std::size_t i = 0, shown = 0; i < a.size(); ++i)
    if (a[i] != b[i]) text += (shown++ ? "; " : ": ") + a[i] + " in the map, " + b[i] + " in the case";
  return text;
}

// What a record says, with the ways of saying one damper made one (damper_differences):
// - interactions.*: not compared. The resolved law of each pair of the damper's materials
//   (model.pair.A/B, in every record that has model.*) decides, so [interactions.a-b] and
//   [interactions.b-a], a law given at its default and a pair of an unused material are one damper.
// - an axis (KEY.axis): "x", "y", "z" or a vector, as its unit vector.
// (The bag's strings: same_strings.)
DamperRecord canonical(const DamperRecord& r) {
  DamperRecord out;
  for (const auto& [k, v] : r)
    if (k.rfind("interactions.", 0) != 0) out[k] = ends_with(k, ".axis") ? unit_axis(v) : v;
  return out;
}

const std::string kStrings = "bag.strings.";

// The bag's strings (bag.strings.N.*), each as the text of its keys (defaults as their values),
// sorted: two records with the same strings in another order give the same list.
std::vector<std::string> strings_of(const DamperRecord& r) {
  std::map<std::string, std::string> text;  // N -> its keys' text
  for (const auto& [k, v] : r) {
    if (k.rfind(kStrings, 0) != 0) continue;
    const std::size_t dot = k.find('.', kStrings.size());
    if (dot == std::string::npos) continue;
    text[k.substr(kStrings.size(), dot - kStrings.size())] +=
        k.substr(dot + 1) + "=" + (v.rfind(kDefault, 0) == 0 ? v.substr(kDefault.size()) : v) + ";";
  }
  std::vector<std::string> out;
  for (const auto& [n, t] : text) out.push_back(t);
  std::sort(out.begin(), out.end());
  return out;
}

// The bag's strings listed in another order are one damper: when the two records hold the same
// strings, their keys are taken out of both. Otherwise they are compared as the case numbers them,
// so that a refusal names each string by its own index.
void same_strings(DamperRecord& a, DamperRecord& b) {
  if (strings_of(a) != strings_of(b)) return;
  for (DamperRecord* r : {&a, &b})
    for (auto it = r->begin(); it != r->end();) it = it->first.rfind(kStrings, 0) == 0 ? r->erase(it) : std::next(it);
}

}  // namespace

DamperRecord damper_record(const Scene& scene) {
  const toml::table root = toml::parse(scene.resolved);
  DamperRecord r;
  auto given = [&](const std::string& key) { return r.count(key) && r[key].rfind(kDefault, 0) != 0; };  // by the case
  auto is_auto = [&](const std::string& key) { return !given(key) || r[key] == "auto"; };
  auto add = [&](const toml::node& n, const std::string& prefix) {
    for (const auto& [key, leaf] : toml_leaves(n, prefix, {"cavity.motion"}))  // a material is named, never a quantity ("4mm")
      r[key] = ends_with(key, ".material") && leaf->is_string() ? leaf->as_string()->get() : si_text(*leaf);
  };
  for (const char* table : {"bag", "particles", "cavity"})  // the interactions: as the resolved laws, model.pair (below)
    if (const toml::node* n = root.get(table)) add(*n, table);
  // The keys of those tables the case leaves out, at their defaults: "(default) VALUE", the same
  // damper as the key given at that value, and as the key not recorded (a map recorded before the
  // defaults were: damper_differences). A seed's default is not the damper's (the map's runs vary it).
  auto defaults = [&](auto&& of_damper) {
    for (const auto& [key, value] : scene.defaults)
      if (of_damper(key) && !ends_with(key, ".seed") && !r.count(key)) r[key] = kDefault + value;
  };
  defaults([](const std::string& key) {
    return (key.rfind("bag.", 0) == 0 || key.rfind("particles.", 0) == 0 || key.rfind("cavity.", 0) == 0) &&
           key.rfind("cavity.motion", 0) != 0;
  });
  // A step the case fixes (a number, not "auto"; forced past the critical step or not): a map made at
  // a fixed step serves no case at its own, nor the reverse. "auto" is left out, so that the maps of
  // the automatic step made before this record stay the case's; its factors follow.
  if (const toml::table* sim = root["simulation"].as_table()) {
    if (const toml::node* n = sim->get("timestep"); n && n->value<std::string>().value_or("") != "auto") r["simulation.timestep"] = si_text(*n);
    if (const toml::node* n = sim->get("force_timestep"); n && n->value<bool>() == true) r["simulation.force_timestep"] = "true";
  }
  // The automatic step's factors (kRecordedLater: a map recorded before them is not asked for them).
  if (!r.count("simulation.timestep"))
    for (const std::string& key : kRecordedLater) {
      if (const toml::node* n = root.at_path(key).node()) r[key] = si_text(*n);
      else if (const auto d = scene.defaults.find(key); d != scene.defaults.end()) r[key] = kDefault + d->second;
    }
  // The materials the contents and the cavity name.
  std::set<std::string> used;
  for (const auto& [key, value] : r)
    if (ends_with(key, ".material")) used.insert(value.rfind(kDefault, 0) == 0 ? value.substr(kDefault.size()) : value);
  if (const toml::table* m = root["materials"].as_table())
    for (const std::string& name : used)
      if (const toml::node* n = m->get(name)) add(*n, "materials." + name);
  defaults([&](const std::string& key) {
    return std::any_of(used.begin(), used.end(), [&](const std::string& name) { return key.rfind("materials." + name + ".", 0) == 0; });
  });
  const Vec3 g = scene.gravity, e = excitation_direction(scene), d = e.norm() > 0 ? Vec3(e.normalized()) : e;
  r["simulation.gravity"] = "[" + number(g.x()) + ", " + number(g.y()) + ", " + number(g.z()) + "]";
  r["direction"] = "[" + number(d.x()) + ", " + number(d.y()) + ", " + number(d.z()) + "]";
  // The model choices the scene resolves and the case may not name, whose defaults a bagdem can
  // change (none of them depends on the seed, the structure or the time step but the clock's
  // "auto"): the film's bending clock (docs/bag.md, "Time step") and its other resolved parameters
  // (model.film.*), and the law of each pair of the damper's materials (model.pair.A/B).
  if (scene.bag) {
    const Bag& b = *scene.bag;
    r["bag.film.bending_interval"] = std::to_string(b.bending_interval);
    r["model.film.tension_field"] = b.film.tension_field ? "true" : "false";
    r["model.film.bending_stiffness"] = number(b.film.bending_stiffness);
    r["model.film.damping_ratio"] = number(b.damping_ratio);
    r["model.film.mass_scaling"] = number(b.mass_scaling);
    // Recorded when not the hinge, so that the maps of the hinge made before the key stay the case's.
    if (b.film.bending_model == BendingModel::Quadratic) r["model.film.bending_model"] = "quadratic";
    // The radii "auto" are fractions of the mean edge, which the seed's fill moves: recorded as
    // those fractions, and not at all where the case gives a length (its key is in the record).
    if (is_auto("bag.film.contact_radius")) r["model.film.contact_radius_per_edge"] = number(b.contact_radius / b.mean_edge);
    if (is_auto("bag.film.self_radius")) r["model.film.self_radius_per_edge"] = number(b.self_radius / b.mean_edge);
  }
  for (std::size_t i = 0; i < scene.materials.size(); ++i)
    for (std::size_t j = i; j < scene.materials.size(); ++j) {
      if (!used.count(scene.materials[i].name) || !used.count(scene.materials[j].name)) continue;
      const PairLaw& l = scene.laws(static_cast<int>(i), static_cast<int>(j));
      r["model.pair." + scene.materials[i].name + "/" + scene.materials[j].name] =
          std::string(contact_law(l.kind).name) + ", e " + number(l.restitution) + ", damping " + number(l.damping) + ", tangential ratio " +
          number(l.tangential_ratio) + ", stiffness " + number(l.stiffness) + ", mu_s " + number(l.friction) + ", mu_r " + number(l.rolling);
    }
  // The files the damper is made of (its balls, a saved bag, its cavity's surface): their contents,
  // which the keys above only name.
  for (const auto& [key, print] : scene.files)
    if (key.rfind("bag.", 0) == 0 || key.rfind("particles.", 0) == 0 || key.rfind("cavity.file", 0) == 0) r["file." + key] = print;
  // A mass ratio is of the structure's mass: the map's runs pin it (study/characterize.cpp).
  if (given("bag.balls.mass_ratio") && !given("bag.balls.primary_mass") && scene.primary)
    r["bag.balls.primary_mass"] = number(scene.primary->structure_mass);
  return r;
}

void write_damper_record(const std::filesystem::path& path, const DamperRecord& record, const std::optional<MapRecord>& map) {
  toml::table damper;
  for (const auto& [k, v] : record) damper.insert(k, v);
  toml::table root{{"damper", damper}};
  if (map) {
    toml::array bands;
    for (const auto& [lo, hi] : map->bands) bands.push_back(toml::array{lo, hi});
    root.insert("map", toml::table{{"csv", map->csv}, {"bands", bands}});
  }
  std::ostringstream s;
  s << "# The damper this map characterised (bagdem characterize): the case's keys that make it, each in SI,\n"
       "# and the map's own record ([map]: the fingerprint of the map.csv written with it, and its frequency bands).\n"
       "# bagdem predict and design refuse a case whose damper differs, and a map.csv changed since (docs/characterize.md).\n"
    << root << "\n";
  write_atomically(path, s.str());
}

std::string file_print(const std::filesystem::path& path) {
  const std::optional<std::string> print = file_fingerprint(path);
  if (!print) throw InputError(path.string(), "", "", "cannot be read");
  return *print;
}

EffectiveMap read_recorded_map(const std::filesystem::path& map_csv) {
  const std::filesystem::path record = map_csv.parent_path() / "damper.toml";
  std::vector<std::pair<double, double>> bands;
  if (std::filesystem::exists(record)) {
    read_damper_record(record);  // a damaged record is refused here, naming it
    const toml::table t = toml::parse_file(record.string());
    if (const toml::node* m = t.get("map")) {
      const auto csv = t["map"]["csv"].value<std::string>();
      const toml::array* b = t["map"]["bands"].as_array();
      bool good = m->is_table() && csv && b && !b->empty();
      for (std::size_t k = 0; good && k < b->size(); ++k) {
        const toml::array* band = b->get(k)->as_array();
        const auto lo = band && band->size() == 2 ? band->get(0)->value<double>() : std::nullopt,
                   hi = band && band->size() == 2 ? band->get(1)->value<double>() : std::nullopt;
        good = lo && hi && *lo > 0 && *hi >= *lo;
        if (good) bands.emplace_back(*lo, *hi);
      }
      if (!good)
        throw InputError(record.string(), "map", "", "is not as bagdem characterize writes it (csv, the map.csv's fingerprint, and bands, "
                                                     "[lo, hi] in Hz): characterize again");
      if (*csv != file_print(map_csv))
        throw InputError(map_csv.string(), "", "",
                         "is not the map.csv bagdem characterize wrote (" + record.string() + " records " + *csv + "; it is now " +
                             file_print(map_csv) + "): it was edited or damaged since. Characterize again (the runs' points are kept)");
    }
  }
  EffectiveMap map = read_effective_map(map_csv);
  map.bands = bands;
  return map;
}

std::optional<DamperRecord> read_damper_record(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) return std::nullopt;
  toml::table t;
  try {
    t = toml::parse_file(path.string());
  } catch (const toml::parse_error& e) {
    throw InputError(path.string(), "", "", std::string("is not a damper record: ") + std::string(e.description()));
  }
  const toml::table* d = t["damper"].as_table();
  if (!d) throw InputError(path.string(), "damper", "", "is missing: not a damper record of bagdem characterize");
  DamperRecord r;
  for (const auto& [k, v] : *d) {
    const auto s = v.value<std::string>();
    if (!s) throw InputError(path.string(), "damper." + std::string(k.str()), "", "must be a string (the value in SI, as text)");
    r[std::string(k.str())] = *s;
  }
  return r;
}

std::vector<std::string> damper_differences(const DamperRecord& map_as_recorded, const DamperRecord& case_as_recorded) {
  DamperRecord map = canonical(map_as_recorded), case_record = canonical(case_as_recorded);
  same_strings(map, case_record);
  std::vector<std::string> out;
  auto models = [](const DamperRecord& r) { return std::any_of(r.begin(), r.end(), [](const auto& kv) { return kv.first.rfind("model.", 0) == 0; }); };
  if (!models(map) && models(case_record))
    return {"the map was made by an earlier bagdem, which did not record its resolved model choices (model.*): characterize it again"};
  std::set<std::string> keys;
  for (const auto& [k, v] : map) keys.insert(k);
  for (const auto& [k, v] : case_record) keys.insert(k);
  // A key left out, at its default, is the same as the key given at that value, and as the key not
  // recorded (a record made before defaults were, whose bagdem left it out too). A key given in one
  // and not recorded in the other differs: that bagdem's default is not known.
  auto value = [](const std::string& v) { return v.rfind(kDefault, 0) == 0 ? v.substr(kDefault.size()) : v; };
  auto shown = [&](const std::string& v) { return v.rfind(kDefault, 0) == 0 ? value(v) + " (the default)" : v; };
  // A radius given "auto" was recorded without its fraction of the edge before the fraction was
  // recorded for it too: not compared where such a record lacks it.
  auto auto_before = [](const DamperRecord& r, const std::string& k) {
    if (k.rfind("model.film.", 0) != 0 || !ends_with(k, "_per_edge")) return false;
    const auto radius = r.find("bag.film." + k.substr(11, k.size() - 11 - 9));
    return radius != r.end() && radius->second == "auto";
  };
  for (const std::string& k : keys) {
    const auto a = map.find(k), b = case_record.find(k);
    if (a == map.end() && kRecordedLater.count(k)) continue;
    if ((a == map.end() && auto_before(map, k)) || (b == case_record.end() && auto_before(case_record, k))) continue;
    if (a != map.end() && b != case_record.end() && value(a->second) == value(b->second)) continue;
    if ((a == map.end() && b->second.rfind(kDefault, 0) == 0) || (b == case_record.end() && a->second.rfind(kDefault, 0) == 0)) continue;
    if (a != map.end() && b != case_record.end() && k.rfind("model.pair.", 0) == 0) {
      out.push_back(law_difference(k, a->second, b->second));
      continue;
    }
    const std::string x = a == map.end() ? "(not set)" : shown(a->second), y = b == case_record.end() ? "(not set)" : shown(b->second);
    out.push_back(k + " is " + x + " in the map, " + y + " in the case");
  }
  return out;
}

}  // namespace bagdem::study
