// The study and its points (study/study.hpp): study.toml and the command line, the grid or zip of
// the varied values, validation of every point by loading its case, point.toml, and what an earlier
// sweep left in OUT.
#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "bagdem/case/case_reader.hpp"
#include "bagdem/case/load_case.hpp"
#include "bagdem/case/overrides.hpp"
#include "bagdem/error.hpp"
#include "bagdem/fingerprint.hpp"
#include "bagdem/study/study.hpp"
#include "bagdem/study/trade.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return "";
  const auto b = s.find_last_not_of(" \t\r\n");
  return s.substr(a, b - a + 1);
}

namespace {

// A grid larger than this is a typo (a forgotten --zip, a value list pasted twice).
constexpr std::size_t kMaxPoints = 100000;

bool holds_table(const toml::node& n) {
  if (n.is_table()) return true;
  if (const auto* a = n.as_array())
    for (const auto& e : *a)
      if (holds_table(e)) return true;
  return false;
}

// A TOML value in TOML syntax, canonical so that equal values give equal overrides: floats in the
// shortest form that reads back the same (toml++ prints 17 digits: 0.05 -> 0.050000000000000003),
// arrays element by element, anything else (strings quoted and escaped) by toml++.
std::string toml_text(const toml::node& n) {
  if (const auto* a = n.as_array()) {
    std::string o = "[";
    for (std::size_t k = 0; k < a->size(); ++k) o += (k ? ", " : "") + toml_text(*a->get(k));
    return o + "]";
  }
  if (const auto* f = n.as_floating_point()) {
    const double x = f->get();
    if (std::isnan(x)) return "nan";
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    char b[32];
    std::string o(b, std::to_chars(b, b + sizeof b, x).ptr);
    if (o.find_first_of(".e") == std::string::npos) o += ".0";  // TOML: a float has a point or an exponent
    return o;
  }
  toml::table t;
  t.insert("v", n);
  std::ostringstream s;
  s << toml::toml_formatter(t, toml::format_flags::none);
  const std::string line = trim(s.str());
  return trim(line.substr(line.find('=') + 1));
}

Value value_of(const toml::node& n, const std::string& given_text) {
  Value v;
  v.toml = toml_text(n);
  if (const auto* str = n.as_string()) v.given = str->get();
  else v.given = given_text.empty() ? v.toml : given_text;
  return v;
}

// "key = value" -> "key=value" (CaseReader takes the key up to the first '=' as written).
std::string normal_set(const std::string& set, const std::string& where) {
  const auto eq = set.find('=');
  if (eq == std::string::npos || trim(set.substr(0, eq)).empty())
    throw InputError(where, "set", set, "expected key=value, e.g. simulation.duration=\"0.2 s\"");
  return trim(set.substr(0, eq)) + "=" + trim(set.substr(eq + 1));
}

std::string set_key(const std::string& set) { return trim(set.substr(0, set.find('='))); }  // "key = v" as CaseReader reads it

// Keys under [vary], flattened: "a.b.c" = [...] and a.b.c = [...] (nested tables) alike.
void read_vary(const toml::table& t, const std::string& prefix, const std::string& file, std::vector<Varied>& out) {
  for (const auto& [k, node] : t) {
    const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const auto* sub = node.as_table()) {
      read_vary(*sub, key, file, out);
      continue;
    }
    const auto* list = node.as_array();
    if (!list || list->empty())
      throw InputError(file, "vary." + key, toml_text(node), "must be a non-empty array of values, e.g. [\"4 mm\", \"8 mm\"]");
    Varied v{key, {}};
    for (const auto& e : *list) {
      if (holds_table(e)) throw InputError(file, "vary." + key, "", "values must be strings, numbers, booleans or arrays, not tables");
      v.values.push_back(value_of(e, ""));
    }
    out.push_back(v);
  }
}

// The value at key as written (toml_text), for error messages.
std::string shown(const toml::table& t, const std::string& key) {
  const toml::node* n = t.get(key);
  return n ? toml_text(*n) : "";
}

long long positive_integer(const toml::table& t, const std::string& key, const std::string& file) {
  const auto* n = t.get(key);
  const bool integer = n && n->is_integer();
  const auto v = t[key].value<long long>();
  if (!integer || !v || *v < 1 || *v > 100000) throw InputError(file, key, shown(t, key), "must be an integer from 1 to 100000");
  return *v;
}

