// `bagdem design` (study/design.hpp): the candidates, their maps, the predictions at every position,
// the ranking and the coupled check of the best. The files it writes are in design_files.cpp.
#include "bagdem/study/design.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>

#include "bagdem/case/overrides.hpp"
#include "bagdem/case/case_reader.hpp"
#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/output_lock.hpp"
#include "bagdem/reduce/interval.hpp"
#include "bagdem/reduce/predict.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "bagdem/reduce/summary.hpp"
#include "bagdem/study/design_files.hpp"
#include "bagdem/study/study.hpp"
#include "bagdem/units.hpp"
#include "design_verify.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;

void set_objective(DesignRow& r) {
  r.objective = r.objective_lo = r.objective_hi = NAN;
  for (std::size_t k = 0; k < r.db.size(); ++k)
    if (k == 0 || r.db[k] < r.objective) r.objective = r.db[k], r.objective_lo = r.db_lo[k], r.objective_hi = r.db_hi[k];
}

void rank_rows(std::vector<DesignRow>& rows) {
  std::stable_sort(rows.begin(), rows.end(), [](const DesignRow& a, const DesignRow& b) {
    const bool ra = a.status.ranked(), rb = b.status.ranked();
    if (ra != rb) return ra;
    if (!ra) return false;
    if (a.objective != b.objective) return a.objective > b.objective;
    return a.added_mass < b.added_mass;
  });
  int rank = 0;
  for (DesignRow& r : rows) {
    r.rank = r.status.ranked() ? ++rank : 0;
    r.pareto = false;
    if (!r.status.ranked()) continue;
    bool dominated = false;
    for (const DesignRow& o : rows)
      if (&o != &r && o.status.ranked() &&
          ((o.objective >= r.objective && o.added_mass < r.added_mass) || (o.objective > r.objective && o.added_mass <= r.added_mass)))
        dominated = true;
    r.pareto = !dominated;
  }
}

std::string mode_label(int mode) { return mode == 0 ? "random" : "mode" + std::to_string(mode); }

std::vector<double> default_fills(double budget) { return {0.3 * budget, 0.6 * budget, 0.95 * budget}; }
std::vector<double> default_diameters(double d) { return {d, 1.5 * d, 2 * d}; }

