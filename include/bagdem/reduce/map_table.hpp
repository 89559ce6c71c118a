// map.csv, the effective-field map of `bagdem characterize`: a row per cell of the Gamma x
// frequency grid (Gamma varying slowest), each figure as the mean over the starts and the half-width
// of its 95% interval. One type (MapCell) and one table of columns (map_figures), through which
// characterize writes it (study/map_files.cpp) and predict and design read it back
// (read_effective_map). Columns and units: docs/characterize.md.
#pragma once
#include <cstddef>
#include <filesystem>
#include <initializer_list>
#include <span>
#include <string>
#include <vector>

#include "bagdem/reduce/interval.hpp"

namespace bagdem {

// One cell of the map: the starts' reductions combined.
struct MapCell {
  double gamma = 0, frequency = 0, amplitude = 0;  // as asked (unit: 1, Hz, m)
  std::size_t starts = 0;          // starts reduced
  std::size_t steady = 0;          // of those, steady windows (reduce.hpp, ReducedRow::steady)
  Interval gamma_measured;         // the cavity's own, over the starts (unit: 1)
  Interval M_eff, C_eff, Cb_over_Mbw, loss_factor, M_eff_ratio, energy_per_cycle, e;
  std::size_t e_starts = 0;        // starts that gave an e (the others' is undefined: no impacts)
  std::string e_method = "none";   // where e came from (reduced.csv's e_method) when the starts agree, else "mixed"
};

// A figure's columns: its mean's name, its interval's name, their unit, and where a cell keeps it.
struct MapFigure {
  const char* name;
  const char* ci95;
  const char* unit;
  Interval MapCell::*field;
};
std::span<const MapFigure> map_figures();

// Writes map.csv (to a temporary name, renamed when complete).
void write_map_csv(const std::filesystem::path& path, const std::vector<MapCell>& cells);

// The cells of a map.csv. Every column in its unit; the grid's (gamma, frequency, amplitude)
// numbers > 0; a figure a finite number or nan (an empty cell: nan). `needed`: the figures that
// must be there; any other absent reads as NaN (a map written by hand for predict may hold only
// M_eff and C_eff). InputError naming the file, the column and the row otherwise.
using MapField = Interval MapCell::*;
std::vector<MapCell> read_map_csv(const std::filesystem::path& path, std::initializer_list<MapField> needed);

}  // namespace bagdem