// study.toml into `s` (paths relative to the file's directory).
void read_study_file(const fs::path& file, StudySpec& s) {
  const fs::path dir = file.parent_path();
  toml::table t;
  try {
    t = toml::parse_file(file.string());
  } catch (const toml::parse_error& e) {
    std::ostringstream m;
    m << file.string() << ":" << e.source().begin.line << ":" << e.source().begin.column << ": not valid TOML: " << e.description();
    throw InputError(m.str());
  }
  const std::string f = file.string();
  static const std::set<std::string> allowed = {"case", "combine", "seeds", "set", "vary", "jobs", "threads", "cores", "out", "tables", "fidelity"};
  for (const auto& [k, node] : t) {
    const std::string key(k.str());
    if (allowed.count(key)) continue;
    const auto near = nearest_key(key, std::vector<std::string>(allowed.begin(), allowed.end()));
    throw InputError(f, key, toml_text(node),
                     "unknown key; " + (near ? "did you mean '" + *near + "'? " : std::string()) +
                         "study.toml takes case, combine, seeds, set, vary, jobs, threads, cores, out, tables, fidelity");
  }
  const auto c = t["case"].value<std::string>();
  if (!c) throw InputError(f, "case", "", "is required: the base case directory, relative to this file");
  s.case_dir = (dir / *c).lexically_normal().string();
  if (t.contains("combine")) {
    const auto how = t["combine"].value<std::string>();
    if (!how || (*how != "grid" && *how != "zip")) throw InputError(f, "combine", shown(t, "combine"), "must be \"grid\" or \"zip\"");
    s.combine = *how == "zip" ? Combine::zip : Combine::grid;
  }
  if (t.contains("seeds")) s.seeds = static_cast<int>(positive_integer(t, "seeds", f));
  if (t.contains("jobs")) s.jobs = static_cast<int>(positive_integer(t, "jobs", f));
  if (t.contains("threads")) s.threads = static_cast<int>(positive_integer(t, "threads", f));
  if (t.contains("cores")) s.cores = static_cast<int>(positive_integer(t, "cores", f));
  if (t.contains("out")) {
    const auto o = t["out"].value<std::string>();
    if (!o) throw InputError(f, "out", shown(t, "out"), "must be a directory name (relative to this file)");
    s.out_dir = (dir / *o).lexically_normal().string();
  }
  auto strings = [&](const char* key, const char* example) {
    std::vector<std::string> out;
    const auto* a = t[key].as_array();
    if (!a) throw InputError(f, key, shown(t, key), std::string("must be an array of strings, e.g. ") + example);
    for (const auto& e : *a) {
      const auto v = e.value<std::string>();
      if (!v) throw InputError(f, key, shown(t, key), std::string("must be an array of strings, e.g. ") + example);
      out.push_back(*v);
    }
    return out;
  };
  if (t.contains("set"))
    for (const auto& x : strings("set", "[\"simulation.duration = \\\"0.2 s\\\"\"]")) s.sets.push_back(normal_set(x, f));
  if (t.contains("tables")) s.tables = strings("tables", "[\"sweep\", \"peaks\"]");
  if (t.contains("fidelity")) {
    const auto p = t["fidelity"].value<std::string>();
    if (!p || (*p != "fast" && *p != "balanced" && *p != "reference"))
      throw InputError(f, "fidelity", shown(t, "fidelity"), "must be \"fast\", \"balanced\" or \"reference\" (a preset of bagdem trade)");
    s.fidelity = *p;
  }
  if (t.contains("vary")) {
    const auto* v = t["vary"].as_table();
    if (!v) throw InputError(f, "vary", shown(t, "vary"), "must be a table of keys of case.toml and their values: [vary] \"bag.balls.diameter\" = [\"4 mm\", \"8 mm\"]");
    read_vary(*v, "", f, s.vary);
  }
}

std::string join(const std::vector<std::string>& v, const std::string& sep) {
  std::string o;
  for (std::size_t k = 0; k < v.size(); ++k) o += (k ? sep : "") + v[k];
  return o;
}


}  // namespace

std::string fingerprint(const std::string& text) {
  // The offset basis every study's point.toml and every design's map name were made with: a digit
  // short of FNV's (kFnvBasis). Another would refuse every study's resume.
  return hex16(fnv1a64(text.data(), text.size(), 1469598103934665603ULL));
}

Value parse_value(const std::string& text) {
  const std::string t = trim(text);
  try {
    const toml::table parsed = toml::parse("v = " + t);
    const toml::node& n = *parsed.get("v");
    if (holds_table(n)) throw InputError("--vary", "", t, "values must be strings, numbers, booleans or arrays, not tables");
    return value_of(n, t);
  } catch (const toml::parse_error&) {
    return value_of(toml::value<std::string>(t), t);  // a bare word: a string, as --set takes it
  }
}