namespace {

struct Candidate {
  std::vector<std::string> sets;   // the case's overrides: every run's, then the candidate's
  std::vector<std::string> given;  // its values as given, one per varied key
  double added_mass = NAN;
  Status status;                   // ranked, over budget, does not load
  std::string map;                 // OUT/maps/map-HASH
};

// The map options that shape a map, for its directory's hash.
std::string map_options_text(const CharacterizeArgs& m) {
  std::string t;
  for (double x : m.gamma) t += short_text(x) + ",";
  for (double x : m.band) t += short_text(x) + ",";
  return t + std::to_string(m.amplitudes) + "," + std::to_string(m.frequencies) + "," + std::to_string(m.seeds) + "," +
         std::to_string(m.cycles) + "," + std::to_string(m.skip) + "," + short_text(m.window_time) + "," + short_text(m.skip_time);
}

std::vector<int> case_modes(const Primary& P) {
  const auto [lo, hi] = std::minmax_element(P.stepped_sine->frequencies.begin(), P.stepped_sine->frequencies.end());
  std::vector<int> m;
  for (std::size_t d : P.evaluated_modes(*lo, *hi)) m.push_back(static_cast<int>(P.elastic_mode_number(d)));
  return m;
}

// The candidates' grid: the study's [vary] and --vary, or the default ball size x fill.
StudySpec candidate_spec(const DesignArgs& a, const fs::path& out) {
  SweepArgs s;
  s.dir = a.dir, s.vary = a.vary, s.sets = a.sets, s.out = out.string();
  StudySpec spec = read_spec(s);
  spec.seeds = 1;
  if (!spec.vary.empty()) return spec;
  const CaseReader in((fs::path(spec.case_dir) / "case.toml").string(), spec.sets);
  if (!in.has("bag.balls.diameter") || !in.has("bag.balls.mass_ratio"))
    throw InputError(in.file(), "bag.balls", "",
                     "the default search varies bag.balls.diameter and bag.balls.mass_ratio, which the case must give: give them, or "
                     "the candidates with --vary key=v1,v2,...");
  const double d = in.quantity("bag.balls.diameter", dim::length);
  Varied D{"bag.balls.diameter", {}}, F{"bag.balls.mass_ratio", {}};
  for (double x : default_diameters(d)) {
    const std::string mm = short_text(std::round(x * 1e7) / 1e4) + " mm";
    D.values.push_back({"\"" + mm + "\"", mm});
  }
  for (double x : default_fills(a.budget)) F.values.push_back({short_text(std::round(x * 1e6) / 1e6), short_text(std::round(x * 1e6) / 1e6)});
  spec.vary = {D, F};
  return spec;
}


// A candidate's map study: bagdem characterize's runs, in OUT/maps/map-HASH (built once), with its
// points done before and its core budget. The same on every rank.
struct MapStudy {
  MapPlan grid;
  Plan plan;
  std::vector<bool> done;
  Budget budget;
};

MapStudy map_study(const DesignArgs& a, const CharacterizeArgs& grid_args, const StudySpec& base, const Candidate& c, const Ranks& ranks) {
  CharacterizeArgs m = grid_args;
  m.dir = base.case_dir, m.sets = c.sets;
  m.jobs = a.jobs, m.threads = a.threads, m.cores = a.cores;
  m.out = c.map;
  MapStudy s;
  s.plan = make_plan(characterize_spec(m, s.grid));
  validate_plan(s.plan);
  s.done = done_points(s.plan);
  s.budget = resolve_budget(s.plan.spec, ranks.cores(), ranks.cores_from(), "bagdem design");
  return s;
}

std::string map_prefix(std::size_t k, std::size_t n) { return "map " + std::to_string(k + 1) + "/" + std::to_string(n) + ": "; }

// The lead's map of candidate i (the k-th of n to build): its study checked, sent to the other
// ranks, its runs shared, the map written.
void build_map(const DesignArgs& a, const CharacterizeArgs& grid_args, const StudySpec& base, const std::vector<Candidate>& cs, std::size_t i,
               std::size_t k, std::size_t n, const Ranks& ranks, bool& failed) {
  const MapStudy s = map_study(a, grid_args, base, cs[i], ranks);
  std::string v;
  for (const std::string& g : cs[i].given) v += (v.empty() ? "" : ", ") + g;
  std::fprintf(stderr, "%s%s: %zu runs -> %s\n", map_prefix(k, n).c_str(), v.c_str(), s.plan.points.size(), s.plan.spec.out_dir.c_str());
  ranks.broadcast(std::vector<double>{1, static_cast<double>(i), static_cast<double>(k), static_cast<double>(n)});
  run_round(s.plan, s.done, s.budget, a.executable, ranks, map_prefix(k, n), [&](const std::vector<bool>& finished) {
    failed = write_map_of(s.plan, finished, s.grid).missing > 0 || failed;
  });
}

// A ranked candidate's map, if its runs gave one; a map of another damper than the candidate's (a
// map directory from elsewhere) takes the candidate out, saying why.
std::optional<EffectiveMap> candidate_map(const StudySpec& cand, Candidate& c) {
  if (!c.status.ranked() || !fs::exists(fs::path(c.map) / "map.csv")) return std::nullopt;
  const std::optional<DamperRecord> made = read_damper_record(fs::path(c.map) / "damper.toml");
  const std::vector<std::string> diff =
      made ? damper_differences(*made, damper_record(load_case(cand.case_dir, c.sets))) : std::vector<std::string>{"no damper.toml"};
  if (!diff.empty()) {
    c.status = {Standing::other_damper, diff.front() + (diff.size() > 1 ? ", ..." : "")};
    return std::nullopt;
  }
  return read_recorded_map(fs::path(c.map) / "map.csv");
}

}  // namespace

