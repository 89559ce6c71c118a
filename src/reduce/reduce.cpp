// Reduction of a run to the damper's effective parameters (reduce/reduce.hpp).
#include "bagdem/reduce/reduce.hpp"
#include "bagdem/reduce/drop_record.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/reduce/continuum_model.hpp"
#include "bagdem/reduce/harmonic_projection.hpp"
#include "bagdem/reduce/impacts.hpp"
#include "bagdem/reduce/interval.hpp"
#include "bagdem/particles.hpp"
#include "bagdem/io/recorded_table.hpp"
#include "bagdem/io/table_csv.hpp"
#include "../io/h5.hpp"

namespace bagdem {
namespace fs = std::filesystem;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Circular mean of axial data (angles defined modulo pi), in [0, pi).
double axial_mean(const std::vector<double>& angles) {
  double c = 0, s = 0;
  for (double a : angles) c += std::cos(2 * a), s += std::sin(2 * a);
  double m = 0.5 * std::atan2(s, c);
  if (m < 0) m += kPi;
  return m;
}

// reduced.csv's columns: the row's real fields in order, then X_hat and F_hat as (re, im). Each
// field is named once here; the writer, the reader and reduced_columns() all follow this table.
struct RealField {
  const char* name;
  const char* unit;
  double ReducedRow::*member;
};
constexpr RealField kRealFields[] = {
    {"frequency", "Hz", &ReducedRow::frequency}, {"cavity_amplitude", "m", &ReducedRow::cavity_amplitude},
    {"gamma", "1", &ReducedRow::gamma}, {"clearance_ratio", "1", &ReducedRow::clearance_ratio},
    {"bag_mass", "kg", &ReducedRow::bag_mass}, {"mass_ratio", "1", &ReducedRow::mass_ratio},
    {"balls", "1", &ReducedRow::balls}, {"ball_diameter", "m", &ReducedRow::ball_diameter},
    {"M_eff", "kg", &ReducedRow::M_eff}, {"M_eff_se", "kg", &ReducedRow::M_eff_se},
    {"M_eff_ci95", "kg", &ReducedRow::M_eff_ci95},
    {"C_eff", "N s/m", &ReducedRow::C_eff}, {"C_eff_se", "N s/m", &ReducedRow::C_eff_se},
    {"C_eff_ci95", "N s/m", &ReducedRow::C_eff_ci95},
    {"M_eff_ratio", "1", &ReducedRow::M_eff_ratio}, {"Cb_over_Mbw", "1", &ReducedRow::Cb_over_Mbw},
    {"Cb_over_Mbw_se", "1", &ReducedRow::Cb_over_Mbw_se}, {"Cb_over_Mbw_ci95", "1", &ReducedRow::Cb_over_Mbw_ci95},
    {"loss_factor", "1", &ReducedRow::loss_factor},
    {"energy_per_cycle", "J", &ReducedRow::energy_per_cycle},
    {"energy_per_cycle_se", "J", &ReducedRow::energy_per_cycle_se},
    {"energy_per_cycle_ci95", "J", &ReducedRow::energy_per_cycle_ci95},
    {"dissipated_per_cycle", "J", &ReducedRow::dissipated_per_cycle}, {"energy_balance", "1", &ReducedRow::energy_balance},
    {"impact_phase", "rad", &ReducedRow::impact_phase}, {"impacts_per_cycle", "1", &ReducedRow::impacts_per_cycle},
    {"e_impact", "1", &ReducedRow::e_impact}, {"e_impact_sd", "1", &ReducedRow::e_impact_sd},
    {"e_impact_count", "1", &ReducedRow::e_impact_count}, {"e_eq19a", "1", &ReducedRow::e_eq19a},
    {"peak_impact_force", "N", &ReducedRow::peak_impact_force},
    {"max_impact_force", "N", &ReducedRow::max_impact_force}, {"impact_duration", "s", &ReducedRow::impact_duration},
    {"response_amplitude", "m", &ReducedRow::response_amplitude}, {"cycles", "1", &ReducedRow::cycles},
    {"e_drop", "1", &ReducedRow::e_drop},
    {"e", "1", &ReducedRow::e}, {"e_se", "1", &ReducedRow::e_se}, {"e_ci95", "1", &ReducedRow::e_ci95},
    {"steady", "1", &ReducedRow::steady}};
// The text column, after the numbers and the complex amplitudes.
const TableColumn kMethodColumn{"e_method", "text"};
constexpr std::size_t kReal = std::size(kRealFields);

const std::vector<TableColumn> kColumns = [] {
  std::vector<TableColumn> c;
  for (const RealField& f : kRealFields) c.push_back({f.name, f.unit});
  for (const TableColumn& z : {TableColumn{"displacement_re", "m"}, TableColumn{"displacement_im", "m"},
                               TableColumn{"force_re", "N"}, TableColumn{"force_im", "N"}})
    c.push_back(z);
  return c;
}();

}  // namespace

