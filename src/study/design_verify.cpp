// The coupled check of `bagdem design`'s best rows (design_verify.hpp).
#include "design_verify.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "bagdem/error.hpp"
#include "bagdem/reduce/interval.hpp"
#include "bagdem/reduce/summary.hpp"
#include "bagdem/study/design_files.hpp"
#include "bagdem/units.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;

VerifyStudy verify_study(const DesignArgs& a, const StudySpec& cand, bool beam, double length, const std::vector<CheckedRow>& best,
                         const Ranks& ranks) {
  const bool pairs = !best.empty() && best.front().second.has_value();
  StudySpec spec = cand;
  spec.out_dir = (fs::path(cand.out_dir) / (pairs ? "verify-pairs" : "verify")).string();
  spec.source = "bagdem design";
  spec.command = "design";
  spec.combine = Combine::zip;
  spec.seeds = a.verify_seeds;
  spec.tables = {"peaks", "reduced"};
  spec.vary.clear();
  const Plan grid = make_plan(cand);
  auto value = [&](std::size_t candidate, std::size_t k) { return cand.vary[k].values.at(grid.points.at(candidate).choice.at(k)); };
  for (std::size_t k = 0; k < cand.vary.size(); ++k) {
    Varied z{cand.vary[k].key, {}};
    for (const CheckedRow& r : best) z.values.push_back(value(r.candidate, k));
    spec.vary.push_back(z);
  }
  if (beam) {
    Varied at{"primary.attach", {}};
    for (const CheckedRow& r : best) at.values.push_back({"\"" + short_text(r.position * length) + " m\"", short_text(r.position * length) + " m"});
    spec.vary.push_back(at);
  }
  if (pairs) {  // the second bag: its candidate's keys and its place, a [[dampers]] entry
    Varied second{"dampers", {}};
    for (const CheckedRow& r : best) {
      std::string given;
      for (std::size_t k = 0; k < cand.vary.size(); ++k) given += value(r.second->first, k).given + ", ";
      const std::string text = second_damper(candidate_keys(cand, r.second->first), r.second->second * length);
      second.values.push_back({text, given + "x/L " + short_text(r.second->second)});
    }
    spec.vary.push_back(second);
  }
  Plan plan = make_plan(spec);
  validate_plan(plan);
  try {
    std::vector<bool> done = done_points(plan);
    return {plan, done, resolve_budget(plan.spec, ranks.cores(), ranks.cores_from(), "bagdem design")};
  } catch (const InputError& e) {
    throw InputError(spec.out_dir, "", "", std::string(e.what()) + " (an earlier design checked other rows: remove " + spec.out_dir + ", or give a new --out)");
  }
}

std::vector<double> verify_task(const std::vector<CheckedRow>& rows) {
  std::vector<double> task = {rows.empty() || !rows.front().second ? 2.0 : 3.0};
  for (const CheckedRow& r : rows) {
    task.push_back(static_cast<double>(r.candidate)), task.push_back(r.position);
    if (r.second) task.push_back(static_cast<double>(r.second->first)), task.push_back(r.second->second);
  }
  return task;
}

std::vector<CheckedRow> verify_task_rows(const std::vector<double>& task) {
  const std::size_t step = task.at(0) == 3 ? 4 : 2;
  std::vector<CheckedRow> rows;
  for (std::size_t j = 1; j + step <= task.size(); j += step) {
    CheckedRow r{static_cast<std::size_t>(task[j]), task[j + 1], std::nullopt};
    if (step == 4) r.second = std::make_pair(static_cast<std::size_t>(task[j + 2]), task[j + 3]);
    rows.push_back(r);
  }
  return rows;
}

