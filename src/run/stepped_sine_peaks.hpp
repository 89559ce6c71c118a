// Internal to src/run: the peaks of a stepped sine (run/stepped_sine.hpp): the points grouped by
// the mode they are nearest to, the peak refinement's next frequency, and peaks.csv.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "bagdem/run/stepped_sine.hpp"
#include "bagdem/structure/primary.hpp"

namespace bagdem {

// The modes whose peaks a stepped sine evaluates (the plan's, or every elastic mode inside the swept
// band), and for each the points nearest to it in log-frequency among the elastic modes, sorted
// by frequency.
struct ModePoints {
  std::size_t dof;
  std::vector<const SteppedSinePoint*> points;
};
std::vector<ModePoints> group_by_mode(const Primary& P, const std::vector<SteppedSinePoint>& points);

// The next frequencies of a mode's peak refinement: n points dividing the gap between the largest
// |H| and its larger neighbour (the side the peak lies on) into n + 1 equal parts (n = 1: halfway).
// None when the largest is at an end of the mode's points; a point is left out when its step from
// the largest would be below 1e-4 of the frequency, or it would round to the steps per cycle of
// another (the same frequency again).
std::vector<double> refinement_frequencies(const ModePoints& m, double dt, std::size_t n);

// peaks.csv: one row per evaluated mode.
void write_peaks_csv(const std::filesystem::path& path, const std::vector<ModePeak>& peaks);

}  // namespace bagdem
