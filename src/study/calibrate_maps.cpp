// `bagdem calibrate --maps` (study/calibrate.hpp): keys of the structure and its drive (a map is the
// damper's alone, study/damper_record.hpp; a key of the damper is refused) fitted to measured peak
// reductions through the prediction from effective-field maps, one per configuration of the
// targets, instead of coupled DEM. The answer is a prediction, to be checked by coupled DEM.
//
// The fit: weighted least squares over the targets, J(v) = sum_k (r_k / w_k)^2 with r_k the
// predicted minus the measured reduction and w_k = max(half the prediction's range over the map's
// 95% intervals, the tolerance), the tolerance where that range is not known. The keys' coordinates are their values, or their logarithms where
// both bounds are positive and at least 3 apart (search_in_log), scaled to [0, 1] over the bounds.
//   - A scan of `scan` values per key (the bounds included; scan^keys predictions), then a compass
//     search from the best (Kolda, Lewis & Torczon, SIAM Review 45 (2003) 385, sec. 3): each key
//     moved by +-h, the best improvement taken and h doubled (up to the scan's spacing), h halved
//     when none improves, until h < 1e-3 or kMaxSearch predictions (then said not converged).
//   - Intervals (Draper & Smith, Applied Regression Analysis, 3rd ed., 1998, sec. 24.2): with A the
//     Jacobian of r_k / w_k in the coordinates at the minimum (central differences), the
//     covariance s^2 (A^T A)^-1 with s^2 = J / (n - p) for n targets and p keys, and the 95%
//     half-width t_{0.975, n-p} sqrt of its diagonal, mapped back to the key's values (asymmetric
//     in log). None when n = p (no degrees of freedom left); n < p is refused.
// KEY@M fits mode M's element of a key with one value per elastic mode (primary.damping_ratio@3),
// written as the list over every elastic mode, the others keeping the scene's values.
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
  std::vector<int> edge;  // per target: the damped peak lay at the band's edge (a bound only)
  double objective = INFINITY;
  std::string outside;
};

// The scene's value of `key` at elastic mode `mode`: primary.damping_ratio as the structure resolved
// it (a default, a modal table's own, a list's last repeating); another key as the case writes it (a
// list's element, its last repeating, or a number for every mode). NaN when there is none.
double case_element(const Scene& s, const std::string& key, int mode) {
  if (key == "primary.damping_ratio" && s.primary) {
    const Primary& P = *s.primary;
    for (std::size_t k = 0; k < P.size(); ++k)
      if (P.elastic_mode_number(k) == static_cast<std::size_t>(mode)) return P.damping_ratio[k];
    return NAN;
  }
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

// The structure's elastic modes (KEY@M's M runs up to this).
std::size_t elastic_modes(const Primary& P) {
  std::size_t n = 0;
  for (std::size_t k = 0; k < P.size(); ++k) n = std::max(n, P.elastic_mode_number(k));
  return n;
}

std::vector<FitKey> read_keys(const CalibrateArgs& a, const Scene& s, const Targets& targets, std::size_t modes) {
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
      const std::string m = given[i].substr(at + 1);
      const bool digits = !m.empty() && m.size() < 5 && m[0] != '0' && std::all_of(m.begin(), m.end(), [](char c) { return c >= '0' && c <= '9'; });
      if (k.key.empty() || !digits || std::stoul(m) > modes)
        throw InputError("--key", "", given[i], "KEY@M names the element of elastic mode M (1 to " + std::to_string(modes) +
                                                    ", the structure's elastic modes) of a key with one value per mode, e.g. primary.damping_ratio@3");
      k.mode = std::stoi(m);
      if (!std::isfinite(case_element(s, k.key, 1)))
        throw InputError("--key", "", given[i], "KEY@M fits one element of " + k.key + ", the others keeping the case's value: the case gives " + k.key +
                                                    " none (as a number or a list of numbers); give it one with --set");
      if (bounds.empty()) {
        const double v = case_element(s, k.key, k.mode);
        if (!(v > 0)) throw InputError("--bounds", given[i], "", "the case gives " + k.key + " no positive number at mode " + m + " to put default bounds around: give --bounds lo,hi");
        k.lo = v / 4, k.hi = v * 4;
      } else {
        std::tie(k.lo, k.hi) = read_bounds(k.key, bounds, s, k.scale);
        if (!k.scale.unit.empty()) throw InputError("--bounds", given[i], bounds, "KEY@M takes plain numbers (an element of a list of numbers)");
      }
    } else {
      std::tie(k.lo, k.hi) = read_bounds(k.key, bounds, s, k.scale);
    }
    if (k.key == targets.config_key)
      throw InputError("--key", "", given[i], "is the targets' configuration column: the key fitted must be another");
    for (const FitKey& o : keys)
      if (o.key == k.key && (o.mode == k.mode || (o.mode == 0) != (k.mode == 0)))
        throw InputError("--key", "", given[i], "is fitted twice (" + o.given + ")");
    k.log = search_in_log(k.lo, k.hi);
    keys.push_back(k);
  }
  if (targets.list.size() < keys.size())
    throw InputError("--key", "", given.back(), std::to_string(keys.size()) + " keys cannot be fitted to " + std::to_string(targets.list.size()) +
                                                    " target" + (targets.list.size() == 1 ? "" : "s") + ": give at least as many targets as keys");
  return keys;
}

