// `bagdem calibrate --maps` (study/calibrate.hpp): keys of the structure and its drive fitted to
// measured peak reductions through the prediction from effective-field maps, one map per
// configuration of the targets, instead of coupled DEM.
//
// A map is the damper's alone (study/damper_record.hpp): the force, the structure and its damping
// move the prediction without a new map, so several keys can be fitted to many figures in seconds.
// What a map cannot vary (a key of the damper) is refused. The answer is a prediction: check it
// with coupled DEM (bagdem sweep at the keys found), as docs/calibrate.md says.
//
// The fit: weighted least squares over the targets, J(v) = sum_k (r_k / w_k)^2 with r_k the
// predicted minus the measured reduction and w_k = max(half the prediction's range over the map's
// 95% intervals, the tolerance). The keys' coordinates are their values, or their logarithms where
// both bounds are positive and at least 3 apart (search_in_log), scaled to [0, 1] over the bounds.
//   - A scan of `scan` values per key (the bounds included; scan^keys predictions), then a compass
//     search from the best (Kolda, Lewis & Torczon, SIAM Review 45 (2003) 385, sec. 3): each key
//     moved by +-h, the best improvement taken, h halved when none improves, until h < 1e-3.
//   - Intervals (Draper & Smith, Applied Regression Analysis, 3rd ed., 1998, sec. 24.2): with A the
//     Jacobian of r_k / w_k in the coordinates at the minimum (central differences), the
//     covariance s^2 (A^T A)^-1 with s^2 = J / (n - p) for n targets and p keys, and the 95%
//     half-width t_{0.975, n-p} sqrt of its diagonal, mapped back to the key's values (asymmetric
//     in log). None when n <= p (the keys are then determined, not estimated).
// A key written KEY@M fits the element of elastic mode M of an array key (primary.damping_ratio@3:
// mode 3's damping ratio), the others keeping the case's value (its last element repeating).
#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>
#include <toml++/toml.h>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/atomic_file.hpp"
#include "bagdem/io/json.hpp"
#include "bagdem/io/output_lock.hpp"
#include "bagdem/reduce/interval.hpp"
#include "bagdem/reduce/predict.hpp"
#include "bagdem/study/calibrate.hpp"
#include "bagdem/study/damper_record.hpp"
#include "bagdem/study/study.hpp"
#include "calibrate_targets.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;

namespace {

// A fitted key: a case key, or (mode > 0) the element of that elastic mode of an array key.
struct FitKey {
  std::string given, key;
  int mode = 0;
  Scale scale;
  double lo = 0, hi = 0;
  bool log = false;
  double value(double u) const { return log ? lo * std::pow(hi / lo, u) : lo + u * (hi - lo); }
};

// One configuration of the targets: its override, its map, and the targets measured there.
struct Config {
  std::string set;  // "KEY=VALUE" ("" without a configuration column)
  std::string given;
  fs::path map_csv;
  EffectiveMap map;
  DamperRecord damper;
  std::vector<std::size_t> targets;
};

// The prediction at one point of the keys: per target the reduction and its range (NaN where the
// map does not cover the response: `outside` says where).
struct Fit {
  std::vector<double> u;
  std::vector<double> db, lo, hi, weight;
  double objective = INFINITY;
  std::string outside;
};

// The case's value of `key` at elastic mode `mode` (an array's element, its last repeating; a
// number applies to every mode): a plain number, or NaN.
double case_element(const Scene& s, const std::string& key, int mode) {
  try {
    const toml::table t = toml::parse(s.resolved);
    const toml::node_view<const toml::node> n = t.at_path(key);
    if (const auto* a = n.as_array(); a && !a->empty()) {
      const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(mode - 1), a->size() - 1);
      return a->get(k)->value<double>().value_or(NAN);
    }
    return n.value<double>().value_or(NAN);
  } catch (const toml::parse_error&) {
    return NAN;
  }
}