Vec3 excitation_direction(const Scene& scene) {
  if (scene.primary) return scene.primary->direction;
  const double f = scene.motion ? scene.motion->frequency() : 0.0;
  if (!(f > 0)) return Vec3::Zero();
  const Vec3 x0 = scene.motion->at(0.0).position;
  Vec3 e = scene.motion->at(0.25 / f).position - x0;
  if (e.norm() == 0) e = scene.motion->at(0.5 / f).position - x0;
  return e.norm() > 0 ? Vec3(e.normalized()) : Vec3::Zero();
}

ReductionContext reduction_context(const Scene& scene, const Vec3& direction) {
  ReductionContext c;
  c.direction = direction.normalized();
  const double g = scene.gravity.norm();
  c.gravity = g > 0 ? g : 9.81;
  double balls = 0, diameters = 0, mass = 0;
  for (const ParticleInit& p : scene.particles) {
    const double m = sphere_mass(scene.materials[static_cast<std::size_t>(p.material)].density, p.radius);
    mass += m, balls += 1, diameters += 2 * p.radius;
  }
  c.balls = balls;
  c.ball_diameter = balls > 0 ? diameters / balls : 0;
  if (scene.bag) mass += scene.bag->film_mass();
  c.bag_mass = mass;
  c.primary_mass = scene.primary ? scene.primary->structure_mass : 0;
  c.clearance = kNaN;  // measured on the live contents by the run (run/clearance.hpp)
  return c;
}

namespace {

// Eq. (19a) inverted at C_b/(M_b w) = c, NaN outside its domain.
double eq19a_restitution(double c, double phi) {
  if (!std::isfinite(c) || !std::isfinite(phi)) return kNaN;
  return continuum::restitution_from_damping(c, phi).value_or(kNaN);
}

// Half the spread of Eq. (19a)'s e over c +- dc (e rises with c at a fixed phase); an end outside
// the domain is taken at the domain's edge, e = 0.
double eq19a_half_width(double c, double dc, double phi) {
  if (!std::isfinite(dc)) return kNaN;
  const double lo = eq19a_restitution(c - dc, phi), hi = eq19a_restitution(c + dc, phi);
  return 0.5 * ((std::isfinite(hi) ? hi : 1.0) - (std::isfinite(lo) ? lo : 0.0));
}

}  // namespace

void set_energy_balance(ReducedRow& r, const EnergyWindow& w, double t0, double t1) {
  const std::size_t n = w.t.size();
  if (n < 2 || w.fields.size() != 5 || !(t1 > t0) || t0 < w.t.front() || t1 > w.t.back() * (1 + 1e-12)) return;
  // Linear interpolation of a cumulative series at time x.
  auto at = [&](const std::vector<double>& y, double x) {
    const auto hi = std::min<std::size_t>(n - 1, std::max<std::size_t>(1, static_cast<std::size_t>(std::lower_bound(w.t.begin(), w.t.end(), x) - w.t.begin())));
    const double a = (x - w.t[hi - 1]) / (w.t[hi] - w.t[hi - 1]);
    return y[hi - 1] + a * (y[hi] - y[hi - 1]);
  };
  auto change = [&](std::size_t k) { return at(w.fields[k], t1) - at(w.fields[k], t0); };
  const double kinetic = change(0), elastic = change(1), work_cavity = change(2), work_gravity = change(3), dissipated = change(4);
  r.dissipated_per_cycle = dissipated / r.cycles;
  const double scale = std::max(std::abs(work_cavity), std::abs(dissipated));
  r.energy_balance = scale > 0 ? (work_cavity + work_gravity - dissipated - kinetic - elastic) / scale : 0.0;
}

