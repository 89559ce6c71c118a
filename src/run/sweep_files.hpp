// Internal to src/run: a stepped-sine sweep's own tables (run/frequency_sweep.hpp): sweep.csv and
// the /sweep table of results.h5 (one row per point), bare_curve.csv and summary.json.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "bagdem/io/table_csv.hpp"
#include "bagdem/run/frequency_sweep.hpp"
#include "bagdem/structure/primary.hpp"

namespace bagdem {

// The columns of sweep.csv and /sweep, and a point's row.
extern const std::vector<TableColumn> kSweepColumns;
std::vector<double> sweep_row(const SweepPoint& p);

// summary.json of a complete sweep: the case, the run's figures and each mode's peak.
std::string sweep_summary_json(const Scene& scene, const SweepReport& rep, std::size_t particles, std::size_t chains);

// sweep.csv: a row per point; and the points read back (every field sweep.csv holds).
void write_sweep_csv(const std::filesystem::path& path, const std::vector<SweepPoint>& points);
std::vector<SweepPoint> read_sweep_csv(const std::filesystem::path& path);

// bare_curve.csv: the bare structure's analytic response at 400 frequencies over the swept band,
// the smooth reference of the plots.
void write_bare_curve(const std::filesystem::path& path, const Primary& P, const std::vector<SweepPoint>& points);

}  // namespace bagdem
