// `bagdem trade`: the ladder of fidelity settings of a case run as a study, each rung against the
// reference; and the fidelity presets. See study/trade.hpp.
#include "bagdem/study/trade.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <toml++/toml.h>

#include "bagdem/io/atomic_file.hpp"
#include "bagdem/case/case_reader.hpp"
#include "bagdem/case/load_case.hpp"
#include "bagdem/case/overrides.hpp"
#include "bagdem/contact/law.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/output_lock.hpp"
#include "bagdem/study/study.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;

namespace {

// What the knobs need to know of a case, read once.
struct CaseFacts {
  std::string case_dir;
  bool explicit_step = false;
  double dt = 0, safety = 0.2, steps_per_contact = 40;
  long long seed = 0;
  std::vector<std::pair<std::string, double>> ball_materials;  // name, Young's modulus
  std::vector<std::pair<std::string, double>> springs;         // [interactions.NAME] with a stiffness (Hooke): NAME, k_n
  std::size_t triangles = 0;                                  // 0: no bag
  std::vector<std::string> interactions;                      // [interactions.NAME]
  bool friction = false, rolling = false;
  double cavity_interval = 0;
  double steady_tolerance = 0;                                // 0: no sweep
};

CaseFacts case_facts(const std::string& case_dir, const std::vector<std::string>& sets) {
  const Scene s = load_case(case_dir, sets);
  refuse_several_dampers(s, "bagdem trade", "measures the trade on one damper");
  CaseFacts f;
  f.case_dir = case_dir;
  f.explicit_step = s.dt_reason.rfind("auto", 0) != 0;
  f.dt = s.dt;
  f.seed = static_cast<long long>(s.seed);
  std::set<int> used;
  for (const auto& p : s.particles) used.insert(p.material);
  for (int m : used) f.ball_materials.emplace_back(s.materials[static_cast<std::size_t>(m)].name, s.materials[static_cast<std::size_t>(m)].youngs_modulus);
  // The Hooke law's springs are the users' stiffness, not the moduli's: the knob scales them too.
  const CaseReader in(s.case_file, sets);
  for (const std::string& name : in.keys("interactions"))
    if (in.has("interactions." + name + ".stiffness"))
      f.springs.emplace_back(name, in.quantity("interactions." + name + ".stiffness", dim::stiffness));
  if (s.bag) f.triangles = s.bag->rest.triangles.size();
  f.friction = s.models.tangential;
  f.rolling = s.models.rolling;
  f.cavity_interval = s.output.cavity_interval;
  if (s.primary && s.primary->stepped_sine) f.steady_tolerance = s.primary->stepped_sine->tolerance;
  // The safety factor, the steps per contact and the interaction tables as resolved (the case file
  // with the user's --set applied: a knob scales the user's value, not the file's).
  try {
    const toml::table t = toml::parse(s.resolved);
    f.safety = t["simulation"]["timestep_safety"].value_or(0.2);         // timestep.cpp's defaults
    f.steps_per_contact = t["simulation"]["steps_per_contact"].value_or(40.0);
    if (const toml::table* in = t["interactions"].as_table())
      for (const auto& [name, node] : *in)
        if (node.is_table()) f.interactions.emplace_back(name.str());
  } catch (const toml::parse_error& e) {
    throw InputError(s.case_file, "", "", std::string("the resolved case cannot be read back: ") + std::string(e.description()));
  }
  return f;
}

std::vector<std::string> knob_overrides(const CaseFacts& f, const std::string& knob, double factor) {
  Overrides o;
  if (knob == "timestep") {
    if (f.explicit_step) o.set(keys::timestep, f.dt * factor);
    else {
      // The automatic step is the least of several limits (timestep.cpp): scale the two a user sets.
      o.set(keys::timestep_safety, std::min(1.0, f.safety * factor));
      o.set(keys::steps_per_contact, std::max(10.0, f.steps_per_contact / factor));
    }
  } else if (knob == "stiffness") {
    for (const auto& [name, E] : f.ball_materials) o.set(keys::youngs_modulus(name), E * factor);
    for (const auto& [name, k] : f.springs) o.set(keys::stiffness(name), k * factor);
  } else if (knob == "film") {
    if (f.triangles > 0) o.set(keys::triangles, std::max<long long>(20, std::llround(static_cast<double>(f.triangles) * factor)));
  } else if (knob == "bending") {
    if (f.triangles > 0) o.set(TomlKey{keys::bending_interval.path}, factor == 1 ? "1" : "\"auto\"");
  } else if (knob == "tangential") {
    if (f.friction && factor == 0)
      for (const std::string& i : f.interactions) o.set(keys::friction(i), 0);
  } else if (knob == "rolling") {
    if (f.rolling && factor == 0)
      for (const std::string& i : f.interactions) o.set(keys::rolling_friction(i), 0);
  } else if (knob == "output") {
    o.set(keys::cavity_interval, f.cavity_interval * factor);
  } else if (knob == "steady") {
    if (f.steady_tolerance > 0) o.set(keys::steady_tolerance, f.steady_tolerance * factor);
  } else {
    std::string names;
    for (const Knob& k : knobs()) names += (names.empty() ? "" : ", ") + k.name;
    throw InputError("bagdem trade", "--knobs", knob, "is not a knob (allowed: " + names + ", none)");
  }
  return std::move(o).sets();
}

bool applies(const CaseFacts& f, const std::string& knob) {
  if (knob == "film" || knob == "bending") return f.triangles > 0;
  if (knob == "tangential") return f.friction;
  if (knob == "rolling") return f.rolling;
  if (knob == "steady") return f.steady_tolerance > 0;
  return true;
}

std::vector<std::string> preset_overrides(const CaseFacts& f, const std::string& preset) {
  std::vector<std::string> o;
  auto add = [&](const std::string& knob, double factor) {
    const auto k = knob_overrides(f, knob, factor);
    o.insert(o.end(), k.begin(), k.end());
  };
  if (preset == "reference") {
    for (const Knob& k : knobs())
      if (applies(f, k.name) && k.factors.front() != 1) add(k.name, k.factors.front());
  } else if (preset == "fast") {
    add("timestep", 2);
    if (applies(f, "film")) add("film", 0.5);
    if (applies(f, "steady")) add("steady", 2);
  } else if (preset != "balanced") {
    throw InputError("bagdem", "--fidelity", preset, "is not a preset (allowed: fast, balanced, reference)");
  }
  return o;
}

std::string knob_label(const Knob& k, double factor) {
  if (k.name == "tangential" || k.name == "rolling") return k.name + (factor == 0 ? " off" : " on");
  if (k.name == "bending") return factor == 1 ? "bending every step" : "bending on its clock";
  return k.name + " x" + short_text(factor);
}

// ---- the table ----------------------------------------------------------------------------------

double cell_number(const Table& t, std::size_t row, const std::string& column) {
  for (std::size_t c = 0; c < t.columns.size(); ++c)
    if (t.columns[c] == column && row < t.rows.size() && c < t.rows[row].size() && !t.rows[row][c].empty()) {
      try {
        return std::stod(t.rows[row][c]);
      } catch (...) {
        return NAN;
      }
    }
  return NAN;
}

struct RungResult {
  bool done = false;
  double wall = NAN, dt = NAN, contact_time = NAN;
  std::map<std::string, double> metric;  // "reduction_dB mode 1", "Cb_over_Mbw", ...
};

// The quantities users care about, from reduced.csv at the row nearest the first mode's damped
// peak (a sweep) or its first row (prescribed motion), and each mode's peak reduction.
const std::vector<std::pair<std::string, std::string>> kReducedMetrics = {
    {"Cb_over_Mbw", "Cb_over_Mbw [1]"}, {"M_eff_ratio", "M_eff_ratio [1]"}, {"e_impact", "e_impact [1]"},
    {"e_eq19a", "e_eq19a [1]"},         {"energy_per_cycle", "energy_per_cycle [J]"},
    {"peak_impact_force", "peak_impact_force [N]"}};

RungResult read_rung(const Plan& plan, const Point& p, const Rung& rung) {
  RungResult r;
  const fs::path dir = plan.point_dir(p);
  r.done = fs::exists(dir / "point.done");
  {
    std::ifstream in(dir / "point.done");
    std::string line;
    while (std::getline(in, line))
      if (line.rfind("wall_time = ", 0) == 0) r.wall = std::stod(line.substr(12));
  }
  // The step and the contact duration of two of the smallest balls at the expected impact speed
  // (their law's: Hertz's is Johnson 1985, 11.24), for the stiffness knob's effect.
  const Scene s = load_case(plan.spec.case_dir, rung.sets);
  r.dt = s.dt;
  if (!s.particles.empty()) {
    std::size_t k = 0;
    for (std::size_t i = 0; i < s.particles.size(); ++i)
      if (s.particles[i].radius < s.particles[k].radius) k = i;
    const auto& ball = s.particles[k];
    const Material& m = s.materials[static_cast<std::size_t>(ball.material)];
    const double mass = m.density * 4.0 / 3.0 * 3.141592653589793 * std::pow(ball.radius, 3);
    const PairLaw& law = s.laws(ball.material, ball.material);
    r.contact_time = contact_law(law.kind).contact_time(law, 0.5 * mass, 0.5 * ball.radius, s.expected_speed);
  }
  if (!r.done) return r;
  double peak_frequency = NAN;
  if (fs::exists(dir / "peaks.csv")) {
    const Table peaks = read_csv((dir / "peaks.csv").string());
    for (std::size_t i = 0; i < peaks.rows.size(); ++i) {
      const double mode = cell_number(peaks, i, "mode [1]");
      r.metric["reduction_dB mode " + short_text(mode)] = cell_number(peaks, i, "reduction_dB [dB]");
      if (i == 0) peak_frequency = cell_number(peaks, i, "frequency [Hz]");
    }
  }
  if (fs::exists(dir / "reduced.csv")) {
    const Table red = read_csv((dir / "reduced.csv").string());
    std::size_t row = 0;
    if (!std::isnan(peak_frequency))
      for (std::size_t i = 0; i < red.rows.size(); ++i)
        if (std::abs(cell_number(red, i, "frequency [Hz]") - peak_frequency) <
            std::abs(cell_number(red, row, "frequency [Hz]") - peak_frequency))
          row = i;
    for (const auto& [name, column] : kReducedMetrics) r.metric[name] = cell_number(red, row, column);
  }
  return r;
}

}  // namespace