void judge_steady(ReducedRow& r) {
  const bool balance_closes = !(std::abs(r.energy_balance) > kSteadyBalanceTolerance);  // NaN: not known, not a flag
  const bool dissipates = !(r.dissipated_per_cycle < 0);
  if (!balance_closes || !dissipates) r.steady = 0;
}

void choose_restitution(ReducedRow& r, const Interval& impact) {
  r.e = r.e_se = r.e_ci95 = kNaN;
  r.e_method = "none";
  if (std::isfinite(r.e_impact) && r.e_impact_count >= static_cast<double>(kMinImpactsForRestitution)) {
    r.e = r.e_impact, r.e_method = "impact";
    r.e_se = impact.se, r.e_ci95 = impact.ci95;
  } else if (std::isfinite(r.e_eq19a)) {
    r.e = r.e_eq19a, r.e_method = "eq19a";
    r.e_se = eq19a_half_width(r.Cb_over_Mbw, r.Cb_over_Mbw_se, r.impact_phase);
    r.e_ci95 = eq19a_half_width(r.Cb_over_Mbw, r.Cb_over_Mbw_ci95, r.impact_phase);
  } else if (std::isfinite(r.e_drop)) {
    r.e = r.e_drop, r.e_method = "drop";
  }
}

ReducedRow reduce_series(const CavitySeries& s, double f, double t_skip, const ReductionContext& ctx) {
  const double w = 2 * kPi * f;
  const EffectiveParameters ep = effective_parameters(s.t, s.x, s.force, f, t_skip, Sampling::interval_mean);
  ReducedRow r;
  r.frequency = f;
  r.displacement = ep.displacement, r.force = ep.force;
  const double X = std::abs(ep.displacement);
  r.cavity_amplitude = X;
  r.gamma = X * w * w / ctx.gravity;
  r.clearance_ratio = X > 0 ? ctx.clearance / X : kNaN;
  r.bag_mass = ctx.bag_mass;
  r.mass_ratio = ctx.primary_mass > 0 ? ctx.bag_mass / ctx.primary_mass : kNaN;
  r.balls = ctx.balls, r.ball_diameter = ctx.ball_diameter;
  r.M_eff = ep.mass, r.M_eff_se = ep.mass_se, r.M_eff_ci95 = ep.mass_ci95;
  r.C_eff = ep.damping, r.C_eff_se = ep.damping_se, r.C_eff_ci95 = ep.damping_ci95;
  const double per_mbw = ctx.bag_mass > 0 ? 1 / (ctx.bag_mass * w) : kNaN;
  r.M_eff_ratio = ctx.bag_mass > 0 ? ep.mass / ctx.bag_mass : kNaN;
  r.Cb_over_Mbw = ep.damping * per_mbw, r.Cb_over_Mbw_se = ep.damping_se * per_mbw, r.Cb_over_Mbw_ci95 = ep.damping_ci95 * per_mbw;
  r.loss_factor = ep.loss_factor;
  r.energy_per_cycle = ep.energy_per_cycle, r.energy_per_cycle_se = ep.energy_per_cycle_se;
  r.energy_per_cycle_ci95 = ep.energy_per_cycle_ci95;
  r.cycles = static_cast<double>(ep.cycles);
  r.response_amplitude = kNaN;

  // Impacts over the same whole cycles: same-side bursts closer than a twentieth of a period are
  // one impact (a bag's contents arrive in waves).
  const double T = 1 / f, t0 = std::max(t_skip, s.t.empty() ? 0.0 : s.t.front());
  const double span = static_cast<double>(ep.cycles) * T;
  std::vector<double> t, F, v;
  for (std::size_t k = 0; k < s.t.size(); ++k)
    if (s.t[k] >= t0 - 1e-12 * T && s.t[k] <= t0 + span + 1e-12 * T) t.push_back(s.t[k]), F.push_back(s.force[k]), v.push_back(s.v_rel[k]);
  constexpr double kThreshold = 0.05;
  const std::vector<Impact> impacts = t.size() > 2 ? find_impacts(t, F, t.front(), kThreshold, T / 20) : std::vector<Impact>{};
  r.impacts_per_cycle = static_cast<double>(impacts.size()) / std::max(1.0, r.cycles);
  r.impact_phase = r.e_impact = r.e_impact_sd = r.e_eq19a = kNaN;
  Interval impact_interval{.mean = kNaN, .se = kNaN, .ci95 = kNaN};
  if (!impacts.empty()) {
    std::vector<double> phases;
    double peak = 0, peak_max = 0, duration = 0, largest = 0;
    for (const Impact& i : impacts) {
      phases.push_back(std::fmod(motion_phase(ep.displacement, w, i.t_centroid), kPi));
      peak += i.peak_force, duration += i.duration();
      peak_max = std::max(peak_max, i.peak_force);
    }
    for (double x : F) largest = std::max(largest, std::abs(x));
    const double n = static_cast<double>(impacts.size());
    r.impact_phase = axial_mean(phases);
    r.peak_impact_force = peak / n, r.max_impact_force = peak_max, r.impact_duration = duration / n;
    // Per impact (Eq. 9) between free flights of a twentieth of a period, approaching at a tenth of
    // the cavity's speed amplitude or faster, the velocities relative to the wall at the impact's
    // centroid (the cavity's first harmonic: x = Re(X e^{iwt}), x' = Re(i w X e^{iwt})).
    const FreeFlight rule{.span = T / 20, .threshold = kThreshold * largest, .min_approach_speed = 0.1 * w * X};
    const std::complex<double> V = std::complex<double>(0, w) * ep.displacement;
    const WallVelocity wall = [V, w](double time) { return (V * std::polar(1.0, w * time)).real(); };
    const RestitutionStats e = impact_restitution(impacts, t, v, F, rule, wall);
    r.e_impact_count = static_cast<double>(e.values.size());
    if (e.values.size() >= kMinImpactsForRestitution) {
      impact_interval = batch_means_interval(e.values);
      r.e_impact = e.body();
      r.e_impact_sd = e.sd;
    }
    r.e_eq19a = eq19a_restitution(r.Cb_over_Mbw, r.impact_phase);
  }
  choose_restitution(r, impact_interval);
  return r;
}