std::vector<Value> parse_value_list(const std::string& list) {
  std::vector<Value> out;
  std::string cur;
  int depth = 0;
  char quote = 0;
  for (std::size_t k = 0; k < list.size(); ++k) {
    const char c = list[k];
    if (quote) {
      cur += c;
      if (c == '\\' && quote == '"' && k + 1 < list.size()) cur += list[++k];  // an escaped character
      else if (c == quote) quote = 0;
      continue;
    }
    if (c == '"' || c == '\'') quote = c;
    if (c == '[' || c == '{') ++depth;
    if (c == ']' || c == '}') --depth;
    if (c == ',' && depth == 0) {
      out.push_back(parse_value(cur));
      cur.clear();
      continue;
    }
    cur += c;
  }
  out.push_back(parse_value(cur));
  for (const Value& v : out)
    if (v.toml == "\"\"") throw InputError("--vary", "", list, "an empty value: the values are separated by single commas");
  return out;
}

StudySpec read_spec(const SweepArgs& a) {
  if (a.dir.empty()) throw InputError("bagdem " + a.command, "", "", "needs CASE_DIR or STUDY_DIR");
  const fs::path dir = fs::absolute(a.dir).lexically_normal();
  StudySpec s;
  s.command = a.command;
  if (fs::is_regular_file(dir / "study.toml")) {
    s.source = (dir / "study.toml").string();
    read_study_file(dir / "study.toml", s);
    if (s.out_dir.empty()) s.out_dir = (dir / "out").string();
  } else if (fs::is_regular_file(dir / "case.toml")) {
    s.source = "the command line";
    s.case_dir = dir.string();
    s.out_dir = (dir / "study").string();
  } else {
    throw InputError(dir.string(), "", "", "holds neither study.toml (a study) nor case.toml (a case)");
  }
  for (const std::string& v : a.vary) {
    const auto eq = v.find('=');
    const std::string key = eq == std::string::npos ? "" : trim(v.substr(0, eq));
    if (key.empty()) throw InputError("--vary", "", v, "expected key=v1,v2,..., e.g. --vary primary.damping_ratio=0.02,0.05");
    Varied var{key, parse_value_list(v.substr(eq + 1))};
    const auto same = std::find_if(s.vary.begin(), s.vary.end(), [&](const Varied& x) { return x.key == key; });
    if (same != s.vary.end()) *same = var;
    else s.vary.push_back(var);
  }
  for (const std::string& x : a.sets) s.sets.push_back(normal_set(x, "--set"));
  if (a.zip) s.combine = Combine::zip;
  if (a.seeds > 0) s.seeds = a.seeds;
  if (a.jobs > 0) s.jobs = a.jobs;
  if (a.threads > 0) s.threads = a.threads;
  if (a.cores > 0) s.cores = a.cores;
  if (!a.out.empty()) s.out_dir = fs::absolute(a.out).lexically_normal().string();
  if (!fs::is_regular_file(fs::path(s.case_dir) / "case.toml"))
    throw InputError(s.source, "case", s.case_dir, "no case.toml there: the base case is a directory holding case.toml");
  // A fidelity preset: its overrides (of the base case) follow the fixed ones.
  if (!a.fidelity.empty()) s.fidelity = a.fidelity;
  for (const std::string& x : fidelity_sets(s.case_dir, s.sets, s.fidelity.empty() ? "balanced" : s.fidelity)) s.sets.push_back(x);
  return s;
}

std::string point_name(std::size_t index, std::size_t count) {
  const std::size_t width = std::max<std::size_t>(3, std::to_string(count - 1).size());
  const std::string num = std::to_string(index);
  return "point-" + std::string(width - num.size(), '0') + num;
}

std::string Plan::point_dir(const Point& p) const { return (fs::path(spec.out_dir) / p.name).string(); }