namespace {

// What the search works on, once the case and the options are read.
struct Search {
  StudySpec cand;                  // the candidates' grid, as a study
  std::vector<Candidate> cs;
  std::vector<int> modes;          // the chosen modes (0: a random force's band)
  CharacterizeArgs map;            // the maps' grid (a random force's band when the case has no sweep)
  std::vector<double> positions;   // x/L (NaN: not a beam)
  double structure_mass = 0, length = 0;
  bool beam = false;
  std::vector<std::optional<EffectiveMap>> maps;  // per candidate, once built (predict_rows)
};

// The modes whose worst reduction is maximized: the case's, or --modes among them; {0} for a
// random force (its band's RMS).
std::vector<int> chosen_modes(const DesignArgs& a, const Scene& s, CharacterizeArgs& map) {
  const Primary& P = *s.primary;
  if (!P.stepped_sine) {
    if (!a.modes.empty()) throw InputError("--modes", "", "", "a random force's case has no modes to choose: its band's RMS is the objective");
    if (map.band.empty()) map.band = {P.random_lo, P.random_hi};
    return {0};
  }
  const std::vector<int> have = case_modes(P);
  if (have.empty())
    throw InputError(s.case_file, "excitation", "", "the sweep's band holds no natural frequency of the structure: no peak to reduce (set excitation.around_modes)");
  const std::vector<int> modes = a.modes.empty() ? have : a.modes;
  for (int m : modes)
    if (std::find(have.begin(), have.end(), m) == have.end())
      throw InputError("--modes", "", std::to_string(m), "the case's sweep evaluates other modes: set excitation.around_modes to include it");
  return modes;
}

// The candidates of the grid, each loaded with the case's seed and every start's (the seed places
// the fill's lattice, and with it the bag's length: the maps' and the check's runs use
// simulation.seed 1..N), its added mass against the budget, and its map's directory.
void list_candidates(const DesignArgs& a, const Primary& P, Search& z) {
  std::string first_load_error;
  const Plan grid = make_plan(z.cand);
  for (const Point& p : grid.points) {
    Candidate c;
    c.sets = p.sets;
    for (std::size_t k = 0; k < z.cand.vary.size(); ++k) c.given.push_back(z.cand.vary[k].values[p.choice[k]].given);
    const int starts = std::max(z.map.seeds, a.verify > 0 ? a.verify_seeds : 1);
    for (int seed = 0; seed <= (starts > 1 ? starts : 0) && c.status.ranked(); ++seed) {  // 0: the case's own
      Overrides sets(c.sets);
      if (seed > 0) sets.set(keys::seed, seed);
      try {
        const Scene cs_scene = load_case(z.cand.case_dir, sets.sets());
        if (seed > 0) continue;
        c.added_mass = reduction_context(cs_scene, P.direction).bag_mass;
        if (c.added_mass > a.budget * z.structure_mass * (1 + 1e-9)) c.status = {Standing::over_budget, ""};
      } catch (const InputError& e) {
        c.status = {Standing::does_not_load, (seed > 0 ? "(simulation.seed " + std::to_string(seed) + ") " : "") + std::string(e.what())};
        if (first_load_error.empty()) first_load_error = e.what();
      }
    }
    const CaseReader text((fs::path(z.cand.case_dir) / "case.toml").string(), c.sets);
    c.map = (fs::path(z.cand.out_dir) / "maps" / ("map-" + fingerprint(text.text() + map_options_text(z.map)).substr(0, 12))).string();
    z.cs.push_back(c);
  }
  if (std::none_of(z.cs.begin(), z.cs.end(), [](const Candidate& c) { return c.status.ranked(); }))
    throw InputError(a.dir, "", "", first_load_error.empty() ? "no candidate is within the budget of " + short_text(a.budget) + " of the structure's mass (--budget)"
                                                             : "no candidate loads; the first: " + first_load_error);
}

// The search read from the case and the options (InputError for what it cannot search).
Search set_up_search(const DesignArgs& a) {
  Search z;
  z.map = a.map, z.positions = a.positions;
  const fs::path out = a.out.empty() ? fs::path(a.dir) / "design" : fs::path(a.out);
  z.cand = candidate_spec(a, fs::absolute(out).lexically_normal());
  const Scene s = load_case(z.cand.case_dir, z.cand.sets);
  refuse_several_dampers(s, "bagdem design", "places one damper, or a pair with --dampers 2");
  if (!s.primary || (!s.primary->stepped_sine && !(s.primary->random_hi > 0)))
    throw InputError(s.case_file, "excitation.kind", "",
                     "design needs a structure ([primary]) and a stepped-sine sweep (its modes' peaks are reduced) or a random force "
                     "(its response's RMS in the band is)");
  const Primary& P = *s.primary;
  z.structure_mass = P.structure_mass;
  z.beam = P.kind == "beam" || P.kind == "fe-beam";
  z.length = P.length;
  z.modes = chosen_modes(a, s, z.map);
  map_plan(s, z.map);  // the maps' options (--gamma, --amplitudes, ...) refused here, before anything is written
  if (a.dampers == 2 && (!z.beam || z.modes == std::vector<int>{0}))
    throw InputError("--dampers", "", "2", "places a pair of bags along a beam ([primary] kind beam or fe-beam) under a stepped sine; " +
                                               std::string(z.beam ? "this case's force is random" : "this case's structure is no beam"));
  if (a.dampers == 2)  // the second bag is a [[dampers]] entry: its keys must be a damper's
    for (const Varied& v : z.cand.vary)
      if (!damper_may_change(v.key))
        throw InputError("--vary", "", v.key, "is no key of a bag: with --dampers 2 the candidates may vary only the keys under " + damper_keys_text());
  if (z.positions.empty() && z.beam)
    for (int k = 1; k <= 19; ++k) z.positions.push_back(0.05 * k);
  if (!z.beam) z.positions = {NAN};
  for (double x : z.positions)
    if (z.beam && !(x > 0 && x < 1)) throw InputError("--positions", "", short_text(x), "x/L between 0 and 1 (ends excluded)");
  list_candidates(a, P, z);
  return z;
}

// The plan on stdout: the candidates with their masses and whether their maps are built.
void print_search(const DesignArgs& a, const Search& z) {
  std::printf("bagdem design %s: %zu candidates x %zu position%s, %s", z.cand.case_dir.c_str(), z.cs.size(), z.positions.size(),
              z.positions.size() > 1 ? "s" : "", z.modes == std::vector<int>{0} ? "the random force's RMS" : "modes");
  for (int m : z.modes)
    if (m > 0) std::printf(" %d", m);
  std::printf(", budget %s of %s kg -> %s\n", short_text(a.budget).c_str(), short_text(z.structure_mass).c_str(), z.cand.out_dir.c_str());
  for (const Candidate& c : z.cs) {
    std::string v;
    for (std::size_t k = 0; k < c.given.size(); ++k) v += (k ? ", " : "") + z.cand.vary[k].key + " = " + c.given[k];
    std::printf("  %-60s %8.4g kg (%5.1f%%)  %s%s\n", v.c_str(), c.added_mass, 100 * c.added_mass / z.structure_mass, c.status.text().c_str(),
                c.status.ranked() ? (fs::exists(fs::path(c.map) / "map.csv") ? ", map built" : ", map to build") : "");
  }
  std::fflush(stdout);
}

// Every candidate at every place predicted from its map: a row each.
std::vector<DesignRow> predict_rows(Search& z) {
  std::vector<DesignRow> rows;
  for (std::size_t i = 0; i < z.cs.size(); ++i) {
    Candidate& c = z.cs[i];
    const std::optional<EffectiveMap>& effective = z.maps.emplace_back(candidate_map(z.cand, c));
    for (double x : z.positions) {
      DesignRow r;
      r.candidate = i, r.given = c.given, r.position = x, r.added_mass = c.added_mass, r.mass_ratio = c.added_mass / z.structure_mass;
      r.status = c.status, r.map = c.map;
      r.attach = z.beam ? x * z.length : NAN;
      r.db.assign(z.modes.size(), NAN), r.db_lo = r.db, r.db_hi = r.db;
      r.objective = r.objective_lo = r.objective_hi = NAN;
      if (c.status.ranked() && !effective) r.status = {Standing::no_map, ""};
      if (r.status.ranked()) {
        Overrides sets(c.sets);
        if (z.beam) sets.set(keys::attach, x * z.length);
        try {
          predict_row(z.cand.case_dir, sets.sets(), *effective, z.modes, r);
        } catch (const InputError& e) {  // a place the case refuses (the cavity beyond the beam's end)
          r.status = {Standing::does_not_load, e.what()};
        }
        if (!z.beam) r.attach = NAN;
      }
      rows.push_back(r);
    }
  }
  return rows;
}

// After the maps: some candidate still ranked, else (every map failed to load or build) nothing is
// ranked, and an earlier design's files stay (InputError, exit 2).
void require_a_map(const Search& z) {
  if (std::any_of(z.cs.begin(), z.cs.end(), [](const Candidate& c) { return c.status.ranked(); })) return;
  const auto first = std::find_if(z.cs.begin(), z.cs.end(), [](const Candidate& c) { return c.status.kind == Standing::does_not_load; });
  throw InputError(z.cand.out_dir, "", "", "no candidate's map could be built or read, so nothing is ranked and nothing was written; the first: " +
                                               (first != z.cs.end() ? first->status.why : std::string("(none said)")));
}

}  // namespace

