// Internal to src/run: a stepped sine's own tables (run/stepped_sine.hpp): sweep.csv and
// the /sweep table of results.h5 (one row per point), bare_curve.csv and summary.json.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "bagdem/io/table_csv.hpp"
#include "bagdem/run/stepped_sine.hpp"
#include "bagdem/reduce/summary.hpp"
#include "bagdem/structure/primary.hpp"

namespace bagdem {

// The columns of sweep.csv and /sweep, and a point's row.
extern const std::vector<TableColumn> kSteppedSineColumns;
std::vector<double> stepped_sine_row(const SteppedSinePoint& p);

// summary.json of a complete stepped sine: the case, the run's figures and each mode's peak.
Summary stepped_sine_summary(const Scene& scene, const SteppedSineReport& rep, std::size_t particles, std::size_t chains);

// sweep.csv: a row per point; and the points read back (every field sweep.csv holds).
void write_stepped_sine_csv(const std::filesystem::path& path, const std::vector<SteppedSinePoint>& points);
std::vector<SteppedSinePoint> read_stepped_sine_csv(const std::filesystem::path& path);

// bare_curve.csv: the bare structure's analytic response at 400 frequencies over the swept band,
// the smooth reference of the plots.
void write_bare_curve(const std::filesystem::path& path, const Primary& P, const std::vector<SteppedSinePoint>& points);

}  // namespace bagdem