// Per key fitted by mode (KEY@M), the scene's value at each of `modes` elastic modes: the elements
// the fit leaves alone, read once.
std::map<std::string, std::vector<double>> base_lists(const std::vector<FitKey>& keys, const Scene& base, std::size_t modes) {
  std::map<std::string, std::vector<double>> lists;
  for (const FitKey& k : keys)
    if (k.mode > 0 && !lists.count(k.key))
      for (int m = 1; m <= static_cast<int>(modes); ++m) lists[k.key].push_back(case_element(base, k.key, m));
  return lists;
}

// The overrides that put the keys at `u`: a key with one value per mode (KEY@M) as its whole list
// (`lists`, base_lists), the fitted elements at `u`.
std::vector<std::string> key_sets(const std::vector<FitKey>& keys, const std::vector<double>& u,
                                  std::map<std::string, std::vector<double>> lists) {
  std::vector<std::string> sets;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (keys[i].mode == 0) sets.push_back(keys[i].key + "=" + keys[i].scale.toml(keys[i].value(u[i])));
    else lists[keys[i].key][static_cast<std::size_t>(keys[i].mode - 1)] = keys[i].value(u[i]);
  }
  for (const auto& [key, values] : lists) {
    std::string list;
    for (std::size_t m = 0; m < values.size(); ++m) list += (m ? ", " : "") + short_text(values[m]);
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
    maps.push_back({fs::absolute(csv).lexically_normal(), *d});
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
    cfg.map = read_recorded_map(cfg.map_csv);
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
  std::map<std::string, std::vector<double>> lists;  // base_lists
  Targets targets;
  std::vector<FitKey> keys;
  std::vector<Config> configs;
  double tolerance = 0.1;
  int points = 400;
  int evaluations = 0;

  // The case of configuration `c` with the keys at `u`; InputError when it does not load or its
  // damper is not the map's.
  Scene scene_at(const Config& c, const std::vector<double>& u) const {
    std::vector<std::string> s = sets;
    if (!c.set.empty()) s.push_back(c.set);
    const std::vector<std::string> ks = key_sets(keys, u, lists);
    s.insert(s.end(), ks.begin(), ks.end());
    Scene scene = load_case(case_dir, s);
    if (const std::vector<std::string> diff = damper_differences(c.damper, damper_record(scene)); !diff.empty())
      throw InputError("changes the damper (" + diff.front() + "): a map is of one damper and cannot vary it; calibrate that key by coupled DEM (without --maps)");
    return scene;
  }

  // Before anything is written: each key at each of its bounds (the others mid-way) loads at every
  // configuration and keeps its damper; else InputError naming the key, the bound and why.
  void check_bounds(const std::vector<std::string>& bounds) const {
    for (std::size_t i = 0; i < keys.size(); ++i)
      for (double end : {0.0, 1.0}) {
        std::vector<double> u(keys.size(), 0.5);
        u[i] = end;
        for (const Config& c : configs) try {
            scene_at(c, u);
          } catch (const InputError& e) {
            throw InputError("--key", keys[i].given, i < bounds.size() ? bounds[i] : "",
                             "at " + keys[i].scale.given(keys[i].value(end)) + (c.given.empty() ? "" : " (" + c.given + ")") + ": " + e.what());
          }
      }
  }

  Fit at(const std::vector<double>& u) {
    ++evaluations;
    Fit f;
    f.u = u;
    const std::size_t n = targets.list.size();
    f.db.assign(n, NAN), f.lo.assign(n, NAN), f.hi.assign(n, NAN), f.weight.assign(n, NAN), f.edge.assign(n, 0);
    for (const Config& c : configs) {
      Scene scene;
      try {
        scene = scene_at(c, u);
      } catch (const InputError& e) {
        std::string at;
        for (std::size_t i = 0; i < keys.size(); ++i) at += (i ? ", " : "") + keys[i].given + " = " + keys[i].scale.given(keys[i].value(u[i]));
        throw InputError("--key", "", "", "at " + at + (c.given.empty() ? "" : " (" + c.given + ")") + ": " + e.what());
      }
      const Primary& P = *scene.primary;
      for (const PredictedMode& m : predict_modes(P, c.map, P.amplitude, P.stepped_sine->frequencies, points, Checks::interval))
        for (std::size_t k : c.targets) {
          if (targets.list[k].mode != static_cast<int>(m.mode)) continue;
          if (!m.outside.empty()) {
            const std::string why = m.outside_why == "band"    ? "a frequency outside the map's band"
                                    : m.outside_why == "below" ? "the cavity's amplitude below the map's"
                                    : m.outside_why == "above" ? "the cavity's amplitude above the map's"
                                                               : "map cells without figures";
            f.outside = "mode " + std::to_string(m.mode) + (c.given.empty() ? "" : " at " + c.given) + ": " + why;
            continue;
          }
          f.db[k] = m.reduction_db, f.lo[k] = m.reduction_db_lo, f.hi[k] = m.reduction_db_hi, f.edge[k] = m.at_band_edge;
          f.weight[k] = std::isfinite(m.reduction_db_hi - m.reduction_db_lo) ? std::max(0.5 * (m.reduction_db_hi - m.reduction_db_lo), tolerance) : tolerance;
        }
    }
    double J = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const double z = (f.db[k] - targets.list[k].reduction_db) / f.weight[k];
      J += z * z;
    }
    f.objective = std::isfinite(J) ? J : INFINITY;
    return f;
  }
};