const std::vector<TableColumn>& reduced_columns() { return kColumns; }

std::vector<double> reduced_values(const ReducedRow& r) {
  std::vector<double> v;
  for (const RealField& f : kRealFields) v.push_back(r.*f.member);
  for (double x : {r.displacement.real(), r.displacement.imag(), r.force.real(), r.force.imag()}) v.push_back(x);
  return v;
}

void write_reduced_csv(const fs::path& path, const std::vector<ReducedRow>& rows) {
  std::vector<std::vector<double>> values;
  std::vector<std::vector<std::string>> methods;
  for (const ReducedRow& r : rows) values.push_back(reduced_values(r)), methods.push_back({r.e_method});
  write_table_csv(path, kColumns, values, {kMethodColumn}, methods);
}

std::vector<ReducedRow> read_reduced_csv(const fs::path& path) {
  const std::vector<std::vector<double>> values = read_table_csv(path, kColumns);
  const TextTable text = read_text_table(path);
  const std::size_t method = text.find(kMethodColumn.name);
  if (method == text.names.size()) throw InputError(path.string(), kMethodColumn.name, "", "column missing from the table");
  std::vector<ReducedRow> rows;
  for (std::size_t i = 0; i < values.size(); ++i) rows.push_back(reduced_row(values[i], text.rows[i][method]));
  return rows;
}

ReducedRow reduced_row(const std::vector<double>& v, const std::string& e_method) {
  if (v.size() != kReal + 4)
    throw std::invalid_argument("a reduced row has " + std::to_string(kReal + 4) + " values, not " + std::to_string(v.size()));
  ReducedRow r;
  for (std::size_t k = 0; k < kReal; ++k) r.*kRealFields[k].member = v[k];
  r.displacement = {v[kReal], v[kReal + 1]};
  r.force = {v[kReal + 2], v[kReal + 3]};
  r.e_method = e_method;
  return r;
}

