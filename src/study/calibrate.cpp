// `bagdem calibrate` (study/calibrate.hpp): the targets and bounds read, the search's rounds run as
// studies, the tables written.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>
#include <toml++/toml.h>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/atomic_file.hpp"
#include "bagdem/io/json.hpp"
#include "bagdem/io/output_lock.hpp"
#include "bagdem/reduce/interval.hpp"
#include "bagdem/study/calibrate.hpp"
#include "bagdem/study/study.hpp"
#include "calibrate_targets.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;

namespace {

// The one key coupled DEM calibrates (--key; excitation.amplitude by default).
std::string key_of(const CalibrateArgs& a) { return a.keys.empty() ? "excitation.amplitude" : a.keys[0]; }

std::string short_number(double x) {
  char b[64];
  std::snprintf(b, sizeof b, "%.4g", x);
  return b;
}

// The reduction of each target at each value of a round's study, over the done seeds (the study
// varies the key, then the targets' configuration key when they have one).
std::vector<std::vector<Estimate>> estimates(const Plan& plan, const std::vector<bool>& finished, const std::vector<Target>& targets,
                                             std::size_t values) {
  std::vector<std::vector<std::vector<double>>> x(values, std::vector<std::vector<double>>(targets.size()));
  auto own_ci = x;  // each run's own interval of its reduction (over its cycles)
  std::vector<std::vector<int>> edges(values, std::vector<int>(targets.size(), 0));
  if (const std::optional<Table> t = merge_table(plan, finished, "peaks")) {
    const std::size_t none = t->columns.size();
    std::size_t c_mode = none, c_db = none, c_ci = none, c_edge = none;
    for (std::size_t c = 0; c < t->columns.size(); ++c) {
      if (t->columns[c] == "mode [1]") c_mode = c;
      if (t->columns[c] == "reduction_dB [dB]") c_db = c;
      if (t->columns[c] == "reduction_dB_ci95 [dB]") c_ci = c;
      if (t->columns[c] == "at_band_edge [1]") c_edge = c;
    }
    if (c_mode < none && c_db < none)
      for (const auto& row : t->rows) {
        if (row[1] != "done" || row[c_mode].empty() || row[c_db].empty()) continue;
        const Point& point = plan.points.at(std::stoul(row[0]));
        const std::size_t combo = point.choice.at(0), config = point.choice.size() > 1 ? point.choice[1] : 0;
        const double mode = std::strtod(row[c_mode].c_str(), nullptr), db = std::strtod(row[c_db].c_str(), nullptr);
        const double ci = c_ci < none && !row[c_ci].empty() ? std::strtod(row[c_ci].c_str(), nullptr) : NAN;
        const bool edge = c_edge < none && row[c_edge] == "1";
        for (std::size_t k = 0; k < targets.size(); ++k)
          if (mode == targets[k].mode && config == targets[k].config && std::isfinite(db))
            x[combo][k].push_back(db), own_ci[combo][k].push_back(ci), edges[combo][k] += edge;
      }
  }
  // Over the starts their interval; one start has only its own, over its cycles.
  std::vector<std::vector<Estimate>> out(values, std::vector<Estimate>(targets.size()));
  for (std::size_t v = 0; v < values; ++v)
    for (std::size_t k = 0; k < targets.size(); ++k) {
      if (x[v][k].empty()) continue;
      const Interval in = independent_interval(x[v][k]);
      out[v][k] = {in.mean, x[v][k].size() == 1 ? own_ci[v][k][0] : in.ci95, static_cast<int>(x[v][k].size()), edges[v][k]};
    }
  return out;
}

// OUT/calibrate.csv (every value run, per target) and OUT/calibration.json (the solutions), and
// the solutions on stdout; a warning per target whose peak lay at the band's edge. Returns whether
// a solution matched.
bool write_results(const std::string& out, const CalibrateArgs& args, const Targets& all, const Scale& scale,
                   const SearchOptions& opt, const SearchResult& r, bool failed) {
  const std::vector<Target>& targets = all.list;
  auto configuration = [&](const Target& t) { return all.config_key.empty() ? std::string() : all.config_key + "=" + all.configs[t.config].given; };
  // calibrate.csv: every value run, per target.
  const std::string unit = scale.unit.empty() ? "1" : scale.unit;
  std::ostringstream csv;
  csv << "round [1]," << key_of(args) << "," << key_of(args) << " [" << (scale.si_unit.empty() ? "1" : scale.si_unit) << "],mode [1],target_db [dB],reduction_db_mean [dB],"
      << "reduction_db_ci95 [dB],seeds [1],at_band_edge [1],residual_db [dB],matched [1],configuration\n";
  for (const Evaluation& e : r.evaluated)
    for (std::size_t k = 0; k < targets.size(); ++k) {
      const Estimate& x = e.at[k];
      const double res = x.mean - targets[k].reduction_db;
      csv << e.round << ",\"" << scale.given(e.value) << "\"," << short_text(e.value * scale.to_si) << ',' << targets[k].mode << ','
          << short_text(targets[k].reduction_db) << ',' << short_text(x.mean) << ',' << short_text(x.ci95) << ',' << x.n << ',' << x.at_band_edge << ',' << short_text(res) << ','
          << (std::abs(res) <= allowance(x, opt.tolerance) ? 1 : 0) << ',' << csv_cell(configuration(targets[k])) << '\n';
    }
  write_atomically(fs::path(out) / "calibrate.csv", csv.str());
  for (std::size_t k = 0; k < targets.size(); ++k) {
    int edge = 0, runs = 0;
    for (const Evaluation& e : r.evaluated) edge += e.at[k].at_band_edge, runs += e.at[k].n;
    if (edge > 0)
      std::fprintf(stderr, "warning: mode %d%s: the peak lay at the band's edge in %d of %d runs: their reduction is only a bound "
                           "(widen excitation.span); calibrate.csv's at_band_edge counts them per value\n", targets[k].mode,
                   all.where(targets[k]).c_str(), edge, runs);
  }

  // calibration.json and the summary.
  std::ostringstream js;
  js << "{\n  \"key\": \"" << json_escape(key_of(args)) << "\",\n  \"unit\": \"" << json_escape(unit) << "\",\n  \"to_si\": " << short_text(scale.to_si)
     << ",\n  \"seeds\": " << args.seeds
     << ",\n  \"tolerance_dB\": " << short_text(opt.tolerance) << ",\n  \"bounds\": [" << short_text(opt.lo) << ", " << short_text(opt.hi)
     << "],\n  \"targets\": [";
  for (std::size_t k = 0; k < targets.size(); ++k)
    js << (k ? ", " : "") << "{\"mode\": " << targets[k].mode << ", \"reduction_dB\": " << short_text(targets[k].reduction_db)
       << (all.config_key.empty() ? "" : ", \"configuration\": \"" + json_escape(configuration(targets[k])) + "\"") << "}";
  js << "],\n  \"solutions\": [";
  bool matched = false;
  for (std::size_t i = 0; i < r.solutions.size(); ++i) {
    const Solution& s = r.solutions[i];
    matched = matched || s.matched;
    js << (i ? "," : "") << "\n    {\"value\": " << short_text(s.value) << ", \"value_text\": \"" << json_escape(scale.given(s.value))
       << "\", \"half_width\": " << json_number_text(s.half_width) << ", \"matched\": " << (s.matched ? "true" : "false") << ", \"targets\": [";
    std::printf("%s %s = %s +- %s%s (95%%)%s\n", s.matched ? "calibrated" : "closest (not matched)", key_of(args).c_str(),
                short_number(s.value).c_str(), short_number(s.half_width).c_str(), scale.unit.empty() ? "" : (" " + scale.unit).c_str(), r.solutions.size() > 1 ? (", solution " + std::to_string(i + 1) + " of " + std::to_string(r.solutions.size())).c_str() : "");
    for (std::size_t k = 0; k < targets.size(); ++k) {
      js << (k ? ", " : "") << "{\"mode\": " << targets[k].mode << ", \"reduction_dB_mean\": " << json_number_text(s.at[k].mean)
         << ", \"reduction_dB_ci95\": " << json_number_text(s.at[k].ci95) << ", \"seeds\": " << s.at[k].n
         << ", \"residual_dB\": " << json_number_text(s.residual[k]) << ", \"slope_dB_per_unit\": " << json_number_text(s.slope[k]) << "}";
      std::printf("  mode %d%s: %.2f +- %.2f dB over %d start%s against %.2f dB (residual %+.2f dB)\n", targets[k].mode,
                  all.where(targets[k]).c_str(), s.at[k].mean, s.at[k].ci95, s.at[k].n, s.at[k].n == 1 ? "" : "s",
                  targets[k].reduction_db, s.residual[k]);
    }
    js << "], \"mae_dB\": " << mae_by_mode(targets, s.residual);
    js << "}";
  }
  js << "\n  ],\n  \"note\": \"" << json_escape(r.note) << "\",\n  \"runs_failed\": " << (failed ? "true" : "false") << "\n}\n";
  write_atomically(fs::path(out) / "calibration.json", js.str());
  return matched;
}

}  // namespace