// The best `a.verify` candidates (pairs: candidate pairs), each at its best position, run coupled
// (the lead's; the other ranks are sent the task). Neighbouring positions of one bag would tell the
// ranking of bags nothing.
bool verify_rows(const DesignArgs& a, const StudySpec& cand, bool beam, double length, const std::vector<int>& modes, const Ranks& ranks,
                 std::vector<DesignRow>& rows) {
  std::vector<DesignRow*> best;
  for (DesignRow& r : rows)
    if (r.status.ranked() && static_cast<int>(best.size()) < a.verify && std::none_of(best.begin(), best.end(), [&](const DesignRow* b) {
          return b->candidate == r.candidate && (!r.pair || b->candidate2 == r.candidate2);
        }))
      best.push_back(&r);  // the rows are ranked: a candidate's first is its best position
  if (best.empty()) return false;
  std::vector<CheckedRow> checked;
  for (const DesignRow* r : best)
    checked.push_back({r->candidate, r->position, r->pair ? std::optional(std::make_pair(r->candidate2, r->position2)) : std::nullopt});
  const VerifyStudy v = verify_study(a, cand, beam, length, checked, ranks);
  const Plan& plan = v.plan;
  ranks.broadcast(verify_task(checked));
  const std::vector<bool> finished =
      run_round(plan, v.done, v.budget, a.executable, ranks, "verify: ", [&](const std::vector<bool>& f) { merge_tables(plan, f); });
  // Per pair, per start, per chosen mode: the reduction.
  std::vector<std::map<std::size_t, std::vector<double>>> x(best.size());
  if (modes == std::vector<int>{0}) {  // a random force: each start's in-band RMS against the bare structure's
    for (const Point& p : plan.points)
      if (finished[p.index]) {
        const Summary run = read_summary(fs::path(plan.point_dir(p)) / "summary.json");
        const double rms = run.structure && run.structure->band ? run.structure->band->response_rms : NAN;
        x[p.combination][p.index] = {20 * std::log10(best[p.combination]->bare_rms / rms)};
      }
  } else if (const std::optional<Table> t = merge_table(plan, finished, "peaks")) {
    const auto col = [&](const std::string& name) {
      return static_cast<std::size_t>(std::find(t->columns.begin(), t->columns.end(), name) - t->columns.begin());
    };
    const std::size_t c_mode = col("mode [1]"), c_db = col("reduction_dB [dB]");
    for (const auto& row : t->rows) {
      if (row[1] != "done" || c_mode >= row.size() || c_db >= row.size() || row[c_db].empty()) continue;
      const Point& p = plan.points.at(std::stoul(row[0]));
      const auto k = std::find(modes.begin(), modes.end(), static_cast<int>(std::strtod(row[c_mode].c_str(), nullptr)));
      if (k == modes.end()) continue;
      auto& start = x[p.combination][p.index];
      start.resize(modes.size(), NAN);
      start[static_cast<std::size_t>(k - modes.begin())] = std::strtod(row[c_db].c_str(), nullptr);
    }
  }
  bool failed = false;
  for (bool f : finished) failed = failed || !f;
  for (std::size_t p = 0; p < best.size(); ++p) {
    DesignRow& r = *best[p];
    r.dem_db.assign(modes.size(), NAN), r.dem_db_ci95.assign(modes.size(), NAN);
    // Each mode over the starts; the objective as each start saw it (its worst mode), over the starts.
    std::vector<double> worst;
    for (std::size_t k = 0; k < modes.size(); ++k) {
      std::vector<double> v;
      for (const auto& [point, db] : x[p])
        if (std::isfinite(db[k])) v.push_back(db[k]);
      const Interval in = independent_interval(v);
      r.dem_db[k] = in.mean, r.dem_db_ci95[k] = in.ci95;
    }
    for (const auto& [point, db] : x[p]) {
      const double w = *std::min_element(db.begin(), db.end());
      if (std::all_of(db.begin(), db.end(), [](double d) { return std::isfinite(d); })) worst.push_back(w);
    }
    r.dem_seeds = static_cast<int>(worst.size());
    const Interval in = independent_interval(worst);
    r.dem_objective = in.mean, r.dem_objective_ci95 = in.ci95;
  }
  return failed;
}

}  // namespace bagdem::study