// At most this many predictions in the compass search (a warning says when it stopped there).
constexpr int kMaxSearch = 2000;

// Scan then compass search; returns the best fit (`capped`: the search stopped at kMaxSearch).
Fit minimise(Problem& p, int scan, bool& capped) {
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
  capped = false;
  if (!std::isfinite(best.objective)) return best;
  // A success doubles the step (up to the scan's spacing), a failure halves it.
  const double widest = 1.0 / (scan - 1), start = p.evaluations;
  for (double h = 0.5 * widest; h >= 1e-3;) {
    if (p.evaluations - start >= kMaxSearch) {
      capped = true;
      break;
    }
    Fit step;
    for (std::size_t i = 0; i < dims; ++i)
      for (double sign : {-1.0, 1.0}) {
        std::vector<double> u = best.u;
        u[i] = std::clamp(u[i] + sign * h, 0.0, 1.0);
        if (u == best.u) continue;
        Fit f = p.at(u);
        if (f.objective < best.objective && (step.u.empty() || f.objective < step.objective)) step = std::move(f);
      }
    if (step.u.empty()) {
      h *= 0.5;
    } else {
      best = std::move(step);
      h = std::min(2 * h, widest);
    }
  }
  return best;
}

struct KeyInterval {
  double lo = NAN, hi = NAN;  // in the key's unit
  bool moves = true;          // the fit's residuals change with the key at the minimum
};

// The keys' 95% intervals at the minimum (the header's recipe); NaN without degrees of freedom or
// where the Jacobian is singular.
std::vector<KeyInterval> key_intervals(Problem& p, const Fit& best) {
  const std::size_t n = p.targets.list.size(), dims = p.keys.size();
  std::vector<KeyInterval> out(dims);
  constexpr double d = 1e-3;
  Eigen::MatrixXd A(n, dims);
  for (std::size_t i = 0; i < dims; ++i) {
    std::vector<double> up = best.u, down = best.u;
    up[i] = std::min(1.0, up[i] + d), down[i] = std::max(0.0, down[i] - d);
    const Fit a = p.at(up), b = p.at(down);
    for (std::size_t k = 0; k < n; ++k)
      A(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i)) = (a.db[k] - b.db[k]) / (up[i] - down[i]) / best.weight[k];
  }
  for (std::size_t i = 0; i < dims; ++i) {  // from the entries a prediction gave (a step beyond a map's edge gives none)
    bool finite = false, moves = false;
    for (Eigen::Index k = 0; k < A.rows(); ++k)
      if (std::isfinite(A(k, static_cast<Eigen::Index>(i)))) finite = true, moves = moves || A(k, static_cast<Eigen::Index>(i)) != 0;
    out[i].moves = moves || !finite;
  }
  if (n <= dims || !A.allFinite()) return out;
  const Eigen::MatrixXd N = A.transpose() * A;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(N);
  if (!lu.isInvertible()) return out;
  const Eigen::MatrixXd cov = lu.inverse() * (best.objective / static_cast<double>(n - dims));
  const double t = student_t_975(n - dims);
  for (std::size_t i = 0; i < dims; ++i) {
    const double h = t * std::sqrt(cov(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)));
    out[i].lo = p.keys[i].value(best.u[i] - h), out[i].hi = p.keys[i].value(best.u[i] + h);
  }
  return out;
}