int design_command(const DesignArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  std::optional<Ranks> ranks;
  if (const int code = start_ranks(ranks)) return code;
  const bool lead = ranks->rank() == 0;
  // The lead reports on stdout; the other ranks show their runs' progress on stderr.
  if (!lead && !std::freopen("/dev/null", "w", stdout)) std::fprintf(stderr, "%swarning: stdout not silenced\n", rank_prefix(*ranks).c_str());
  Search z;
  std::optional<OutputLock> lock;  // the lead's: one design writes a directory at a time; its runs write inside it
  if (const int code = agreed(*ranks, [&] {
        z = set_up_search(a);
        if (!a.check) {
          if (lead) refuse_other_outputs(z.cand.out_dir, OutputOwner::study), lock.emplace(z.cand.out_dir);
          share_output_with_children(z.cand.out_dir);
        }
        return 0;
      }))
    return code;
  print_search(a, z);
  if (a.check) return 0;

  // The other ranks run their share of each study the lead sends (a candidate's map: {1, i, k, n};
  // the check: {2, candidate, x/L, ...}) until it sends none: the search is the lead's alone.
  if (!lead) {
    for (;;) {
      const std::vector<double> task = ranks->broadcast(std::vector<double>{});
      if (task.empty()) break;
      try {
        if (task[0] == 1) {
          const auto i = static_cast<std::size_t>(task[1]), k = static_cast<std::size_t>(task[2]), n = static_cast<std::size_t>(task[3]);
          const MapStudy s = map_study(a, z.map, z.cand, z.cs.at(i), *ranks);
          run_round(s.plan, s.done, s.budget, a.executable, *ranks, map_prefix(k, n), nullptr);
        } else {
          const VerifyStudy v = verify_study(a, z.cand, z.beam, z.length, verify_task_rows(task), *ranks);
          run_round(v.plan, v.done, v.budget, a.executable, *ranks, "verify: ", nullptr);
        }
      } catch (const RoundFailed&) {  // the lead's failure, said by the lead
      } catch (const std::exception& e) {
        std::fprintf(stderr, "%s%s: %s\n", rank_prefix(*ranks).c_str(), error_label(e), e.what());
        ranks->abort(exit_code_after_runs(e));  // the lead sent a study this rank cannot plan: the ranks see different files
      }
    }
    return ranks->broadcast(0);
  }
  int code = 0;
  try {
    bool failed = false;
    // 1. The maps.
    std::size_t n = 0, k = 0;
    for (const Candidate& c : z.cs) n += c.status.ranked();
    for (std::size_t i = 0; i < z.cs.size(); ++i)
      if (z.cs[i].status.ranked()) try {
          build_map(a, z.map, z.cand, z.cs, i, k++, n, *ranks, failed);
        } catch (const InputError& e) {  // a run of its map does not load, or its runs give no map: the candidate is out, the search goes on
          z.cs[i].status = {Standing::does_not_load, e.what()};
          std::fprintf(stderr, "map %zu/%zu: %s\n", k, n, z.cs[i].status.text().c_str());
        }
    if (n > 0) require_a_map(z);
    // 2. The predictions.
    std::vector<DesignRow> rows = predict_rows(z);
    rank_rows(rows);
    // 3. The coupled check of the best.
    if (a.verify > 0) failed = verify_rows(a, z.cand, z.beam, z.length, z.modes, *ranks, rows) || failed;
    // 4. The files of the single bags.
    std::vector<std::vector<std::string>> sets;
    std::vector<const EffectiveMap*> maps;
    for (std::size_t i = 0; i < z.cs.size(); ++i) sets.push_back(z.cs[i].sets), maps.push_back(z.maps[i] ? &*z.maps[i] : nullptr);
    const DesignSummary sum{z.cand, z.modes, z.structure_mass, a.budget, z.beam, z.length};
    write_design(sum, rows);
    std::string chosen = write_chosen_case(sum, rows, sets);
    print_design(sum, rows);
    // 5. Pairs of bags: predicted, the best checked, their files.
    if (a.dampers == 2) {
      std::size_t overlapping = 0;
      std::vector<DesignRow> pairs = predict_pairs(z.cand.case_dir, sets, maps, rows, z.modes, a.budget * z.structure_mass, overlapping);
      if (a.verify > 0) failed = verify_rows(a, z.cand, z.beam, z.length, z.modes, *ranks, pairs) || failed;
      write_design(sum, pairs, true);
      const std::string pair = write_chosen_case(sum, pairs, sets, true);
      if (!pair.empty()) chosen += (chosen.empty() ? "" : ", ") + pair;
      print_design(sum, pairs);
      if (overlapping > 0) std::printf("%zu pairs of places left out: their cavities overlap on the beam\n", overlapping);
      if (std::none_of(pairs.begin(), pairs.end(), [](const DesignRow& r) { return r.status.ranked(); }))
        std::printf("no pair of bags ranked: none fits the budget of %s of the structure's mass at two places, or none could be predicted "
                    "(design-pairs.csv says why)\n", short_text(a.budget).c_str());
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("design %s: %.1f s wall -> %s/design.csv%s%s\n", failed ? "finished with failed runs" : "complete", wall, z.cand.out_dir.c_str(),
                a.dampers == 2 ? ", design-pairs.csv" : "", chosen.empty() ? "" : (", " + chosen).c_str());
    code = failed ? kExitRunError : 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", error_label(e), e.what());
    code = exit_code_of(e);
  }
  ranks->broadcast(std::vector<double>{});  // no more studies
  return ranks->broadcast(code);
}

}  // namespace bagdem::study