namespace {

// Reading a closed results file: what is missing or unreadable is an InputError naming it.
struct ResultsReader {
  std::string path;
  h5::H5 file;
  h5::Check ok{[this](const std::string& what) { throw InputError(path, "", "", what + " (a damaged file?)"); }};

  bool has(const char* group) const { return H5Lexists(file, group, H5P_DEFAULT) > 0; }
  std::vector<double> series(const std::string& name) const {
    if (H5Lexists(file, name.substr(0, name.find('/', 1)).c_str(), H5P_DEFAULT) <= 0 ||
        H5Lexists(file, name.c_str(), H5P_DEFAULT) <= 0)
      throw InputError(path, name, "", "is missing: the run wrote no such series");
    h5::H5 ds(ok(H5Dopen2(file, name.c_str(), H5P_DEFAULT), name), H5Dclose);
    return h5::read_doubles(ds, name, ok);
  }
  // A root attribute ("" or NaN when absent).
  std::string text(const char* name) const {
    if (H5Aexists(file, name) <= 0) return "";
    h5::H5 a(ok(H5Aopen(file, name, H5P_DEFAULT), name), H5Aclose);
    return h5::read_string(a, name, ok);
  }
  double number(const char* name) const {
    if (H5Aexists(file, name) <= 0) return kNaN;
    double v = kNaN;
    h5::H5 a(ok(H5Aopen(file, name, H5P_DEFAULT), name), H5Aclose);
    ok(H5Aread(a, H5T_NATIVE_DOUBLE, &v), name);
    return v;
  }
};

}  // namespace