Plan make_plan(const StudySpec& spec) {
  Plan plan;
  plan.spec = spec;
  const std::string& src = spec.source;
  std::set<std::string> fixed;
  for (const std::string& s : spec.sets) fixed.insert(set_key(s));
  for (const Varied& v : spec.vary) {
    if (v.values.empty()) throw InputError(src, "vary." + v.key, "", "needs at least one value");
    if (fixed.count(v.key)) throw InputError(src, v.key, "", "is both varied and set: vary it or set it, not both");
  }
  if (spec.seeds < 1) throw InputError(src, "seeds", std::to_string(spec.seeds), "must be >= 1");
  if (spec.seeds > 1) {
    const bool varied = std::any_of(spec.vary.begin(), spec.vary.end(), [](const Varied& v) { return v.key == "simulation.seed"; });
    if (varied || fixed.count("simulation.seed"))
      throw InputError(src, "simulation.seed", "", "is set by the ensemble (seeds > 1 runs seeds 1..N): do not vary or set it too");
  }

  // Combinations: a zip takes the i-th of every list, a grid counts in mixed radix (last key fastest).
  std::size_t combos = 1;
  if (spec.combine == Combine::zip && !spec.vary.empty()) {
    combos = spec.vary[0].values.size();
    for (const Varied& v : spec.vary)
      if (v.values.size() != combos) {
        std::string lengths;
        for (const Varied& w : spec.vary) lengths += (lengths.empty() ? "" : ", ") + w.key + " has " + std::to_string(w.values.size());
        const bool file = src != "the command line";
        throw InputError(src, file ? "combine" : "--zip", file ? "\"zip\"" : "",
                         "takes the value lists together, so they must have equal lengths: " + lengths + " values (or use a grid: " +
                             (file ? "combine = \"grid\")" : "leave out --zip)"));
      }
  } else {
    for (const Varied& v : spec.vary) {
      combos *= v.values.size();
      if (combos > kMaxPoints) break;
    }
  }
  const auto seeds = static_cast<std::size_t>(spec.seeds);
  if (combos * seeds > kMaxPoints)
    throw InputError(src, "vary", "", "gives more than " + std::to_string(kMaxPoints) + " points; split the study");
  const std::size_t n = combos * seeds;

  for (std::size_t c = 0; c < combos; ++c) {
    std::vector<std::size_t> choice(spec.vary.size());
    std::size_t rest = c;
    for (std::size_t k = spec.vary.size(); k-- > 0;) {
      const std::size_t m = spec.vary[k].values.size();
      choice[k] = spec.combine == Combine::zip ? c : rest % m;
      rest /= m;
    }
    for (std::size_t s = 1; s <= seeds; ++s) {
      Point p;
      p.index = plan.points.size();
      p.combination = c;
      p.choice = choice;
      Overrides o(spec.sets);
      for (std::size_t k = 0; k < spec.vary.size(); ++k) o.set(TomlKey{spec.vary[k].key}, spec.vary[k].values[choice[k]].toml);
      if (seeds > 1) {
        p.seed = static_cast<int>(s);
        o.set(keys::seed, static_cast<long long>(s));
      }
      p.sets = std::move(o).sets();
      p.name = point_name(p.index, n);
      plan.points.push_back(p);
    }
  }
  return plan;
}

std::vector<std::string> validate_plan(Plan& plan) {
  std::map<std::string, std::vector<std::string>> warned;  // warning -> the points that gave it
  std::vector<std::string> order;
  for (Point& p : plan.points) {
    std::vector<std::string> own(p.sets.begin() + static_cast<long>(plan.spec.sets.size()), p.sets.end());
    try {
      const Scene s = load_case(plan.spec.case_dir, p.sets);
      p.case_seed = static_cast<long long>(s.seed);
      p.case_hash = fingerprint(s.resolved);
      p.scene = scene_record(s);
      for (const std::string& w : s.warnings) {
        if (!warned.count(w)) order.push_back(w);
        warned[w].push_back(p.name);
      }
    } catch (const InputError& e) {
      throw InputError(p.name + (own.empty() ? "" : " (" + join(own, ", ") + ")") + " does not load: " + e.what());
    }
  }
  std::vector<std::string> out;
  for (const std::string& w : order) {
    const auto& pts = warned[w];
    out.push_back((pts.size() == plan.points.size() ? std::string("every point") : join(pts, ", ")) + ": " + w);
  }
  return out;
}

std::string point_toml(const Plan& plan, const Point& p) {
  toml::table t;
  t.insert("point", static_cast<std::int64_t>(p.index));
  t.insert("case", plan.spec.case_dir);
  t.insert("case_hash", p.case_hash);
  t.insert("seed", static_cast<std::int64_t>(p.seed > 0 ? p.seed : p.case_seed));
  toml::array sets;
  for (const std::string& s : p.sets) sets.push_back(s);
  t.insert("set", sets);
  toml::table vary;
  for (std::size_t k = 0; k < plan.spec.vary.size(); ++k) {
    const toml::table parsed = toml::parse("v = " + plan.spec.vary[k].values[p.choice[k]].toml);
    vary.insert(plan.spec.vary[k].key, *parsed.get("v"));
  }
  t.insert("vary", vary);
  toml::array scene;
  for (const std::string& line : p.scene) scene.push_back(line);
  t.insert("scene", scene);
  std::ostringstream s;
  s << "# bagdem " << plan.spec.command << ": " << p.name << " of " << plan.points.size() << ". Written before its run; point.done beside it\n"
    << "# marks a run that exited 0. case_hash fingerprints the resolved case text (a changed case shows);\n"
    << "# scene is what `bagdem check` says of it (a bagdem with other defaults shows).\n"
    << toml::toml_formatter(t) << "\n";
  return s.str();
}