namespace {

// The calibration's rounds share this spec (each its own OUT/round-RR and values).
StudySpec calibration_spec(const CalibrateArgs& args) {
  StudySpec base;
  base.case_dir = fs::absolute(args.dir).lexically_normal().string();
  if (!fs::exists(fs::path(base.case_dir) / "case.toml"))
    throw InputError(args.dir, "", "", "holds no case.toml (bagdem calibrate takes a case directory)");
  base.out_dir = fs::absolute(args.out.empty() ? fs::path(base.case_dir) / "calibrate" : fs::path(args.out)).lexically_normal().string();
  base.source = "bagdem calibrate";
  base.command = "calibrate";
  base.sets = args.sets;
  base.seeds = args.seeds;
  base.jobs = args.jobs, base.threads = args.threads, base.cores = args.cores;
  base.tables = {"peaks", "reduced"};
  return base;
}

// What coupled DEM's calibration reads before it runs (every rank alike).
struct Setup {
  Targets targets;
  std::vector<double> target_db;
  SearchOptions opt;
  Scale scale;
  StudySpec base;
  Budget budget;
};

Setup read_setup(const CalibrateArgs& args, const Ranks& ranks) {
  Setup u;
  u.base = calibration_spec(args);
  require_same_method(u.base.out_dir, false);
  if (args.keys.size() > 1 || args.bounds.size() > 1)
    throw InputError(args.keys.size() > 1 ? "--key" : "--bounds", "", args.keys.size() > 1 ? args.keys.back() : args.bounds.back(),
                     "coupled DEM calibrates one key (with one --bounds); several keys are fitted on effective-field maps (--maps, docs/calibrate.md)");
  if (key_of(args).find('@') != std::string::npos)
    throw InputError("--key", "", key_of(args), "KEY@M (one mode's element of a key) is fitted on effective-field maps (--maps); by coupled DEM, give the whole key");
  if (args.targets.empty() == args.targets_file.empty())
    throw InputError("--target", "", "", "give the measured peak reductions either as --target mode=M,reduction_db=R (repeatable) or as --targets FILE, one of the two");
  if (!args.targets_file.empty()) u.targets = read_targets_file(args.targets_file);
  for (const std::string& t : args.targets) u.targets.list.push_back(parse_target(t));
  if (u.targets.config_key == key_of(args))
    throw InputError(args.targets_file, key_of(args), "", "is the key calibrated: the targets' configuration column must be another key");
  const Scene s = load_case(u.base.case_dir, args.sets);
  // Each configuration the case must take, refused here naming the targets' file and row (not a
  // point of the first round's study, after its directory was made).
  for (std::size_t c = 0; c < u.targets.configs.size(); ++c) {
    std::vector<std::string> sets = args.sets;
    sets.push_back(u.targets.config_key + "=" + u.targets.configs[c].toml);
    try {
      load_case(u.base.case_dir, sets);
    } catch (const InputError& e) {
      std::size_t row = 0;
      while (row < u.targets.list.size() && u.targets.list[row].config != c) ++row;
      throw InputError(args.targets_file, "row " + std::to_string(row + 1) + ", " + u.targets.config_key, u.targets.configs[c].given,
                       std::string("is refused by the case: ") + e.what());
    }
  }
  u.target_db = target_reductions(s, u.targets.list, args.targets_file.empty() ? "--target" : args.targets_file);
  const auto [lo, hi] = read_bounds(key_of(args), args.bounds.empty() ? "" : args.bounds[0], s, u.scale);
  u.opt.lo = lo, u.opt.hi = hi, u.opt.log = search_in_log(lo, hi);
  u.opt.scan = args.scan, u.opt.rounds = args.rounds, u.opt.tolerance = args.tolerance;
  u.budget = resolve_budget(u.base, ranks.cores(), ranks.cores_from(), "bagdem calibrate");
  return u;
}

// The rounds of a calibration by coupled DEM among the ranks: each round's study, OUT taken before
// the first writes, and the other ranks' part.
class Rounds {
 public:
  Rounds(const CalibrateArgs& args, const Setup& setup, const Ranks& ranks) : args_(args), u_(setup), ranks_(ranks) {}

