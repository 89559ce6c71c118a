// `bagdem characterize` (study/characterize.hpp): the grid, the points as a study, the map.
#include "bagdem/study/characterize.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

#include "bagdem/case/case_reader.hpp"
#include "bagdem/case/load_case.hpp"
#include "bagdem/case/overrides.hpp"
#include "bagdem/error.hpp"
#include "bagdem/study/study.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;

std::vector<std::pair<double, double>> stepped_sine_bands(std::vector<double> f) {
  std::sort(f.begin(), f.end());
  std::vector<std::pair<double, double>> bands;
  if (f.empty()) return bands;
  std::vector<double> gaps;
  for (std::size_t k = 1; k < f.size(); ++k) gaps.push_back(f[k] - f[k - 1]);
  double median = 0;
  if (!gaps.empty()) {
    std::vector<double> s = gaps;
    std::nth_element(s.begin(), s.begin() + s.size() / 2, s.end());
    median = s[s.size() / 2];
  }
  bands.push_back({f[0], f[0]});
  for (std::size_t k = 1; k < f.size(); ++k) {
    if (gaps[k - 1] > 3 * median) bands.push_back({f[k], f[k]});
    bands.back().second = f[k];
  }
  return bands;
}

MapPlan map_plan(const Scene& scene, const CharacterizeArgs& a) {
  MapPlan m;
  auto range = [](const std::vector<double>& r, const std::string& option, const std::string& what) {
    if (r.size() != 2 || !(r[0] > 0) || !(r[1] > r[0]) || !std::isfinite(r[1]))
      throw InputError(option, "", "", "expected lo,hi with 0 < lo < hi, both finite (" + what + ")");
  };
  range(a.gamma, "--gamma", "acceleration ratios Gamma = X w^2 / g");
  if (a.amplitudes < 2) throw InputError("--amplitudes", "", std::to_string(a.amplitudes), "at least 2 (a map interpolates between them)");
  if (a.frequencies < 2) throw InputError("--frequencies", "", std::to_string(a.frequencies), "at least 2 per band");
  for (int i = 0; i < a.amplitudes; ++i)
    m.axes.gamma.push_back(a.gamma[0] * std::pow(a.gamma[1] / a.gamma[0], double(i) / (a.amplitudes - 1)));
  std::vector<std::pair<double, double>> bands;
  if (!a.band.empty()) {
    range(a.band, "--band", "frequencies in Hz");
    bands.push_back({a.band[0], a.band[1]});
  } else if (scene.primary && scene.primary->stepped_sine) {
    bands = stepped_sine_bands(scene.primary->stepped_sine->frequencies);
  } else {
    throw InputError(scene.case_file, "excitation", "", "has no stepped-sine sweep to take the band from: give --band lo,hi (Hz)");
  }
  for (const auto& [lo, hi] : bands)
    for (int j = 0; j < a.frequencies; ++j) m.axes.frequency.push_back(lo + (hi - lo) * j / (a.frequencies - 1));
  m.bands = bands;
  std::sort(m.axes.frequency.begin(), m.axes.frequency.end());
  m.axes.frequency.erase(std::unique(m.axes.frequency.begin(), m.axes.frequency.end()), m.axes.frequency.end());
  m.direction = scene.primary ? scene.primary->direction : excitation_direction(scene);
  if (m.direction.norm() == 0)
    throw InputError(scene.case_file, "cavity.motion", "", "gives no direction to shake in: set primary.direction or a harmonic cavity.motion");
  m.direction.normalize();
  if (scene.gravity.norm() > 0) m.axes.g = scene.gravity.norm();
  return m;
}

namespace {

// Every figure of the cell over the starts that have it (finite).
Interval over(const std::vector<ReducedRow>& starts, double ReducedRow::*field) {
  std::vector<double> x;
  for (const ReducedRow& r : starts)
    if (std::isfinite(r.*field)) x.push_back(r.*field);
  if (x.empty()) return {std::nan(""), std::nan(""), std::nan(""), 0};
  return independent_interval(x);
}

}  // namespace

