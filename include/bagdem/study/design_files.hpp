// The files of `bagdem design` (study/design.hpp): OUT/design.csv, OUT/chosen, the summary printed.
#pragma once
#include <string>
#include <vector>

#include "bagdem/study/design.hpp"
#include "bagdem/study/study.hpp"

namespace bagdem::study {

struct DesignSummary {
  StudySpec candidates;       // the case, every run's overrides, the varied keys
  std::vector<int> modes;     // the chosen modes
  double structure_mass = 0;  // (unit: kg)
  double budget = 0;          // (unit: 1)
  bool beam = false;          // positions are x/L on a beam of `length` (unit: m)
  double length = 0;
};

// OUT/design.csv, a row per (candidate, position), ranked first (columns: docs/bag-design.md; an
// empty cell where a figure is undefined), to a temporary name and renamed.
void write_design(const DesignSummary& s, const std::vector<DesignRow>& rows);

// The row chosen: the verified one with the best coupled objective, else the best predicted; null
// when nothing is ranked.
const DesignRow* chosen_row(const std::vector<DesignRow>& rows);

// OUT/chosen: the case directory of the chosen row (the case's own files beside case.toml copied;
// case.toml its text with every override applied: the run's, the candidate's `sets[candidate]`
// and its place), written as OUT/chosen.part and renamed, then loaded to show it is ready.
// Returns its path ("" when nothing is ranked).
std::string write_chosen_case(const DesignSummary& s, const std::vector<DesignRow>& rows,
                              const std::vector<std::vector<std::string>>& sets);

// The best rows and the Pareto front, on stdout.
void print_design(const DesignSummary& s, const std::vector<DesignRow>& rows);

}  // namespace bagdem::study