std::vector<FitKey> read_keys(const CalibrateArgs& a, const Scene& s, const Targets& targets) {
  std::vector<std::string> given = a.keys.empty() ? std::vector<std::string>{"excitation.amplitude"} : a.keys;
  if (a.bounds.size() > given.size())
    throw InputError("--bounds", "", a.bounds.back(), "is given " + std::to_string(a.bounds.size()) + " times for " + std::to_string(given.size()) +
                                                         " --key: one --bounds per key, in the keys' order");
  std::vector<FitKey> keys;
  for (std::size_t i = 0; i < given.size(); ++i) {
    FitKey k;
    k.given = k.key = given[i];
    const std::string bounds = i < a.bounds.size() ? a.bounds[i] : "";
    if (const auto at = k.key.find('@'); at != std::string::npos) {
      k.key = given[i].substr(0, at);
      char* end = nullptr;
      const long m = std::strtol(given[i].c_str() + at + 1, &end, 10);
      if (at + 1 == given[i].size() || *end != '\0' || m < 1 || m > 1000)
        throw InputError("--key", "", given[i], "KEY@M names the element of elastic mode M (1, 2, ...) of an array key, e.g. primary.damping_ratio@3");
      k.mode = static_cast<int>(m);
      if (bounds.empty()) {
        const double v = case_element(s, k.key, k.mode);
        if (!(v > 0)) throw InputError("--bounds", given[i], "", "the case gives " + k.key + " no positive number at mode " + std::to_string(m) + " to put default bounds around: give --bounds lo,hi");
        k.lo = v / 4, k.hi = v * 4;
      } else {
        std::tie(k.lo, k.hi) = read_bounds(k.key, bounds, s, k.scale);
        if (!k.scale.unit.empty()) throw InputError("--bounds", given[i], bounds, "KEY@M takes plain numbers (an element of an array of numbers)");
      }
    } else {
      std::tie(k.lo, k.hi) = read_bounds(k.key, bounds, s, k.scale);
    }
    if (k.key == targets.config_key)
      throw InputError("--key", "", given[i], "is the targets' configuration column: the key fitted must be another");
    for (const FitKey& o : keys)
      if (o.given == k.given || (o.key == k.key && (o.mode == 0) != (k.mode == 0)))
        throw InputError("--key", "", given[i], "is fitted twice (" + o.given + ")");
    k.log = search_in_log(k.lo, k.hi);
    keys.push_back(k);
  }
  return keys;
}

// The overrides that put the keys at `u` (an array key's elements gathered into one --set).
std::vector<std::string> key_sets(const std::vector<FitKey>& keys, const std::vector<double>& u, const Scene& base) {
  std::vector<std::string> sets;
  std::map<std::string, std::map<int, double>> arrays;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (keys[i].mode == 0) sets.push_back(keys[i].key + "=" + keys[i].scale.toml(keys[i].value(u[i])));
    else arrays[keys[i].key][keys[i].mode] = keys[i].value(u[i]);
  }
  for (const auto& [key, elements] : arrays) {
    std::string list;
    for (int m = 1; m <= elements.rbegin()->first; ++m) {
      const auto e = elements.find(m);
      list += (m > 1 ? ", " : "") + short_text(e != elements.end() ? e->second : case_element(base, key, m));
    }
    sets.push_back(key + "=[" + list + "]");
  }
  return sets;
}