const std::vector<Knob>& knobs() {
  static const std::vector<Knob> table = {
      {"timestep", "simulation.timestep_safety x factor and steps_per_contact / factor (or an explicit simulation.timestep x factor)", {0.5, 1, 2}},
      {"stiffness", "Young's modulus of every ball material, and the spring of every Hooke interaction, x factor (softening)",
       {1, 0.1, 0.01}},
      {"film", "bag.triangles x factor (film resolution)", {2, 1, 0.5}},
      {"bending", "the film's bending hinges on every step (1) or on their slower clock (0: bag.film.bending_interval = \"auto\")", {1, 0}},
      {"tangential", "tangential model (friction) on / off", {1, 0}},
      {"rolling", "rolling resistance on / off", {1, 0}},
      {"output", "output.cavity_interval x factor (the reduction's sampling)", {1, 4}},
      {"steady", "excitation.steady_tolerance x factor (sweeps)", {0.5, 1, 2}},
  };
  return table;
}

std::vector<std::string> fidelity_sets(const std::string& case_dir, const std::vector<std::string>& sets,
                                       const std::string& preset) {
  if (preset == "balanced") return {};
  if (preset != "fast" && preset != "reference")
    throw InputError("bagdem", "--fidelity", preset, "is not a preset (allowed: fast, balanced, reference)");
  return preset_overrides(case_facts(case_dir, sets), preset);
}

