// Internal to src/study: the coupled check of `bagdem design`'s best rows (design.cpp), a study of
// their keys zipped, each row a combination run with --verify-seeds starts. A pair of bags
// (--dampers 2) is the first bag's keys and place and its second as a `dampers` entry.
#pragma once
#include <optional>
#include <utility>
#include <vector>

#include "bagdem/study/design.hpp"
#include "bagdem/study/study.hpp"

namespace bagdem::study {

// A row to check: its candidate at x/L, and a pair's second bag.
struct CheckedRow {
  std::size_t candidate = 0;
  double position = 0;
  std::optional<std::pair<std::size_t, double>> second;
};

// The study (OUT/verify, a pair's OUT/verify-pairs), its points done before and its core budget.
// The same on every rank.
struct VerifyStudy {
  Plan plan;
  std::vector<bool> done;
  Budget budget;
};
VerifyStudy verify_study(const DesignArgs& a, const StudySpec& cand, bool beam, double length, const std::vector<CheckedRow>& rows,
                         const Ranks& ranks);

// What the lead sends the other ranks for a check ({2 or 3, candidate, x/L[, candidate2, x/L2], ...})
// and what they read back from it.
std::vector<double> verify_task(const std::vector<CheckedRow>& rows);
std::vector<CheckedRow> verify_task_rows(const std::vector<double>& task);

// The best `a.verify` ranked rows (distinct candidates, or candidate pairs) run coupled, their
// figures (dem_*) set; the lead's, the other ranks being sent the task. True when a run failed.
bool verify_rows(const DesignArgs& a, const StudySpec& cand, bool beam, double length, const std::vector<int>& modes, const Ranks& ranks,
                 std::vector<DesignRow>& rows);

}  // namespace bagdem::study