// Each configuration with the map of its damper among `maps` (by damper.toml); InputError naming
// the configuration and the nearest map's differences when none is.
std::vector<Config> assign_maps(const CalibrateArgs& a, const std::string& case_dir, const Targets& targets) {
  struct Candidate {
    fs::path csv;
    DamperRecord damper;
  };
  std::vector<Candidate> maps;
  for (const std::string& m : a.maps) {
    fs::path csv = m;
    if (fs::is_directory(csv)) csv /= "map.csv";
    if (!fs::exists(csv)) throw InputError("--maps", "", m, "holds no map.csv (bagdem characterize's OUT, or the file)");
    const std::optional<DamperRecord> d = read_damper_record(csv.parent_path() / "damper.toml");
    if (!d) throw InputError("--maps", "", m, "records no damper (no damper.toml beside map.csv, as bagdem characterize writes): calibrate cannot tell which configuration it is of");
    maps.push_back({csv, *d});
  }
  std::vector<Config> configs;
  const std::size_t n = targets.config_key.empty() ? 1 : targets.configs.size();
  for (std::size_t c = 0; c < n; ++c) {
    Config cfg;
    if (!targets.config_key.empty()) cfg.set = targets.config_key + "=" + targets.configs[c].toml, cfg.given = targets.config_key + " = " + targets.configs[c].given;
    std::vector<std::string> sets = a.sets;
    if (!cfg.set.empty()) sets.push_back(cfg.set);
    cfg.damper = damper_record(load_case(case_dir, sets));
    std::vector<std::string> nearest;
    std::size_t fewest = SIZE_MAX;
    for (const Candidate& m : maps) {
      const std::vector<std::string> diff = damper_differences(m.damper, cfg.damper);
      if (diff.empty() && !cfg.map_csv.empty())
        throw InputError("--maps", "", m.csv.string(), "characterises the same damper as " + cfg.map_csv.string() + " (" + (cfg.given.empty() ? "the case's" : cfg.given) + "): give one map per configuration");
      if (diff.empty()) cfg.map_csv = m.csv;
      else if (diff.size() < fewest) fewest = diff.size(), nearest = diff;
    }
    if (cfg.map_csv.empty()) {
      std::string list;
      for (std::size_t k = 0; k < nearest.size() && k < 4; ++k) list += (k ? "; " : "") + nearest[k];
      throw InputError("--maps", "", "", "no map characterises the damper " + (cfg.given.empty() ? "of the case" : "at " + cfg.given) + " (the nearest: " + list +
                                             "). Characterize it: bagdem characterize " + case_dir + (cfg.set.empty() ? "" : " --set '" + cfg.set + "'"));
    }
    cfg.map = read_effective_map(cfg.map_csv);
    for (std::size_t k = 0; k < targets.list.size(); ++k)
      if (targets.list[k].config == c) cfg.targets.push_back(k);
    configs.push_back(std::move(cfg));
  }
  for (const Candidate& m : maps) {
    bool used = false;
    for (const Config& c : configs) used = used || c.map_csv == m.csv;
    if (!used) std::fprintf(stderr, "warning: %s is the map of no configuration of the targets: not used\n", m.csv.string().c_str());
  }
  return configs;
}

struct Problem {
  std::string case_dir;
  std::vector<std::string> sets;
  const Scene* base = nullptr;
  Targets targets;
  std::vector<FitKey> keys;
  std::vector<Config> configs;
  double tolerance = 0.1;
  int points = 400;
  int evaluations = 0;

  Fit at(const std::vector<double>& u) {
    ++evaluations;
    Fit f;
    f.u = u;
    const std::size_t n = targets.list.size();
    f.db.assign(n, NAN), f.lo.assign(n, NAN), f.hi.assign(n, NAN), f.weight.assign(n, NAN);
    const std::vector<std::string> ks = key_sets(keys, u, *base);
    for (const Config& c : configs) {
      std::vector<std::string> s = sets;
      if (!c.set.empty()) s.push_back(c.set);
      s.insert(s.end(), ks.begin(), ks.end());
      const Scene scene = load_case(case_dir, s);
      if (const std::vector<std::string> diff = damper_differences(c.damper, damper_record(scene)); !diff.empty())
        throw InputError("--key", "", ks.front(), "changes the damper (" + diff.front() + "): a map is of one damper and cannot vary it; calibrate that key by coupled DEM (without --maps)");
      const Primary& P = *scene.primary;
      for (const PredictedMode& m : predict_modes(P, c.map, P.amplitude, P.stepped_sine->frequencies, points, Checks::interval))
        for (std::size_t k : c.targets) {
          if (targets.list[k].mode != static_cast<int>(m.mode)) continue;
          if (!m.outside.empty()) {
            f.outside = "mode " + std::to_string(m.mode) + (c.given.empty() ? "" : " at " + c.given) + " (" + m.outside_why + ")";
            continue;
          }
          f.db[k] = m.reduction_db, f.lo[k] = m.reduction_db_lo, f.hi[k] = m.reduction_db_hi;
          f.weight[k] = std::max(0.5 * (m.reduction_db_hi - m.reduction_db_lo), tolerance);
        }
    }
    double J = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const double z = (f.db[k] - targets.list[k].reduction_db) / f.weight[k];
      J += z * z;
    }
    f.objective = std::isfinite(J) ? J : INFINITY;
    if (f.outside.empty() && !std::isfinite(J)) f.outside = "a target's mode is not among the sweep's peaks";
    return f;
  }
};