std::vector<Rung> trade_ladder(const std::string& case_dir, const std::vector<std::string>& sets,
                               const std::vector<std::string>& only) {
  const CaseFacts f = case_facts(case_dir, sets);
  // "none": only the reference, its reseeded twin and the presets.
  for (const std::string& k : only)
    if (k != "none") knob_overrides(f, k, 1);  // an unknown knob throws
  auto chosen = [&](const std::string& k) { return only.empty() || std::find(only.begin(), only.end(), k) != only.end(); };
  // The reference: every knob that applies at its reference setting.
  std::map<std::string, std::vector<std::string>> ref;
  for (const Knob& k : knobs())
    if (applies(f, k.name)) ref[k.name] = knob_overrides(f, k.name, k.factors.front());
  auto with = [&](const std::string& knob, const std::vector<std::string>& own) {
    std::vector<std::string> all = sets;
    for (const Knob& k : knobs()) {
      if (!ref.count(k.name)) continue;
      const auto& o = k.name == knob ? own : ref[k.name];
      all.insert(all.end(), o.begin(), o.end());
    }
    return all;
  };
  std::vector<Rung> ladder;
  ladder.push_back({"reference", "", with("", {})});
  // The noise floor: the reference with another packing seed (a chaotic bed's results move by this
  // much without any shortcut).
  Overrides reseeded(with("", {}));
  reseeded.set(keys::seed, f.seed + 1);
  ladder.push_back({"reference, seed+1", "seed", std::move(reseeded).sets()});
  for (const Knob& k : knobs()) {
    if (!applies(f, k.name) || !chosen(k.name)) continue;
    for (std::size_t i = 1; i < k.factors.size(); ++i)
      ladder.push_back({knob_label(k, k.factors[i]), k.name, with(k.name, knob_overrides(f, k.name, k.factors[i]))});
  }
  for (const char* preset : {"balanced", "fast"}) {
    std::vector<std::string> all = sets;
    const auto o = preset_overrides(f, preset);
    all.insert(all.end(), o.begin(), o.end());
    ladder.push_back({std::string("preset ") + preset, "", all});
  }
  return ladder;
}