  // A round's study (OUT/round-RR) of the values and its points done before: the same on every rank.
  std::pair<Plan, std::vector<bool>> plan(int round, const std::vector<double>& values) const {
    StudySpec spec = u_.base;
    const std::string name = prefix(round).substr(0, 8);
    spec.out_dir = (fs::path(u_.base.out_dir) / name).string();
    Varied v{key_of(args_), {}};
    for (double x : values) v.values.push_back({u_.scale.toml(x), u_.scale.given(x)});
    spec.vary = {v};
    if (!u_.targets.config_key.empty()) spec.vary.push_back({u_.targets.config_key, u_.targets.configs});
    Plan plan = make_plan(spec);
    const std::vector<std::string> warnings = validate_plan(plan);
    if (round == 0 && ranks_.rank() == 0)
      for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    try {
      return {plan, done_points(plan)};
    } catch (const InputError& e) {
      throw InputError(spec.out_dir, "", "", std::string(e.what()) + " (an earlier calibration with other targets or options: give a new --out, or remove " + name + " and the rounds after it)");
    }
  }

  static std::string prefix(int round) {
    char name[32];
    std::snprintf(name, sizeof name, "round-%02d: ", round);
    return name;
  }

  // Before the first round writes: the lead's lock on OUT (its runs write inside it); every rank.
  int take_out() {
    return agreed(ranks_, [&] {
      if (ranks_.rank() == 0) refuse_other_outputs(u_.base.out_dir, OutputOwner::study), lock_.emplace(u_.base.out_dir);
      share_output_with_children(u_.base.out_dir);
      return 0;
    });
  }

