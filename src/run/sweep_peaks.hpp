// Internal to src/run: the peaks of a stepped-sine sweep (run/frequency_sweep.hpp): the points grouped by
// the mode they are nearest to, the peak refinement's next frequency, and peaks.csv / summary.json.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "bagdem/run/frequency_sweep.hpp"
#include "bagdem/structure/primary.hpp"

namespace bagdem {

// The modes whose peaks a sweep evaluates (the plan's, or every elastic mode inside the swept
// band), and for each the points nearest to it in log-frequency among the elastic modes, sorted
// by frequency.
struct ModePoints {
  std::size_t dof;
  std::vector<const SweepPoint*> points;
};
std::vector<ModePoints> group_by_mode(const Primary& P, const std::vector<SweepPoint>& points);

// The next frequency of a mode's peak refinement: halfway between the largest |H| and its larger
// neighbour (the side the peak lies on); 0 when the largest is at an end of the mode's points or
// the step would be below 1e-4 of the frequency, or would round to the steps per cycle of one of
// the two points (the same frequency again).
double refinement_frequency(const ModePoints& m, double dt);

// peaks.csv: one row per evaluated mode.
void write_peaks_csv(const std::filesystem::path& path, const std::vector<ModePeak>& peaks);
// summary.json's "peaks" array (NaN as null).
std::string peaks_json(const std::vector<ModePeak>& peaks);

}  // namespace bagdem
