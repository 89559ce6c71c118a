// Internal to src/run: the balls' data in results.h5 in the scene's order, and the derived tables
// a new run removes. (Atomic writes of the small files: io/atomic_file.hpp.)
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "bagdem/io/results_file.hpp"
#include "bagdem/step/simulation.hpp"

namespace bagdem {

// results.h5 for `sim`'s balls (radius and material per ball), in the scene's order.
inline ResultsFile open_results(const std::string& path, const Simulation& sim,
                                const std::vector<std::string>& materials, double cavity_interval) {
  return ResultsFile(path, sim.in_scene_order(sim.particles().radius), sim.in_scene_order(sim.particles().material),
                     materials, cavity_interval);
}

// The balls' positions, velocities and spins and the bag's film nodes as a frame at time t, in the
// scene's order (the stepper keeps its own, Simulation::input_index): a run appends it at once, a
// sweep's chains keep a point's frame until the points before it are written.
struct Frame {
  double t = 0;
  std::vector<Vec3> x, v, w, film;
};
inline Frame frame_of(const Simulation& sim, double t) {
  const Particles& p = sim.particles();
  return {t, sim.in_scene_order(p.x), sim.in_scene_order(p.v), sim.in_scene_order(p.w),
          sim.scene().bag ? sim.film().x : std::vector<Vec3>{}};
}
inline void append_frame(ResultsFile& file, const Frame& f) {
  file.append_frame(f.t, f.x, f.v, f.w);
  if (!f.film.empty()) file.append_film_frame(f.film);
}

// The tables a run, a sweep, `reduce`, `compare`, `drop` and `export` derive in an output
// directory: a new run (or a resumed one) removes them first, so that none of an earlier run is
// left beside its results. results.h5 is not among them: it is replaced when the new one is
// complete (renamed over it), so an interrupted or failed run leaves the earlier one intact.
inline constexpr const char* kDerivedTables[] = {"summary.json", "reduced.csv", "compare.csv", "peaks.csv",
                                                 "sweep.csv", "bare_curve.csv", "drop.csv", "drop_result.csv",
                                                 "export.csv", "export.json", "export.h5"};

inline void remove_derived_tables(const std::filesystem::path& out) {
  for (const char* name : kDerivedTables) std::filesystem::remove(out / name);
}

}  // namespace bagdem