  // A rank other than the lead: its share of each round the lead sends, until it sends none; the
  // lead's exit code.
  int follow() {
    for (int round = 0;; ++round) {
      const std::vector<double> values = ranks_.broadcast(std::vector<double>{});
      if (values.empty()) break;
      try {
        const auto [plan, done] = this->plan(round, values);
        if (round == 0 && take_out() != 0) continue;  // the lead said why; it sends no more
        run_round(plan, done, u_.budget, args_.executable, ranks_, prefix(round), nullptr);
      } catch (const RoundFailed&) {  // the lead's failure, said by the lead; it sends no more
      } catch (const std::exception& e) {
        std::fprintf(stderr, "%s%s: %s\n", rank_prefix(ranks_).c_str(), error_label(e), e.what());
        ranks_.abort(exit_code_after_runs(e));  // the lead planned a round this rank cannot: the ranks see different files
      }
    }
    return ranks_.broadcast(0);
  }

 private:
  const CalibrateArgs& args_;
  const Setup& u_;
  const Ranks& ranks_;
  std::optional<OutputLock> lock_;
};

}  // namespace

int calibrate_command(const CalibrateArgs& args) {
  std::optional<Ranks> ranks;
  if (const int code = start_ranks(ranks)) return code;
  const bool lead = ranks->rank() == 0;
  // The lead reports on stdout; the other ranks show their runs' progress on stderr.
  if (!lead && !std::freopen("/dev/null", "w", stdout)) std::fprintf(stderr, "%swarning: stdout not silenced\n", rank_prefix(*ranks).c_str());
  if (!args.maps.empty()) {  // no runs to share: the other ranks would wait doing nothing
    if (ranks->size() == 1) {
      refuse_several_dampers(load_case(args.dir, args.sets), "bagdem calibrate --maps", "predicts with one damper's map");
      return calibrate_on_maps(args);
    }
    if (lead) std::fprintf(stderr, "error: --maps: a fit on maps runs no simulation and gains nothing from %d MPI ranks: run it without mpirun\n", ranks->size());
    return kExitInputError;
  }
  const auto t0 = std::chrono::steady_clock::now();
  Setup setup;
  if (const int code = agreed(*ranks, [&] {
        setup = read_setup(args, *ranks);
        return 0;
      }))
    return code;
  const auto& [targets, target_db, opt, scale, base, budget] = setup;

  if (lead)
    std::fprintf(stderr, "bagdem calibrate %s: %s from %s to %s (%s scan of %d), %d seed%s per value -> %s; %d at once with %d thread%s%s\n",
                 base.case_dir.c_str(), key_of(args).c_str(), scale.given(opt.lo).c_str(), scale.given(opt.hi).c_str(), opt.log ? "log" : "linear",
                 opt.scan, args.seeds, args.seeds > 1 ? "s" : "", base.out_dir.c_str(), budget.jobs, budget.threads, budget.threads > 1 ? "s" : "",
                 ranks->size() > 1 ? (" on each of " + std::to_string(ranks->size()) + " ranks").c_str() : "");
  // The lead searches and sends each round's values; the other ranks run their share of the round
  // it sends until it sends none, so no rank chooses a round from files it may see differently.
  Rounds rounds(args, setup, *ranks);
  if (!lead) return rounds.follow();
  bool failed = false;
  int round = 0;
  struct Reported {  // an error already said (by agreed), with its exit code
    int code;
  };
  // One round: its study checked, its values sent to the other ranks, its runs shared. Bad input
  // surfaces in the first round's validation, before anything runs.
  Evaluate evaluate = [&](const std::vector<double>& values) {
    const auto [plan, done] = rounds.plan(round, values);
    std::string list;
    for (double x : values) list += (list.empty() ? "" : ", ") + scale.given(x);
    std::fprintf(stderr, "round %d: %s = %s\n", round, key_of(args).c_str(), list.c_str());
    ranks->broadcast(values);
    if (round == 0)
      if (const int code = rounds.take_out()) throw Reported{code};
    const std::vector<bool> finished = run_round(plan, done, budget, args.executable, *ranks, Rounds::prefix(round),
                                                 [&](const std::vector<bool>& f) { merge_tables(plan, f); });
    for (bool f : finished) failed = failed || !f;
    ++round;
    return estimates(plan, finished, targets.list, values.size());
  };

  int code = 0;
  SearchResult r;
  try {
    r = calibrate_search(target_db, opt, evaluate);
  } catch (const Reported& e) {
    code = e.code;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", error_label(e), e.what());
    code = round == 0 && dynamic_cast<const InputError*>(&e) ? kExitInputError : exit_code_after_runs(e);  // bad input: nothing ran
  }
  ranks->broadcast(std::vector<double>{});  // no more rounds
  if (code == 0) try {
      const bool matched = write_results(base.out_dir, args, targets, scale, opt, r, failed);
      if (!r.note.empty()) std::printf("note: %s\n", r.note.c_str());
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::printf("calibration %s: %zu values in %d rounds, %.1f s wall -> %s/calibrate.csv, calibration.json\n",
                  failed ? "finished with failed runs" : matched ? "complete" : "found no matching value", r.evaluated.size(), round, wall,
                  base.out_dir.c_str());
      code = failed || !matched ? kExitRunError : 0;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      code = 1;
    }
  return ranks->broadcast(code);
}

}  // namespace bagdem::study