// Scan then compass search; returns the best fit.
Fit minimise(Problem& p, int scan) {
  const std::size_t dims = p.keys.size();
  Fit best;
  std::vector<std::size_t> index(dims, 0);
  for (bool more = true; more;) {
    std::vector<double> u(dims);
    for (std::size_t i = 0; i < dims; ++i) u[i] = static_cast<double>(index[i]) / (scan - 1);
    Fit f = p.at(u);
    if (f.objective < best.objective || best.u.empty()) best = std::move(f);
    more = false;
    for (std::size_t i = 0; i < dims && !more; ++i) {
      if (++index[i] < static_cast<std::size_t>(scan)) more = true;
      else index[i] = 0;
    }
  }
  if (!std::isfinite(best.objective)) return best;
  for (double h = 0.5 / (scan - 1); h >= 1e-3;) {
    Fit step;
    for (std::size_t i = 0; i < dims; ++i)
      for (double sign : {-1.0, 1.0}) {
        std::vector<double> u = best.u;
        u[i] = std::clamp(u[i] + sign * h, 0.0, 1.0);
        if (u == best.u) continue;
        Fit f = p.at(u);
        if (f.objective < best.objective && (step.u.empty() || f.objective < step.objective)) step = std::move(f);
      }
    if (step.u.empty()) h *= 0.5;
    else best = std::move(step);
  }
  return best;
}

struct KeyInterval {
  double lo = NAN, hi = NAN;  // in the key's unit
};

// The keys' 95% intervals at the minimum (the header's recipe); NaN without degrees of freedom or
// where the Jacobian is singular.
std::vector<KeyInterval> key_intervals(Problem& p, const Fit& best) {
  const std::size_t n = p.targets.list.size(), dims = p.keys.size();
  std::vector<KeyInterval> out(dims);
  if (n <= dims) return out;
  constexpr double d = 1e-3;
  Eigen::MatrixXd A(n, dims);
  for (std::size_t i = 0; i < dims; ++i) {
    std::vector<double> up = best.u, down = best.u;
    up[i] = std::min(1.0, up[i] + d), down[i] = std::max(0.0, down[i] - d);
    const Fit a = p.at(up), b = p.at(down);
    for (std::size_t k = 0; k < n; ++k)
      A(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i)) = (a.db[k] - b.db[k]) / (up[i] - down[i]) / best.weight[k];
  }
  if (!A.allFinite()) return out;
  const Eigen::MatrixXd N = A.transpose() * A;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(N);
  if (!lu.isInvertible()) return out;
  const Eigen::MatrixXd cov = lu.inverse() * (best.objective / static_cast<double>(n - dims));
  const double t = student_t_975(n - dims);
  for (std::size_t i = 0; i < dims; ++i) {
    const double h = t * std::sqrt(cov(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)));
    out[i] = {p.keys[i].value(best.u[i] - h), p.keys[i].value(best.u[i] + h)};
  }
  return out;
}

std::string json_number(double x) { return std::isfinite(x) ? short_text(x) : "null"; }