std::string point_tables_text(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string ext = e.path().extension().string();
    if (e.is_regular_file() && (ext == ".csv" || ext == ".json")) names.push_back(e.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  toml::table tables;
  for (const std::string& n : names)
    if (const auto print = file_fingerprint(dir / n)) tables.insert(n, *print);
  std::ostringstream s;
  s << "# The point's tables as its run left them (a study refuses them changed since):\n" << toml::table{{"tables", tables}} << "\n";
  return s.str();
}

namespace {

// The tables point.done records (point_tables_text) as they are now: the first that differs (or is
// gone), said; empty when all are as recorded, or point.done records none (an earlier bagdem's).
std::string changed_point_table(const fs::path& dir) {
  toml::table t;
  try {
    t = toml::parse_file((dir / "point.done").string());
  } catch (const toml::parse_error&) {
    return "point.done is not readable";
  }
  if (const toml::table* tables = t["tables"].as_table())
    for (const auto& [name, print] : *tables) {
      const auto now = file_fingerprint(dir / std::string(name.str()));
      if (!now) return std::string(name.str()) + " is gone";
      if (*now != print.value<std::string>().value_or("")) return std::string(name.str()) + " is not as its run wrote it";
    }
  return "";
}

}  // namespace

std::vector<bool> done_points(const Plan& plan) {
  std::vector<bool> done(plan.points.size(), false);
  std::set<std::string> names;
  for (const Point& p : plan.points) {
    names.insert(p.name);
    const fs::path dir = plan.point_dir(p);
    if (!fs::exists(dir / "point.done") || !fs::exists(dir / "point.toml")) continue;
    toml::table t;
    try {
      t = toml::parse_file((dir / "point.toml").string());
    } catch (const toml::parse_error&) {
      continue;  // unreadable: not trusted, run again
    }
    std::vector<std::string> sets;
    if (const auto* a = t["set"].as_array())
      for (const auto& e : *a) sets.push_back(e.value<std::string>().value_or(""));
    const std::string hash = t["case_hash"].value<std::string>().value_or("");
    std::vector<std::string> scene;
    if (const auto* a = t["scene"].as_array())
      for (const auto& e : *a) scene.push_back(e.value<std::string>().value_or(""));
    const std::string scene_diff = scene_difference(scene, p.scene);
    if (sets != p.sets || hash != p.case_hash || !scene_diff.empty()) {
      std::string why =
          sets != p.sets   ? "it was run with --set " + join(sets, " --set ") + ", the plan now gives --set " + join(p.sets, " --set ")
          : hash != p.case_hash ? "its case resolves differently now (the base case or a file it reads was edited)"
          : scene.empty()  ? "it was run by a bagdem that did not record the scene it resolved (before point.toml's `scene`), "
                             "so this one cannot tell whether its defaults were the same"
                           : "this bagdem resolves its case to another scene (another default or rule): " + scene_diff;
      throw InputError("the study changed: " + (dir / "point.toml").string() + ": " + why +
                       ". Keep the study as it was (its case, options and bagdem), give another --out, or delete " + dir.string() +
                       " to run it again");
    }
    if (const std::string changed = changed_point_table(dir); !changed.empty())
      throw InputError("the study's point " + dir.string() + " changed since its run finished: " + changed +
                       " (point.done records each table's fingerprint). Delete " + dir.string() + " to run it again");
    done[p.index] = true;
  }
  if (fs::is_directory(plan.spec.out_dir))
    for (const auto& e : fs::directory_iterator(plan.spec.out_dir)) {
      const std::string name = e.path().filename().string();
      if (e.is_directory() && name.rfind("point-", 0) == 0 && !names.count(name))
        throw InputError("the study changed: " + e.path().string() + " is not a point of the plan (" + std::to_string(plan.points.size()) +
                         " points, " + plan.points.front().name + " to " + plan.points.back().name +
                         "). Give another --out, or delete the point directories of the earlier study");
    }
  return done;
}

}  // namespace bagdem::study
