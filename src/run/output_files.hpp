// Internal to src/run: the balls' data in results.h5 in the scene's order, and the derived tables
// a new run removes. (Atomic writes of the small files: io/atomic_file.hpp.)
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "bagdem/error.hpp"
#include "bagdem/io/results_file.hpp"
#include "bagdem/step/simulation.hpp"

namespace bagdem {

// results.h5 for `sim`'s balls (radius and material per ball), in the scene's order.
inline ResultsFile open_results(const std::string& path, const Simulation& sim,
                                const std::vector<std::string>& materials, double cavity_interval) {
  return ResultsFile(path, sim.in_scene_order(sim.particles().radius), sim.in_scene_order(sim.particles().material),
                     materials, cavity_interval);
}

// The root attributes of a run's results file that say what made it, and its status "running":
// a new file's, and written again when a run resumes, whatever the interrupted file holds.
inline void write_run_attributes(ResultsFile& file, const Scene& scene) {
  file.set_attribute("case_file", scene.case_file);
  file.set_attribute("resolved_config", scene.resolved);
  file.set_attribute("settle_end", scene.settle);
  file.set_attribute("timestep", scene.dt);
  file.set_attribute("status", "running");
}

// results.h5.part of an interrupted run reopened to continue it (ResultsFile::reopen verifies its
// data against the checkpoint's digest): a file HDF5 cannot read is refused as damaged data are,
// with InputError (exit 2) saying to run again without --resume.
inline ResultsFile reopen_results(const std::filesystem::path& part, const SeriesLengths& lengths) {
  try {
    return ResultsFile::reopen(part.string(), lengths);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(part.string(), "", "", std::string(e.what()) + ": the interrupted run cannot be continued; run again without --resume");
  }
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

// The files a run, a sweep, `reduce`, `compare`, `drop` and `export` derive in an output directory,
// and what a failed run left: a new run (or a resumed one) removes them first, so that none of an
// earlier run is left beside its results. results.h5 is not among them: it is replaced when the new
// one is complete (renamed over it), so an interrupted or failed run leaves the earlier one intact.
// A stepped sine's tables of the points done so far, while it runs (and after an interruption, which
// a resume continues): never under the names of a whole run's tables, which its reading commands
// would take for the results.h5 beside them (an earlier run's, until the new one is complete).
inline constexpr const char* kSweepPartial = "sweep.partial.csv";
inline constexpr const char* kReducedPartial = "reduced.partial.csv";

inline constexpr const char* kDerivedTables[] = {"summary.json", "reduced.csv", "compare.csv", "peaks.csv",
                                                 "sweep.csv", "bare_curve.csv", "drop.csv", "drop_result.csv", "drop_result.toml",
                                                 kSweepPartial, kReducedPartial,
                                                 "export.csv", "export.json", "export.h5",
                                                 "results.failed.h5", "results.failed.xmf", "sweep.failed.csv",
                                                 "reduced.failed.csv"};

inline void remove_derived_tables(const std::filesystem::path& out) {
  for (const char* name : kDerivedTables) std::filesystem::remove(out / name);
}

// Several dampers ([[dampers]]): each but the case's own writes in OUT/dampers/NAME. A fresh run
// removes what bagdem wrote for an earlier run's dampers that the case has not (the derived tables,
// results.h5 and its kin, bag.h5, checkpoint.bin; a directory left empty goes too, other files
// stay); a resumed run keeps them.
inline std::filesystem::path damper_dir(const std::filesystem::path& out, const std::string& name) { return out / "dampers" / name; }

inline void clear_other_dampers(const std::filesystem::path& out, const Scene& scene, bool resume) {
  namespace fs = std::filesystem;
  const fs::path all = out / "dampers";
  if (resume || !fs::is_directory(all)) return;
  for (const auto& entry : fs::directory_iterator(all)) {
    const std::string name = entry.path().filename().string();
    bool kept = false;
    for (const Damper& d : scene.more_dampers) kept = kept || d.name == name;
    if (kept || !entry.is_directory()) continue;
    remove_derived_tables(entry.path());
    for (const char* f : {"results.h5", "results.xmf", "results.h5.part", "bag.h5", "checkpoint.bin"}) fs::remove(entry.path() / f);
    if (fs::is_empty(entry.path())) fs::remove(entry.path());
  }
  if (fs::is_empty(all)) fs::remove(all);
}

// What the XDMF index of a results file needs besides its frames' times: the balls, and the film's
// nodes and triangles (0 without a bag).
struct XdmfShape {
  std::size_t particles = 0, film_nodes = 0, film_triangles = 0;
};

// Ends results.h5.part of a run in OUT: its status set, closed, and renamed with the XDMF index
// beside it. A complete run's becomes results.h5 (over an earlier one); a failed run's becomes
// results.failed.h5, so that an earlier complete results.h5 stays as it was. Returns the new path.
inline std::filesystem::path close_results_file(ResultsFile& file, const std::filesystem::path& out, const std::string& status,
                                                bool complete, const std::vector<double>& frame_times, const XdmfShape& shape) {
  if (complete) file.seal();
  file.set_attribute("status", status);
  file.close();
  const std::string name = complete ? "results" : "results.failed";
  const std::filesystem::path to = out / (name + ".h5");
  std::filesystem::rename(out / "results.h5.part", to);
  write_xdmf((out / (name + ".xmf")).string(), name + ".h5", shape.particles, frame_times, shape.film_nodes, shape.film_triangles);
  return to;
}

// A failed run's message, with where its record went and that an earlier run's results are kept.
inline std::string failed_run_message(const std::string& what, const std::filesystem::path& record) {
  return what + " (this run's record: " + record.string() + "; the results.h5 of an earlier run, if any, is kept)";
}

}  // namespace bagdem