void write_fit(const fs::path& out, const Problem& p, const Fit& best, const std::vector<KeyInterval>& iv, const std::string& note) {
  const std::vector<Target>& targets = p.targets.list;
  auto configuration = [&](const Target& t) { return p.targets.config_key.empty() ? std::string() : p.targets.config_key + "=" + p.targets.configs[t.config].given; };
  auto map_of = [&](const Target& t) { return p.configs[p.targets.config_key.empty() ? 0 : t.config].map_csv.string(); };
  std::ostringstream csv;
  csv << "configuration,mode [1],target_db [dB],reduction_db [dB],reduction_db_lo [dB],reduction_db_hi [dB],weight_db [dB],residual_db [dB],map\n";
  for (std::size_t k = 0; k < targets.size(); ++k)
    csv << csv_cell(configuration(targets[k])) << ',' << targets[k].mode << ',' << short_text(targets[k].reduction_db) << ',' << short_text(best.db[k])
        << ',' << short_text(best.lo[k]) << ',' << short_text(best.hi[k]) << ',' << short_text(best.weight[k]) << ','
        << short_text(best.db[k] - targets[k].reduction_db) << ',' << csv_cell(map_of(targets[k])) << '\n';
  write_atomically(out / "calibrate.csv", csv.str());

  std::ostringstream js;
  js << "{\n  \"method\": \"maps\",\n  \"keys\": [";
  for (std::size_t i = 0; i < p.keys.size(); ++i) {
    const FitKey& k = p.keys[i];
    const double v = k.value(best.u[i]);
    const bool at_bound = best.u[i] <= 0 || best.u[i] >= 1;
    js << (i ? "," : "") << "\n    {\"key\": \"" << json_escape(k.given) << "\", \"value\": " << short_text(v) << ", \"value_text\": \"" << json_escape(k.scale.given(v))
       << "\", \"ci95_lo\": " << json_number(iv[i].lo) << ", \"ci95_hi\": " << json_number(iv[i].hi) << ", \"bounds\": [" << short_text(k.lo) << ", "
       << short_text(k.hi) << "], \"at_bound\": " << (at_bound ? "true" : "false") << "}";
    const std::string range = std::isfinite(iv[i].lo) ? " (95%: " + k.scale.given(iv[i].lo) + " to " + k.scale.given(iv[i].hi) + ")" : " (no interval)";
    std::printf("fitted %s = %s%s%s\n", k.given.c_str(), k.scale.given(v).c_str(), range.c_str(), at_bound ? " AT A BOUND: widen --bounds" : "");
  }
  js << "\n  ],\n  \"tolerance_dB\": " << short_text(p.tolerance) << ",\n  \"objective\": " << json_number(best.objective)
     << ",\n  \"degrees_of_freedom\": " << static_cast<long>(targets.size()) - static_cast<long>(p.keys.size()) << ",\n  \"predictions\": " << p.evaluations
     << ",\n  \"targets\": [";
  for (std::size_t k = 0; k < targets.size(); ++k) {
    const double r = best.db[k] - targets[k].reduction_db;
    js << (k ? "," : "") << "\n    {\"mode\": " << targets[k].mode << ", \"configuration\": \"" << json_escape(configuration(targets[k])) << "\", \"target_dB\": "
       << short_text(targets[k].reduction_db) << ", \"reduction_dB\": " << json_number(best.db[k]) << ", \"reduction_dB_lo\": " << json_number(best.lo[k])
       << ", \"reduction_dB_hi\": " << json_number(best.hi[k]) << ", \"residual_dB\": " << json_number(r) << "}";
    std::printf("  mode %d%s: predicted %.2f dB (%.2f to %.2f) against %.2f dB (residual %+.2f dB)\n", targets[k].mode, p.targets.where(targets[k]).c_str(),
                best.db[k], best.lo[k], best.hi[k], targets[k].reduction_db, r);
  }
  js << "\n  ],\n  \"mae_dB\": [";
  std::vector<int> modes;
  for (const Target& t : targets)
    if (std::find(modes.begin(), modes.end(), t.mode) == modes.end()) modes.push_back(t.mode);
  for (std::size_t m = 0; m < modes.size(); ++m) {
    double sum = 0;
    int n = 0;
    for (std::size_t k = 0; k < targets.size(); ++k)
      if (targets[k].mode == modes[m]) sum += std::abs(best.db[k] - targets[k].reduction_db), ++n;
    js << (m ? ", " : "") << "{\"mode\": " << modes[m] << ", \"figures\": " << n << ", \"mae_dB\": " << json_number(sum / n) << "}";
    std::printf("  mode %d: mean absolute residual %.2f dB over %d figure%s\n", modes[m], sum / n, n, n == 1 ? "" : "s");
  }
  js << "],\n  \"note\": \"" << json_escape(note) << "\"\n}\n";
  write_atomically(out / "calibration.json", js.str());
}

}  // namespace