MapCell map_cell(double gamma, double frequency, double amplitude, const std::vector<ReducedRow>& all) {
  MapCell c;
  c.gamma = gamma, c.frequency = frequency, c.amplitude = amplitude;
  c.starts = all.size();
  std::vector<ReducedRow> starts;  // the steady ones: an unsteady window is no measurement
  for (const ReducedRow& r : all)
    if (r.steady == 1) starts.push_back(r);
  c.steady = starts.size();
  c.gamma_measured = over(starts, &ReducedRow::gamma);
  c.M_eff = over(starts, &ReducedRow::M_eff);
  c.C_eff = over(starts, &ReducedRow::C_eff);
  c.Cb_over_Mbw = over(starts, &ReducedRow::Cb_over_Mbw);
  c.loss_factor = over(starts, &ReducedRow::loss_factor);
  c.M_eff_ratio = over(starts, &ReducedRow::M_eff_ratio);
  c.energy_per_cycle = over(starts, &ReducedRow::energy_per_cycle);
  c.e = over(starts, &ReducedRow::e);
  c.e_starts = c.e.repeats;
  for (const ReducedRow& r : starts) {
    if (!std::isfinite(r.e)) continue;
    c.e_method = c.e_method == "none" || c.e_method == r.e_method ? r.e_method : "mixed";
  }
  return c;
}

std::pair<int, int> run_cycles(const CharacterizeArgs& a, double f) {
  // Whole cycles spanning t seconds; the 1e-9 keeps a product that is whole up to rounding whole.
  auto spanning = [f](double t) { return static_cast<int>(std::ceil(t * f - 1e-9)); };
  return {std::max(a.skip, spanning(a.skip_time)), std::max(a.cycles, spanning(a.window_time))};
}

namespace {

// The motion starts smoothly over this many cycles (cavity.motion.ramp): started at once, its
// velocity jump X w would set rolling contents drifting for good.
constexpr double kRampCycles = 2;

// The study of a grid: a zip over the cells (Gamma slowest, then frequency) of the motion's
// amplitude and frequency and the run's duration; the overrides that make a coupled case prescribed.
StudySpec grid_spec(const CharacterizeArgs& a, const Scene& scene, const MapPlan& m) {
  StudySpec s;
  s.case_dir = fs::absolute(a.dir).lexically_normal().string();
  s.out_dir = fs::absolute(a.out.empty() ? fs::path(s.case_dir) / "map" : fs::path(a.out)).lexically_normal().string();
  s.source = "bagdem characterize";
  s.command = "characterize";
  s.combine = Combine::zip;
  s.seeds = a.seeds;
  s.jobs = a.jobs, s.threads = a.threads, s.cores = a.cores;
  s.tables = {"reduced"};
  // The keys a map's run sets itself (its length, its motion) are its own: an override of them,
  // made for the coupled case (bagdem design passes the coupled runs' length), is left out.
  for (const std::string& x : a.sets)
    if (!sets_key(x, keys::duration.path) && !sets_key(x, keys::skip_cycles.path) && !sets_key(x, keys::cavity_motion.path))
      s.sets.push_back(x);
  Overrides o(std::move(s.sets));
  if (scene.primary) {
    // A bag filled to a mass ratio keeps its balls: the ratio is then of the dropped structure's mass.
    const CaseReader in((fs::path(s.case_dir) / "case.toml").string(), a.sets);
    if (in.has(keys::mass_ratio.path) && !in.has(keys::primary_mass.path)) o.set(keys::primary_mass, scene.primary->structure_mass);
    o.set(keys::primary, "{kind=\"prescribed\"}").set(keys::excitation, "{kind=\"none\"}");
  }
  const Vec3& d = m.direction;
  o.set(keys::cavity_motion,
        "{kind=\"harmonic\", direction=[" + short_text(d.x()) + ", " + short_text(d.y()) + ", " + short_text(d.z()) + "]}");
  s.sets = std::move(o).sets();
  Varied X{keys::motion_amplitude.path, {}}, f{keys::motion_frequency.path, {}}, R{keys::motion_ramp.path, {}},
      T{keys::duration.path, {}}, K{keys::skip_cycles.path, {}};
  auto add = [](Varied& v, const std::string& given) { v.values.push_back({"\"" + given + "\"", given}); };
  for (std::size_t i = 0; i < m.axes.gamma.size(); ++i)
    for (std::size_t j = 0; j < m.axes.frequency.size(); ++j) {
      const double period = 1 / m.axes.frequency[j];
      const auto [skip, cycles] = run_cycles(a, m.axes.frequency[j]);
      add(X, short_text(m.amplitude(i, j)) + " " + keys::motion_amplitude.unit);
      add(f, short_text(m.axes.frequency[j]) + " " + keys::motion_frequency.unit);
      add(R, short_text(kRampCycles * period) + " " + keys::motion_ramp.unit);
      add(T, short_text((kRampCycles + skip + cycles) * period) + " " + keys::duration.unit);
      K.values.push_back({std::to_string(skip), std::to_string(skip)});
    }
  s.vary = {X, f, R, T, K};
  return s;
}

}  // namespace