namespace {

// The table of a finished trade: each rung against the reference, printed and written to
// OUT/trade.csv. Returns whether a rung failed.
bool write_trade_table(const Plan& plan, const std::vector<Rung>& ladder) {
  // The table: each rung against the reference.
  std::vector<RungResult> res;
  for (std::size_t k = 0; k < ladder.size(); ++k) res.push_back(read_rung(plan, plan.points[k], ladder[k]));
  std::vector<std::string> metrics;
  for (const RungResult& r : res)
    for (const auto& [name, v] : r.metric)
      if (std::find(metrics.begin(), metrics.end(), name) == metrics.end()) metrics.push_back(name);
  std::stable_sort(metrics.begin(), metrics.end(), [](const std::string& a, const std::string& b) {
    return (a.rfind("reduction_dB", 0) == 0) > (b.rfind("reduction_dB", 0) == 0);
  });
  auto unit_of = [](const std::string& m) {
    if (m.rfind("reduction_dB", 0) == 0) return std::string("dB");
    if (m == "energy_per_cycle") return std::string("J");
    if (m == "peak_impact_force") return std::string("N");
    return std::string("1");
  };
  const RungResult& ref = res.front();
  std::ostringstream csv;
  csv << "rung,knob,status,wall_time [s],speedup [1],dt [s],contact_time [s]";
  for (const std::string& m : metrics) {
    const bool db = m.rfind("reduction_dB", 0) == 0;
    csv << ',' << m << " [" << unit_of(m) << "]," << m << (db ? "_error [dB]" : "_error [1]");
  }
  csv << '\n';
  std::printf("%-18s %8s %7s %10s %10s", "run", "wall [s]", "speedup", "dt [s]", "t_c [s]");
  for (const std::string& m : metrics) std::printf("  %s", (m.rfind("reduction_dB", 0) == 0 ? "dB" + m.substr(12) : m).c_str());
  std::printf("\n%-18s %8s %7s %10s %10s", "", "", "", "", "");
  for (const std::string& m : metrics)
    std::printf("  %*s", static_cast<int>((m.rfind("reduction_dB", 0) == 0 ? 2 + m.size() - 12 : m.size())),
                m.rfind("reduction_dB", 0) == 0 ? "(diff)" : "(rel. err)");
  std::printf("\n");
  bool failed = false;
  for (std::size_t k = 0; k < ladder.size(); ++k) {
    const RungResult& r = res[k];
    failed = failed || !r.done;
    const double speedup = ref.wall / r.wall;
    csv << '"' << ladder[k].name << "\"," << ladder[k].knob << ',' << (r.done ? "done" : "failed") << ',' << short_text(r.wall)
        << ',' << short_text(speedup) << ',' << short_text(r.dt) << ',' << short_text(r.contact_time);
    std::printf("%-18s %8.1f %7.2f %10.3g %10.3g", ladder[k].name.c_str(), r.wall, speedup, r.dt, r.contact_time);
    for (const std::string& m : metrics) {
      const bool db = m.rfind("reduction_dB", 0) == 0;
      const double v = r.metric.count(m) ? r.metric.at(m) : NAN;
      const double v0 = ref.metric.count(m) ? ref.metric.at(m) : NAN;
      // C_b/(M_b w) and M_eff/M_bag are the parts of one complex effective mass: their errors are
      // relative to its magnitude (either part may be near zero).
      double scale = std::abs(v0);
      if (m == "Cb_over_Mbw" || m == "M_eff_ratio") scale = std::hypot(ref.metric.count("Cb_over_Mbw") ? ref.metric.at("Cb_over_Mbw") : 0.0,
                                                                     ref.metric.count("M_eff_ratio") ? ref.metric.at("M_eff_ratio") : 0.0);
      const double err = db ? v - v0 : std::abs(v - v0) / scale;
      csv << ',' << short_text(v) << ',' << short_text(err);
      const int w = static_cast<int>(db ? 2 + m.size() - 12 : m.size());
      char cell[64];
      if (db) std::snprintf(cell, sizeof cell, "%.2f (%+.2f)", v, err);
      else std::snprintf(cell, sizeof cell, "%.3g (%.1f%%)", v, 100 * err);
      std::printf("  %*s", std::max(w, 14), cell);
    }
    std::printf("\n");
    csv << '\n';
  }
  write_atomically(fs::path(plan.spec.out_dir) / "trade.csv", csv.str());
  return failed;
}

// The trade's plan: a rung a point (its overrides), the study's spec from the command line.
Plan trade_plan(const TradeArgs& args, std::vector<Rung>& ladder) {
  Plan plan;
  StudySpec& spec = plan.spec;
  spec.case_dir = fs::absolute(args.dir).lexically_normal().string();
  if (!fs::exists(fs::path(spec.case_dir) / "case.toml"))
    throw InputError(args.dir, "", "", "holds no case.toml (bagdem trade takes a case directory)");
  spec.out_dir = fs::absolute(args.out.empty() ? fs::path(spec.case_dir) / "trade" : fs::path(args.out)).lexically_normal().string();
  spec.source = "bagdem trade";
  spec.command = "trade";
  spec.combine = Combine::zip;
  spec.jobs = args.jobs, spec.threads = args.threads, spec.cores = args.cores;
  spec.tables = {"reduced", "peaks"};
  ladder = trade_ladder(spec.case_dir, args.sets, args.only);
  Varied rung{"rung", {}};
  for (const Rung& r : ladder) rung.values.push_back({"\"" + r.name + "\"", r.name});
  spec.vary.push_back(rung);
  for (std::size_t k = 0; k < ladder.size(); ++k) {
    Point p;
    p.index = p.combination = k;
    p.choice = {k};
    p.sets = ladder[k].sets;
    p.name = point_name(k, ladder.size());
    plan.points.push_back(p);
  }
  return plan;
}

}  // namespace

