// summary.json: the headline figures of a complete run or stepped sine, written last and
// atomically (its presence marks the output complete). One type, written and read by the same code
// (src/reduce/summary.cpp, through nlohmann-json): the run writes it, and `bagdem peaks`, design, the
// tests and the tools read it back. Keys and units: docs/outputs.md.
#pragma once
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bagdem/energy.hpp"
#include "bagdem/structure/response.hpp"
#include "bagdem/vec3.hpp"

namespace bagdem {

// A mode's peak reduction: a row of peaks.csv and of summary.json's "peaks".
struct ModePeak {
  std::string name;                       // "mode 1", ...
  std::size_t mode = 0;                   // elastic mode number (1 = the first elastic mode)
  double bare_frequency = 0, bare_peak = 0;  // peak of |H| of the bare structure (unit: Hz, m/N)
  double frequency = 0, peak = 0;         // fitted peak of |H| with the contents (unit: Hz, m/N)
  double simulated_frequency = 0, simulated_peak = 0;  // the largest simulated |H| (unit: Hz, m/N)
  double peak_ci95 = 0;                   // 95% half-width of the largest simulated |H| (unit: m/N)
  double reduction_db = 0, reduction_percent = 0;
  double reduction_db_ci95 = 0;           // 95% half-width of the reduction (unit: dB)
  bool at_band_edge = false;              // the largest |H| is the mode's first or last point
  std::size_t unsteady_points = 0;        // the mode's points left out as unsteady
};

// What wrote the summary: `bagdem run` (one run of a scene) or a stepped sine ("kind").
enum class SummaryKind { run, stepped_sine };

// A bag's settled state ("bag").
struct SummaryBag {
  std::size_t balls = 0, film_triangles = 0;
  double packing_fraction = 0;     // when settling ended
  Vec3 outer = Vec3::Zero();       // its outer length, width, height then (outer_m; unit: m)
  // The film's self-contacts over the run (film_self_steps, film_self_pairs_max; 0 in a summary
  // written before they were counted).
  std::uint64_t self_steps = 0, self_pairs_max = 0;
  // The steps at which the walls' stop held a film node (film_wall_stops; docs/bag.md, Guards).
  std::uint64_t wall_stops = 0;
};

// A random force's band ("structure": band_response_rms_m, band_Hz, band_from_s).
struct SummaryBand {
  double response_rms = 0;  // the in-band RMS at x_a after band_from_s (unit: m)
  double lo = 0, hi = 0;    // (unit: Hz)
  double from = 0;          // (unit: s)
};

// The primary structure's figures ("structure").
struct SummaryStructure {
  std::string kind;
  double response_at = 0;                         // x_a (unit: m)
  double response_rms = 0, acceleration_rms = 0;  // at x_a after release (unit: m, m/s^2)
  std::optional<SummaryBand> band;                // a random force
  double work_external = 0, work_contents = 0, dissipated = 0, energy = 0;  // (unit: J)
  std::optional<DecayFit> decay;                  // free decay or a blow
};

struct Summary {
  SummaryKind kind = SummaryKind::run;
  std::string case_file;
  std::string damper;              // which of several dampers ([[dampers]]); "" for a case of one
  std::size_t particles = 0;
  double dt = 0;                   // (unit: s)
  int threads = 0;
  double wall_time = 0;            // (unit: s)
  // A run's.
  std::uint64_t steps = 0;
  std::string dt_reason;
  double particle_steps_per_second = 0, ns_per_particle_step = 0;
  std::uint64_t neighbour_builds = 0;
  std::optional<EnergySample> energy;  // null with output.energy = false (and a note says so)
  double energy_balance_error = NAN;   // relative (NaN: no energy budget)
  std::optional<SummaryBag> bag;
  std::optional<SummaryStructure> structure;
  double cycles_measured = 0;
  double dissipated_per_cycle = NAN;   // (unit: J; NaN: no whole cycle measured)
  // A stepped sine's.
  std::size_t chains = 0, points = 0, not_steady = 0;
  double force_amplitude = 0;          // (unit: N)
  std::vector<std::string> peaks_missing;  // why a mode has no peak
  std::vector<ModePeak> peaks;         // last in the file: `bagdem peaks` rewrites them
};

// Writes `s` to `path` (a temporary name, then renamed).
void write_summary(const std::filesystem::path& path, const Summary& s);
// Reads a summary.json; InputError naming the file and the key when it is missing, not JSON, or a
// key is missing or of the wrong type.
Summary read_summary(const std::filesystem::path& path);

}  // namespace bagdem