// A reduction with another case (an edited case.toml, other --set options) would reproject the
// run as something it was not (reduce.hpp).
void require_case_of_run(const fs::path& h5, const Scene& scene, const char* missing) {
  if (!fs::exists(h5)) throw InputError(h5.string(), "", "", missing);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // failures become exceptions, not stderr dumps
  const ResultsReader in{h5.string(), h5::H5(H5Fopen(h5.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose)};
  if (in.file < 0) throw InputError(h5.string(), "", "", "is not a readable HDF5 file");
  // output.skip_cycles chooses what is reduced, not what was run: it may differ.
  const std::string diff = case_differences(in.text("resolved_config"), scene.resolved, kReducedAtAnyCycles);
  if (!diff.empty())
    throw InputError(h5.string(), "resolved_config", "",
                     "the case differs from the one the run was made with (" + diff +
                         "); give the case and the --set options of the run (only output.skip_cycles may change), or run it again");
}

std::vector<ReducedRow> reduce_run(const Scene& scene, const std::string& out_dir) {
  const fs::path out = out_dir;
  if (scene.primary && scene.primary->stepped_sine) {
    require_case_of_run(out / "results.h5", scene, "is missing: run the sweep first (bagdem run)");
    const fs::path csv = out / "reduced.csv";
    if (!fs::exists(csv))
      throw InputError(csv.string(), "", "", fs::exists(out / "reduced.partial.csv")
                                                 ? std::string("is missing: the last sweep in this directory did not finish (reduced.partial.csv "
                                                               "holds its points so far); ") +
                                                       (fs::exists(out / "checkpoint.bin") ? "resume it (bagdem run --resume) or run it again"
                                                                                           : "it stopped as it wrote its tables: run it again")
                                                 : "is missing: run the sweep first (bagdem run)");
    // The figures the run measured must be its record's (/reduced; a sweep of a bagdem before that
    // record has none to check against). The restitution's columns are not: reduce attaches a drop
    // test run since (attach_drop_result).
    if (ResultsReader{(out / "results.h5").string(), h5::H5(H5Fopen((out / "results.h5").string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose)}
            .has("/reduced")) {
      std::vector<TableColumn> measured;
      for (const TableColumn& c : kColumns)
        if (std::none_of(std::begin(kRestitutionColumns), std::end(kRestitutionColumns), [&](const char* e) { return std::string_view(c.name) == e; }))
          measured.push_back(c);
      require_recorded_table(csv, out / "results.h5", "reduced", measured);
    }
    return read_reduced_csv(csv);
  }
  const double f = scene.motion->frequency();
  if (scene.primary || !(f > 0))
    throw InputError(scene.case_file, "cavity.motion.kind", "", "reduction needs harmonic cavity motion ([cavity.motion] kind = \"harmonic\") or a stepped-sine sweep of a primary structure");
  const fs::path h5 = out / "results.h5";
  require_case_of_run(h5, scene, "is missing: run the case first (bagdem run)");
  const ResultsReader in{h5.string(), h5::H5(H5Fopen(h5.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose)};
  const std::string status = in.text("status");
  if (status != "complete") throw InputError(h5.string(), "status", status, "must be \"complete\": reduce a finished run");
  const std::vector<double> t = in.series("/cavity/time"), pos = in.series("/cavity/position"),
                            force = in.series("/cavity/force"), vrel = in.series("/cavity/contents_velocity");
  const double clearance = in.number("clearance");
  if (t.size() < 4) throw InputError(h5.string(), "/cavity/time", std::to_string(t.size()), "too few samples to reduce");
  const Vec3 e = excitation_direction(scene);
  if (e.norm() == 0) throw InputError(scene.case_file, "cavity.motion", "", "the cavity does not move: nothing to reduce");
  // Samples are interval means centred on t: the intervals end half an interval later. The run's
  // last sample may cover a shorter interval (the run's end): it is left out.
  const double interval = t[1] - t[0];
  std::size_t n = t.size();
  if (std::abs((t[n - 1] - t[n - 2]) - interval) > 1e-6 * interval) --n;
  CavitySeries s;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 x(pos[3 * k], pos[3 * k + 1], pos[3 * k + 2]), F(force[3 * k], force[3 * k + 1], force[3 * k + 2]);
    const Vec3 v(vrel[3 * k], vrel[3 * k + 1], vrel[3 * k + 2]);
    s.t.push_back(t[k] + 0.5 * interval), s.x.push_back(x.dot(e)), s.force.push_back(F.dot(e)), s.v_rel.push_back(v.dot(e));
  }
  ReductionContext ctx = reduction_context(scene, e);
  ctx.clearance = clearance;
  const double t_skip = scene.settle + scene.motion->ramp_time() + scene.output.skip_cycles / f;
  std::vector<ReducedRow> rows;
  try {
    rows.push_back(reduce_series(s, f, t_skip, ctx));
  } catch (const std::invalid_argument& e) {  // too few whole cycles after settling, the ramp and skip_cycles
    throw InputError(h5.string(), "/cavity/time", std::to_string(s.t.back()) + " s",
                     std::string("cannot be reduced: ") + e.what() + "; run longer (simulation.duration)");
  }
  // The energy over the window: the force samples' intervals from the first after t_skip on.
  ReducedRow& row = rows.front();
  if (H5Lexists(in.file, "/energy", H5P_DEFAULT) > 0) {
    const auto first = std::lower_bound(s.t.begin(), s.t.end(), t_skip - 1e-9 * interval);
    const double t0 = (first == s.t.end() ? s.t.back() : *first) - interval;
    EnergyWindow w;
    w.t = in.series("/energy/time");
    for (const char* name : {"kinetic", "elastic", "work_cavity", "work_gravity"}) w.fields.push_back(in.series(std::string("/energy/") + name));
    std::vector<double> dissipated(w.t.size(), 0.0);
    for (const char* name : {"dissipated_normal", "dissipated_tangential", "dissipated_rolling", "dissipated_damping"}) {
      const std::vector<double> d = in.series(std::string("/energy/") + name);
      for (std::size_t k = 0; k < d.size() && k < dissipated.size(); ++k) dissipated[k] += d[k];
    }
    w.fields.push_back(dissipated);
    set_energy_balance(row, w, t0, t0 + row.cycles / f);
  }
  judge_steady(row);
  write_reduced_csv(out / "reduced.csv", rows);
  return rows;
}

std::string describe_restitution(const std::vector<ReducedRow>& rows) {
  std::ostringstream o;
  o << std::setprecision(4);
  for (const ReducedRow& r : rows) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (double e : {r.e_impact, r.e_eq19a, r.e_drop})
      if (std::isfinite(e)) lo = std::min(lo, e), hi = std::max(hi, e);
    o << "restitution at " << r.frequency << " Hz: ";
    if (r.e_method == "none") o << "none (no estimator gave one: e is left empty)";
    else o << "e = " << r.e << " +- " << r.e_ci95 << " (" << r.e_method << ")";
    o << "; per impact "
      << r.e_impact << " (sd " << r.e_impact_sd << ", " << r.e_impact_count << " impacts between free flights), Eq. (19a) "
      << r.e_eq19a << ", drop test " << (std::isfinite(r.e_drop) ? std::to_string(r.e_drop) : std::string("not run"));
    if (hi > lo) o << "; they span " << hi - lo;
    o << "\n";
  }
  return o.str();
}

bool check_drop_result(const std::string& out_dir, const Scene& scene) {
  const fs::path p = fs::path(out_dir) / "drop_result.csv";
  if (!fs::exists(p)) return false;
  if (!check_drop_record(p, scene))
    std::fprintf(stderr, "warning: %s has no drop_result.toml (a drop test of an earlier bagdem): its e is attached unchecked\n", p.c_str());
  return true;
}

void attach_drop_result(std::vector<ReducedRow>& rows, const std::string& out_dir) {
  const fs::path p = fs::path(out_dir) / "drop_result.csv";
  if (!fs::exists(p)) return;
  const std::vector<std::vector<double>> v = read_table_csv(p, {{"restitution", "1"}});
  if (v.empty()) return;
  for (ReducedRow& r : rows) {
    r.e_drop = v.front().front();
    if (r.e_method == "none" || r.e_method == "drop") choose_restitution(r, Interval{.mean = kNaN, .se = kNaN, .ci95 = kNaN});
  }
  write_reduced_csv(fs::path(out_dir) / "reduced.csv", rows);
}

namespace {
// A figure as the table's other cells print (4 significant digits).
std::string number_text(double x) {
  std::ostringstream o;
  o << std::setprecision(4) << x;
  return o.str();
}
}  // namespace

std::string describe_reduced(const std::vector<ReducedRow>& rows) {
  std::ostringstream o;
  o << std::setprecision(4);
  o << "(+- the half-width of a 95% interval; * a window that is not steady, left out of the peak reduction; ! C_eff below zero\n"
       " beyond its interval: the contents gave energy back at the drive frequency)\n";
  o << "  f [Hz]      X [m]  Gamma     d/X  M_eff/M_bag (+-)    Cb/(Mb w) (+-)       loss  E/cycle [J]  phi [rad]  e (+-)            method  F_peak [N]  t_imp [s]\n";
  for (const ReducedRow& r : rows) {
    const bool negative = r.C_eff + (std::isfinite(r.C_eff_ci95) ? r.C_eff_ci95 : 0.0) < 0;
    o << (r.steady == 1 ? (negative ? '!' : ' ') : '*') << std::setw(7) << r.frequency << " " << std::setw(10) << r.cavity_amplitude << " " << std::setw(6)
      << r.gamma << " " << std::setw(7) << r.clearance_ratio << " " << std::setw(8) << r.M_eff_ratio << " (" << std::setw(7)
      << r.M_eff_ci95 / r.bag_mass << ") " << std::setw(8) << r.Cb_over_Mbw << " (" << std::setw(7) << r.Cb_over_Mbw_ci95 << ") "
      << std::setw(8) << r.loss_factor << " " << std::setw(12) << r.energy_per_cycle << " " << std::setw(10) << r.impact_phase << " "
      << std::setw(6) << (r.e_method == "none" ? std::string("-") : number_text(r.e)) << " (" << std::setw(7)
      << (r.e_method == "none" ? std::string("-") : number_text(r.e_ci95)) << ") " << std::setw(7) << r.e_method << " " << std::setw(11)
      << r.peak_impact_force << " " << std::setw(10) << r.impact_duration << "\n";
  }
  return o.str();
}

}  // namespace bagdem
