// The files of `bagdem design` (study/design.hpp): OUT/design.csv, OUT/chosen, the summary printed.
#pragma once
#include <filesystem>
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

// design.csv: one type, written and read by the same code. A row per (candidate, position), ranked
// first (columns: docs/bag-design.md; an empty cell where a figure is undefined). What a row keeps
// of its candidate is its values as given and its map's directory name (DesignRow::candidate is 0
// when read back).
struct DesignTable {
  std::vector<std::string> varied;  // the candidates' keys, the columns after status
  std::vector<int> modes;           // the chosen modes (0: a random force's band)
  std::vector<DesignRow> rows;
  bool pairs = false;               // design-pairs.csv: after attach, the second bag's keys (KEY_2),
                                    // position_xL_2 and attach_2; its map's directory last (map_2)
};
// To a temporary name, then renamed.
void write_design_csv(const std::filesystem::path& path, const DesignTable& table);
// InputError naming the file, the column and the cell when a column is missing or a cell is not
// what the column holds (a number, a count, a status design writes).
DesignTable read_design_csv(const std::filesystem::path& path);
// OUT/design.csv of a design, or OUT/design-pairs.csv of its pairs (rows[k].pair).
void write_design(const DesignSummary& s, const std::vector<DesignRow>& rows, bool pairs = false);

// Candidate c's varied keys with their TOML values, in the candidates' order.
std::vector<std::pair<std::string, std::string>> candidate_keys(const StudySpec& candidates, std::size_t c);

// The row chosen: the verified one with the best coupled objective, else the best predicted; null
// when nothing is ranked.
const DesignRow* chosen_row(const std::vector<DesignRow>& rows);

// OUT/chosen: the case directory of the chosen row (the case's own files beside case.toml copied;
// case.toml its text with every override applied: the run's, the candidate's `sets[candidate]`
// and its place; a pair's second bag as a [[dampers]] entry), written as OUT/chosen.part and
// renamed, then loaded to show it is ready (a case that does not load leaves nothing). A pair's is
// OUT/chosen-pair. Returns its path; "" when nothing is ranked, an earlier design's choice removed.
std::string write_chosen_case(const DesignSummary& s, const std::vector<DesignRow>& rows,
                              const std::vector<std::vector<std::string>>& sets, bool pairs = false);

// The best rows and the Pareto front, on stdout.
void print_design(const DesignSummary& s, const std::vector<DesignRow>& rows);

}  // namespace bagdem::study