int calibrate_on_maps(const CalibrateArgs& args) {
  const auto t0 = std::chrono::steady_clock::now();
  return reporting_errors([&] {
    Problem p;
    p.case_dir = fs::absolute(args.dir).lexically_normal().string();
    if (!fs::exists(fs::path(p.case_dir) / "case.toml")) throw InputError(args.dir, "", "", "holds no case.toml (bagdem calibrate takes a case directory)");
    if (args.targets.empty() == args.targets_file.empty())
      throw InputError("--target", "", "", "give the measured peak reductions either as --target mode=M,reduction_db=R (repeatable) or as --targets FILE, one of the two");
    if (!args.targets_file.empty()) p.targets = read_targets_file(args.targets_file);
    for (const std::string& t : args.targets) p.targets.list.push_back(parse_target(t));
    p.sets = args.sets;
    const Scene base = load_case(p.case_dir, args.sets);
    if (!base.primary || !base.primary->stepped_sine)
      throw InputError(base.case_file, "excitation.kind", "", "calibrate needs a structure and a stepped-sine sweep: its peak reductions are predicted");
    p.base = &base;
    p.keys = read_keys(args, base, p.targets);
    p.configs = assign_maps(args, p.case_dir, p.targets);
    p.tolerance = args.tolerance, p.points = args.points;
    const fs::path out = fs::absolute(args.out.empty() ? fs::path(p.case_dir) / "calibrate" : fs::path(args.out)).lexically_normal();
    require_same_method(out.string(), true);
    OutputLock lock(out);
    std::string keys;
    for (const FitKey& k : p.keys) keys += (keys.empty() ? "" : ", ") + k.given + " in [" + k.scale.given(k.lo) + ", " + k.scale.given(k.hi) + "]" + (k.log ? " (log)" : "");
    std::fprintf(stderr, "bagdem calibrate %s on %zu map%s: %s; %zu targets -> %s\n", p.case_dir.c_str(), p.configs.size(), p.configs.size() == 1 ? "" : "s",
                 keys.c_str(), p.targets.list.size(), out.string().c_str());
    const Fit best = minimise(p, args.scan);
    if (!std::isfinite(best.objective))
      throw InputError("--maps", "", "", "no value of the keys within their bounds keeps every target's response inside its map (" + best.outside +
                                             "): narrow --bounds or extend the maps (bagdem characterize --gamma, --band)");
    const std::vector<KeyInterval> iv = key_intervals(p, best);
    std::string note = "a prediction from the maps, to be checked by coupled DEM at the keys found";
    if (p.targets.list.size() <= p.keys.size()) note += "; as many keys as targets: the keys are determined, not estimated (no interval)";
    write_fit(out, p, best, iv, note);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("calibration on maps complete: %d predictions, %.1f s wall -> %s/calibrate.csv, calibration.json\n", p.evaluations, wall, out.string().c_str());
    return 0;
  });
}

}  // namespace bagdem::study