void write_fit(const fs::path& out, const Problem& p, const Fit& best, const std::vector<KeyInterval>& iv, const std::string& note) {
  const std::vector<Target>& targets = p.targets.list;
  auto configuration = [&](const Target& t) { return p.targets.config_key.empty() ? std::string() : p.targets.config_key + "=" + p.targets.configs[t.config].given; };
  auto map_of = [&](const Target& t) { return p.configs[p.targets.config_key.empty() ? 0 : t.config].map_csv.string(); };
  std::ostringstream csv;
  csv << "configuration,mode [1],target_db [dB],reduction_db [dB],reduction_db_lo [dB],reduction_db_hi [dB],weight_db [dB],residual_db [dB],at_band_edge [1],map\n";
  for (std::size_t k = 0; k < targets.size(); ++k)
    csv << csv_cell(configuration(targets[k])) << ',' << targets[k].mode << ',' << short_text(targets[k].reduction_db) << ',' << short_text(best.db[k])
        << ',' << short_text(best.lo[k]) << ',' << short_text(best.hi[k]) << ',' << short_text(best.weight[k]) << ','
        << short_text(best.db[k] - targets[k].reduction_db) << ',' << best.edge[k] << ',' << csv_cell(map_of(targets[k])) << '\n';
  for (std::size_t k = 0; k < targets.size(); ++k)
    if (best.edge[k])
      std::fprintf(stderr, "warning: mode %d%s: the predicted peak lies at the band's edge: its reduction is only a bound (widen excitation.span)\n",
                   targets[k].mode, p.targets.where(targets[k]).c_str());
  write_atomically(out / "calibrate.csv", csv.str());

  std::ostringstream js;
  js << "{\n  \"method\": \"maps\",\n  \"keys\": [";
  for (std::size_t i = 0; i < p.keys.size(); ++i) {
    const FitKey& k = p.keys[i];
    const double v = k.value(best.u[i]);
    const bool at_bound = best.u[i] <= 0 || best.u[i] >= 1;
    js << (i ? "," : "") << "\n    {\"key\": \"" << json_escape(k.given) << "\", \"value\": " << short_text(v) << ", \"value_text\": \"" << json_escape(k.scale.given(v))
       << "\", \"ci95_lo\": " << json_number_text(iv[i].lo) << ", \"ci95_hi\": " << json_number_text(iv[i].hi) << ", \"bounds\": [" << short_text(k.lo) << ", "
       << short_text(k.hi) << "], \"at_bound\": " << (at_bound ? "true" : "false") << ", \"moves_fit\": " << (iv[i].moves ? "true" : "false") << "}";
    const std::string range = std::isfinite(iv[i].lo) ? " (95%: " + k.scale.given(iv[i].lo) + " to " + k.scale.given(iv[i].hi) + ")" : " (no interval)";
    std::printf("fitted %s = %s%s%s%s\n", k.given.c_str(), k.scale.given(v).c_str(), range.c_str(), at_bound ? " AT A BOUND: widen --bounds" : "",
                iv[i].moves ? "" : " (THE FIT DOES NOT DEPEND ON IT: leave it out)");
  }
  js << "\n  ],\n  \"tolerance_dB\": " << short_text(p.tolerance) << ",\n  \"objective\": " << json_number_text(best.objective)
     << ",\n  \"degrees_of_freedom\": " << static_cast<long>(targets.size()) - static_cast<long>(p.keys.size()) << ",\n  \"predictions\": " << p.evaluations
     << ",\n  \"targets\": [";
  for (std::size_t k = 0; k < targets.size(); ++k) {
    const double r = best.db[k] - targets[k].reduction_db;
    js << (k ? "," : "") << "\n    {\"mode\": " << targets[k].mode << ", \"configuration\": \"" << json_escape(configuration(targets[k])) << "\", \"target_dB\": "
       << short_text(targets[k].reduction_db) << ", \"reduction_dB\": " << json_number_text(best.db[k]) << ", \"reduction_dB_lo\": " << json_number_text(best.lo[k])
       << ", \"reduction_dB_hi\": " << json_number_text(best.hi[k]) << ", \"residual_dB\": " << json_number_text(r) << "}";
    std::printf("  mode %d%s: predicted %.2f dB (%.2f to %.2f) against %.2f dB (residual %+.2f dB)\n", targets[k].mode, p.targets.where(targets[k]).c_str(),
                best.db[k], best.lo[k], best.hi[k], targets[k].reduction_db, r);
  }
  std::vector<double> residual;
  for (std::size_t k = 0; k < targets.size(); ++k) residual.push_back(best.db[k] - targets[k].reduction_db);
  js << "\n  ],\n  \"mae_dB\": " << mae_by_mode(targets, residual);
  js << ",\n  \"note\": \"" << json_escape(note) << "\"\n}\n";
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
    target_reductions(base, p.targets.list, args.targets_file.empty() ? "--target" : args.targets_file);  // validates the targets' modes
    const std::size_t modes = elastic_modes(*base.primary);
    p.keys = read_keys(args, base, p.targets, modes);
    p.lists = base_lists(p.keys, base, modes);
    if (std::pow(static_cast<double>(args.scan), static_cast<double>(p.keys.size())) > 1e5)
      throw InputError("--scan", "", std::to_string(args.scan), "gives " + std::to_string(args.scan) + "^" + std::to_string(p.keys.size()) +
                                                                     " predictions in the scan: lower it (5 is the default) or fit fewer keys");
    p.configs = assign_maps(args, p.case_dir, p.targets);
    p.tolerance = args.tolerance, p.points = args.points;
    p.check_bounds(args.bounds);
    const fs::path out = fs::absolute(args.out.empty() ? fs::path(p.case_dir) / "calibrate" : fs::path(args.out)).lexically_normal();
    require_same_method(out.string(), true);
    refuse_other_outputs(out, OutputOwner::study);
    OutputLock lock(out);
    for (const char* name : {"calibration.json", "calibrate.csv"}) fs::remove(out / name);  // an earlier fit's tables never outlive a failed one
    std::string keys;
    for (const FitKey& k : p.keys) keys += (keys.empty() ? "" : ", ") + k.given + " in [" + k.scale.given(k.lo) + ", " + k.scale.given(k.hi) + "]" + (k.log ? " (log)" : "");
    std::fprintf(stderr, "bagdem calibrate %s on %zu map%s: %s; %zu targets -> %s\n", p.case_dir.c_str(), p.configs.size(), p.configs.size() == 1 ? "" : "s",
                 keys.c_str(), p.targets.list.size(), out.string().c_str());
    bool capped = false;
    const Fit best = minimise(p, args.scan, capped);
    if (!std::isfinite(best.objective))
      throw InputError("--maps", "", "", "at no value of the keys within their bounds does every target's response lie inside its map (" + best.outside +
                                             "): extend that map (bagdem characterize --gamma, --band) or move the bounds");
    const std::vector<KeyInterval> iv = key_intervals(p, best);
    std::string note = "a prediction from the maps, to be checked by coupled DEM at the keys found";
    if (p.targets.list.size() == p.keys.size()) note += "; as many keys as targets: no degrees of freedom left for an interval";
    if (capped) {
      note += "; the search stopped after " + std::to_string(kMaxSearch) + " predictions, not converged";
      std::fprintf(stderr, "warning: the search stopped after %d predictions before its step fell below 1e-3 of the bounds: the fit is not converged\n", kMaxSearch);
    }
    for (std::size_t i = 0; i < p.keys.size(); ++i)
      if (!iv[i].moves) note += "; the fit does not depend on " + p.keys[i].given;
    write_fit(out, p, best, iv, note);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("calibration on maps complete: %d predictions, %.1f s wall -> %s/calibrate.csv, calibration.json\n", p.evaluations, wall, out.string().c_str());
    return 0;
  });
}

}  // namespace bagdem::study