StudySpec characterize_spec(const CharacterizeArgs& a, MapPlan& grid) {
  if (!fs::exists(fs::path(a.dir) / "case.toml"))
    throw InputError(a.dir, "", "", "holds no case.toml (bagdem characterize takes a case directory)");
  const Scene scene = load_case(a.dir, a.sets);
  refuse_several_dampers(scene, "bagdem characterize", "maps one damper");
  grid = map_plan(scene, a);
  grid.damper = damper_record(scene);
  StudySpec spec = grid_spec(a, scene, grid);
  // A map already made here of another damper (or by a bagdem whose defaults made another one):
  // its runs are not this damper's, and resuming would mix them in.
  if (const std::optional<DamperRecord> made = read_damper_record(fs::path(spec.out_dir) / "damper.toml")) {
    const std::vector<std::string> diff = damper_differences(*made, grid.damper);
    if (!diff.empty())
      throw InputError(spec.out_dir, "damper.toml", "", "holds the runs of another damper (" + diff.front() + (diff.size() > 1 ? ", ..." : "") +
                                                            "): give a new --out, or remove the directory");
  }
  return spec;
}

MapOutcome write_map_of(const Plan& plan, const std::vector<bool>& finished, const MapPlan& grid) {
  std::vector<MapCell> cells;
  MapOutcome o;
  for (std::size_t i = 0; i < grid.axes.gamma.size(); ++i)
    for (std::size_t j = 0; j < grid.axes.frequency.size(); ++j) {
      const std::size_t combination = i * grid.axes.frequency.size() + j;
      std::vector<ReducedRow> starts;
      for (const Point& p : plan.points) {
        if (p.combination != combination) continue;
        const fs::path csv = fs::path(plan.point_dir(p)) / "reduced.csv";
        if (!finished[p.index] || !fs::exists(csv)) {
          ++o.missing;
          continue;
        }
        const std::vector<ReducedRow> rows = read_reduced_csv(csv);
        if (!rows.empty()) starts.push_back(rows.front());
      }
      cells.push_back(map_cell(grid.axes.gamma[i], grid.axes.frequency[j], grid.amplitude(i, j), starts));
    }
  write_map(plan.spec.out_dir, grid, cells, plan.spec.case_dir);
  for (const MapCell& c : cells) o.unsteady += c.starts - c.steady;
  return o;
}

int characterize_command(const CharacterizeArgs& a) {
  MapPlan grid;
  auto after = [&](const Plan& plan, const std::vector<bool>& finished) {
    const MapOutcome o = write_map_of(plan, finished, grid);
    std::printf("map: %zu amplitudes x %zu frequencies, %d start%s each -> %s/map.csv, map.json, map.h5%s\n", grid.axes.gamma.size(),
                grid.axes.frequency.size(), plan.spec.seeds, plan.spec.seeds > 1 ? "s" : "", plan.spec.out_dir.c_str(),
                o.missing ? (" (" + std::to_string(o.missing) + " runs missing)").c_str() : "");
    if (o.unsteady)
      std::printf("note: %zu run%s of %zu did not reach a steady window (energy balance off by more than 1%%): a longer --window-time or --skip-time\n",
                  o.unsteady, o.unsteady > 1 ? "s" : "", plan.points.size());
    return o.missing ? kExitRunError : 0;
  };
  return study_command([&] { return characterize_spec(a, grid); }, a.check, a.executable, "bagdem characterize", after);
}

}  // namespace bagdem::study