int trade_command(const TradeArgs& args) {
  const auto t0 = std::chrono::steady_clock::now();
  Plan plan;
  std::vector<Rung> ladder;
  Budget budget;
  std::optional<OutputLock> lock;
  std::vector<bool> done;
  if (const int code = reporting_errors([&] {
    plan = trade_plan(args, ladder);
    budget = resolve_budget(plan.spec, machine_cores(), "the cores of this machine", "bagdem trade");
    for (const std::string& w : validate_plan(plan)) std::fprintf(stderr, "warning: %s\n", w.c_str());
    refuse_other_outputs(plan.spec.out_dir, OutputOwner::study);
    lock.emplace(plan.spec.out_dir);  // one study writes a directory at a time; its runs write inside it
    share_output_with_children(plan.spec.out_dir);
    done = done_points(plan);
    return 0;
  }))
    return code;
  try {
    std::fprintf(stderr, "bagdem trade %s: %zu runs -> %s; %d at once with %d thread%s\n", plan.spec.case_dir.c_str(), ladder.size(),
                 plan.spec.out_dir.c_str(), budget.jobs, budget.threads, budget.threads > 1 ? "s" : "");
    for (std::size_t k = 0; k < ladder.size(); ++k) {
      std::string o;
      for (std::size_t i = args.sets.size(); i < ladder[k].sets.size(); ++i) o += " " + ladder[k].sets[i];
      std::fprintf(stderr, "  %s  %-18s%s\n", plan.points[k].name.c_str(), ladder[k].name.c_str(), o.c_str());
    }
    fs::create_directories(plan.spec.out_dir);
    remove_merged_tables(plan);
    run_share(plan, done, budget, args.executable);
    merge_tables(plan, finished_points(plan));

    const bool failed = write_trade_table(plan, ladder);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("trade %s: %zu runs, %.1f s wall -> %s/trade.csv\n", failed ? "finished with failed runs" : "complete",
                ladder.size(), wall, plan.spec.out_dir.c_str());
    return failed ? kExitRunError : 0;
  } catch (const std::exception& e) {  // after the runs started: not "bad input, nothing run"
    std::fprintf(stderr, "%s: %s\n", error_label(e), e.what());
    return exit_code_after_runs(e);
  }
}

}  // namespace bagdem::study
