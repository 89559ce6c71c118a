#include "bagdem/run/bench.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <variant>

#include "bagdem/case/case_reader.hpp"
#include "bagdem/case/load_case.hpp"
#include "bagdem/case/overrides.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/neighbour/broad_phase.hpp"
#include "bagdem/step/simulation.hpp"

namespace bagdem {
namespace fs = std::filesystem;

namespace {

// A column of a benchmark's table: its heading in the Markdown table (nullptr: the figure joins the
// previous column's cell after a '-', as in "min-max"), its name and unit in the CSV ("text": a
// string), and the printf format of its figure in the Markdown table.
struct BenchColumn {
  const char* heading;
  const char* name;
  const char* unit;
  const char* format;
};

// Prints a benchmark's rows as they are measured: the Markdown table, or with --format csv a header
// row of `name [unit]` entries and one row per measured configuration, numbers at full precision.
// The prose around the table (title, notes, fits) goes to `prose()`: stdout with the table, stderr
// with the CSV, so that stdout holds the CSV alone.
class BenchTable {
 public:
  using Cell = std::variant<double, std::string>;

  BenchTable(const BenchOptions& opt, std::vector<BenchColumn> columns) : csv_(opt.format == "csv"), columns_(std::move(columns)) {}

  std::FILE* prose() const { return csv_ ? stderr : stdout; }

  void header() const {
    std::string line, rule;
    for (const BenchColumn& c : columns_) {
      if (csv_) {
        line += (line.empty() ? "" : ",") + std::string(c.name) + " [" + c.unit + "]";
      } else if (c.heading) {
        line += std::string("| ") + c.heading + " ";
        rule += "|---";
      }
    }
    std::printf("%s\n", csv_ ? line.c_str() : (line + "|\n" + rule + "|").c_str());
  }

  void row(const std::vector<Cell>& cells) const {
    std::string line;
    char figure[64];
    for (std::size_t k = 0; k < columns_.size(); ++k) {
      const BenchColumn& c = columns_[k];
      std::string text;
      if (const auto* v = std::get_if<double>(&cells.at(k))) {
        std::snprintf(figure, sizeof figure, csv_ ? "%.12g" : c.format, *v);
        text = figure;
      } else {
        text = csv_ ? csv_cell(std::get<std::string>(cells[k])) : std::get<std::string>(cells[k]);
      }
      if (csv_) line += (k ? "," : "") + text;
      else line += (c.heading ? (k ? " | " : "| ") : "-") + text;
    }
    std::printf("%s%s\n", line.c_str(), csv_ ? "" : " |");
    std::fflush(stdout);
  }

 private:
  bool csv_;
  std::vector<BenchColumn> columns_;
};

// The columns the PD-box and growth benchmarks share.
constexpr BenchColumn kParticles{"N", "particles", "1", "%.0f"}, kMethod{"method", "method", "text", ""},
    kThreads{"threads", "threads", "1", "%.0f"}, kNs{"ns/particle-step (median)", "ns_per_particle_step", "ns", "%.1f"},
    kNsMin{"min-max", "ns_per_particle_step_min", "ns", "%.1f"}, kNsMax{nullptr, "ns_per_particle_step_max", "ns", "%.1f"},
    kBuilds{"neighbour builds", "neighbour_builds", "1", "%.0f"};

// PD-box geometry rule of gen_pdbox.py: n = round(sqrt(N/4.5)) sites a row, L = 1.05 d n, H = 12 d.
std::vector<std::string> pdbox_overrides(int N, const std::string& data_file) {
  const double d = 0.004;
  const int n = std::max(2, static_cast<int>(std::lround(std::sqrt(N / 4.5))));
  const double L = n * 1.05 * d, H = 12 * d;
  Overrides o;
  o.set(keys::cavity_max, Vec3(L, L, H));
  if (!data_file.empty()) o.set(keys::bed_file, data_file);  // any path: a quote or a backslash in it is escaped
  else o.set(keys::bed_count, N);
  return std::move(o).sets();
}

// What the step loop works on at the end of a run, per particle: candidate pairs (and the share of
// them across the threads' ranges), closed pair contacts and closed wall contacts; and where the
// time of the run went (the stages' shares).
struct Workload {
  double pairs = 0, pair_contacts = 0, wall_contacts = 0;
  double crossing = 0;  // the share of the candidate pairs across the threads' ranges (PairState) (unit: 1)
  double integrate = 0, neighbours = 0, pair_stage = 0, wall_stage = 0;  // shares of the step (unit: 1)
};

double timed_run(const Scene& scene, long long steps, int threads, std::uint64_t* builds, Workload* load = nullptr) {
  omp_set_num_threads(threads);
  Simulation sim(scene);
  // Settling (if any) is not timed.
  const auto settle_steps = static_cast<long long>(std::llround(scene.settle / scene.dt));
  sim.advance(static_cast<std::uint64_t>(settle_steps));
  // With `load`, the stages are clocked too (a read of the clock per stage and step, not free when
  // the step is short), so that run is not one of the timed ones.
  sim.set_profiling(load != nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  sim.advance(static_cast<std::uint64_t>(steps));
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  *builds = sim.neighbour_builds();
  if (load) {
    const auto n = static_cast<double>(sim.particles().size());
    const PairListSize list = sim.pair_list();
    const auto pair_contacts = static_cast<double>(list.touching);
    load->pairs = static_cast<double>(list.pairs) / n;
    load->crossing = static_cast<double>(list.cross) / static_cast<double>(std::max<std::size_t>(1, list.pairs));
    load->pair_contacts = pair_contacts / n;
    load->wall_contacts = (static_cast<double>(sim.contact_count()) - pair_contacts) / n;
    const StageTimes& t = sim.stage_times();
    const double total = t.integrate + t.neighbours + t.pairs + t.walls + t.triangles + t.film + t.guards;
    load->integrate = t.integrate / total, load->neighbours = t.neighbours / total;
    load->pair_stage = t.pairs / total, load->wall_stage = t.walls / total;
  }
  return s;
}

// The scene with this broad phase and the energy tallies on or off.
Scene with_method(const Scene& scene, const std::string& method, bool energy) {
  Scene sc = scene;
  sc.broad_phase = method;
  sc.models.energy = energy;
  return sc;
}

// `repeats` timed runs of a scene: ns per particle-step, median and range, and the neighbour-list
// builds of the last run.
struct Timing {
  double median = 0, lo = 0, hi = 0;
  std::uint64_t builds = 0;
  Workload load;
};
// With `workload`, one more run of a quarter of the steps measures the workload and the stages' shares.
Timing time_repeats(const Scene& sc, long long steps, int threads, int repeats, bool workload = false) {
  Timing t;
  std::vector<double> ns;
  for (int r = 0; r < repeats; ++r)
    ns.push_back(1e9 * timed_run(sc, steps, threads, &t.builds) / (static_cast<double>(steps) * static_cast<double>(sc.particles.size())));
  if (workload) {
    std::uint64_t builds = 0;  // of that run: not reported
    timed_run(sc, std::max(100LL, steps / 4), threads, &builds, &t.load);
  }
  std::sort(ns.begin(), ns.end());
  t.median = ns[ns.size() / 2], t.lo = ns.front(), t.hi = ns.back();
  return t;
}

// The peers' bed of N particles (runs/N*.vib1.data, or its .gz: the case reads either); "" if absent.
std::string peers_bed(const std::string& peers, int N) {
  const std::string data = peers + "/runs/N" + std::to_string(N) + ".vib1.data";
  for (const std::string& path : {data, data + ".gz"})
    if (fs::exists(path)) return fs::absolute(path).string();  // the case would read a relative path from its own directory
  return "";
}

// Peak resident memory of this process so far (VmHWM) (unit: bytes).
// Median wall time of one neighbour-list build of the scene's balls by a broad phase (threads as
// set) (unit: s).
double time_broad_phase(const Scene& sc, const std::string& method, int repeats) {
  std::vector<Vec3> x;
  std::vector<double> r;
  for (const ParticleInit& p : sc.particles) x.push_back(p.x), r.push_back(p.radius);
  const std::unique_ptr<BroadPhase> bp = make_broad_phase(method);
  CandidatePairs pairs;
  std::vector<double> s;
  for (int k = 0; k < std::max(3, repeats); ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    bp->find(x, r, sc.skin, pairs);
    s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(s.begin(), s.end());
  return s[s.size() / 2];
}

double peak_memory() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmHWM:", 0) == 0) return 1024.0 * std::stod(line.substr(6));
  return NAN;
}

}  // namespace

double log_log_slope(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double a = std::log(x[i]), b = std::log(y[i]);
    sx += a, sy += b, sxx += a * a, sxy += a * b;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// Growth: the N = 1000 bed tiled k x k. Every size runs the same steps, so that neighbour-list
// rebuilds (driven by the motion, not by N) weigh alike. The repeats run in rounds, each round every
// size once in ascending order: a slow minute of a shared machine (its speed can drift by a third
// from minute to minute) then weighs on every size alike instead of on one size's repeats, which would
// tilt the fitted exponent. The peak memory is read in the first round, after each size's runs:
// sizes ascend and each run frees its simulation, so it is that size's.
// Points (N, y) of the growth benchmark per (method, threads).
using GrowthSeries = std::map<std::pair<std::string, int>, std::vector<std::pair<double, double>>>;

// The fitted exponents a of y ~ N^a of the growth benchmark: wall time per step, one neighbour
// build and the peak memory (memory: (N, bytes above the start)).
void print_growth_fits(const BenchTable& table, const GrowthSeries& fits, const GrowthSeries& builds,
                       const std::vector<std::pair<double, double>>& memory) {
  std::fprintf(table.prose(), "\nFitted exponents a of y ~ N^a (least squares over the sizes; flat cost per particle-step is a = 1):\n");
  auto slopes = [&](const GrowthSeries& series, const char* what) {
    for (const auto& [key, pts] : series) {
      std::vector<double> x, y;
      for (const auto& [n, t] : pts) x.push_back(n), y.push_back(t);
      std::fprintf(table.prose(), "  %s, %s, %d thread%s: a = %.3f\n", what, key.first.c_str(), key.second, key.second > 1 ? "s" : "",
                   log_log_slope(x, y));
    }
  };
  slopes(fits, "wall time per step");
  slopes(builds, "one neighbour build");
  std::vector<double> x, y;
  for (const auto& [n, m] : memory) x.push_back(n), y.push_back(m);
  std::fprintf(table.prose(), "  peak memory above the process's start: a = %.3f\n", log_log_slope(x, y));
}

int run_growth_bench(const BenchOptions& opt) {
  const std::string src = BAGDEM_SOURCE_DIR;
  const std::string peers = opt.peers_dir.empty() ? src + "/../shared/peers" : opt.peers_dir;
  const std::string data = peers_bed(peers, 1000);
  if (data.empty()) {
    std::fprintf(stderr, "error: %s/runs/N1000.vib1.data not found: the growth benchmark tiles the peers' settled bed\n",
                 peers.c_str());
    return kExitInputError;
  }
  const long long steps = std::max(100LL, static_cast<long long>(10000 * opt.step_scale));
  const BenchTable table(opt, {kParticles,
                               {"k", "tiles", "1", "%.0f"},
                               kMethod, kThreads, kNs, kNsMin, kNsMax, kBuilds,
                               {"one build (ms)", "build_time", "ms", "%.2f"},
                               {"peak memory (MB)", "peak_memory", "MiB", "%.1f"},
                               {"bytes/particle", "memory_per_particle", "B", "%.0f"}});
  std::fprintf(table.prose(), "Growth benchmark: the settled PD-box bed of 1000 balls tiled k x k (N = 1000 k^2), %lld steps each; energy "
               "tallies %s; median of %d runs, run in rounds over the sizes; wall clock\n",
               steps, opt.energy ? "on" : "off", opt.repeats);
  const Scene one = load_case(src + "/cases/pdbox-peers", pdbox_overrides(1000, data));
  const Vec3 L = one.cavity_hi - one.cavity_lo;
  // The box widened k times in x and y (its walls are planes through cavity_lo and cavity_hi).
  auto tiled = [&](int k) {
    std::vector<std::string> o = pdbox_overrides(1000, data);
    o[0] = Overrides().set(keys::cavity_max, Vec3(k * L.x(), k * L.y(), L.z())).sets().front();  // the first is cavity.max
    Scene scene = load_case(src + "/cases/pdbox-peers", o);
    const std::vector<ParticleInit> bed = scene.particles;
    scene.particles.clear();
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j)
        for (ParticleInit p : bed) {
          p.x += Vec3(i * L.x(), j * L.y(), 0);
          scene.particles.push_back(p);
        }
    return scene;
  };
  struct Point {
    int k = 0, threads = 0;
    std::string method;
    double N = 0, build_ms = 0, peak = 0;
    std::vector<double> ns;  // ns per particle-step, one per round
    std::uint64_t builds = 0;
  };
  std::vector<Point> points;
  std::vector<int> tiles = opt.tiles;
  std::sort(tiles.begin(), tiles.end());
  const double base_memory = peak_memory();
  for (int round = 0; round < opt.repeats; ++round) {
    std::size_t at = 0;
    for (int k : tiles) {
      // Built anew each round, not kept: a kept 1e5-ball scene would weigh on every size's peak memory.
      const Scene scene = tiled(k);
      const double N = static_cast<double>(scene.particles.size());
      for (const std::string& method : opt.methods) {
        const Scene sc = with_method(scene, method, opt.energy);
        for (int th : opt.threads) {
          if (round == 0) points.push_back({k, th, method, N, 0, 0, {}, 0});
          Point& p = points[at++];
          p.ns.push_back(1e9 * timed_run(sc, steps, th, &p.builds) / (static_cast<double>(steps) * N));
          if (round == 0) {
            p.peak = peak_memory();
            p.build_ms = 1e3 * time_broad_phase(sc, method, opt.repeats);
          }
        }
      }
    }
    std::fprintf(stderr, "growth: round %d of %d done\n", round + 1, opt.repeats);
  }
  table.header();
  GrowthSeries fits;    // (method, threads) -> (N, s/step)
  GrowthSeries builds;  // (method, threads) -> (N, ms/build)
  std::map<double, double> size_peak;  // N -> the peak memory of its runs
  for (const Point& p : points) size_peak[p.N] = std::max(size_peak[p.N], p.peak);
  for (Point& p : points) {
    std::sort(p.ns.begin(), p.ns.end());
    const double median = p.ns[p.ns.size() / 2];
    fits[{p.method, p.threads}].emplace_back(p.N, median * 1e-9 * p.N);
    builds[{p.method, p.threads}].emplace_back(p.N, p.build_ms);
    table.row({p.N, static_cast<double>(p.k), p.method, static_cast<double>(p.threads), median, p.ns.front(), p.ns.back(),
               static_cast<double>(p.builds), p.build_ms, size_peak[p.N] / 1048576, (size_peak[p.N] - base_memory) / p.N});
  }
  std::vector<std::pair<double, double>> memory;
  for (const auto& [n, peak] : size_peak) memory.emplace_back(n, peak - base_memory);
  if (tiles.size() >= 2) print_growth_fits(table, fits, builds, memory);
  return 0;
}

int run_bench(const BenchOptions& opt) {
  const std::string src = BAGDEM_SOURCE_DIR;
  const std::string peers = opt.peers_dir.empty() ? src + "/../shared/peers" : opt.peers_dir;
  const std::string case_dir = opt.case_dir.empty() ? src + "/cases/pdbox" : opt.case_dir;
  const BenchTable table(opt, {kParticles,
                               {"steps", "steps", "1", "%.0f"},
                               kMethod, kThreads, kNs, kNsMin, kNsMax, kBuilds,
                               {"pairs/particle", "pairs_per_particle", "1", "%.2f"},
                               {"pairs across threads %", "pairs_across_threads", "%", "%.1f"},
                               {"pair contacts/particle", "pair_contacts_per_particle", "1", "%.2f"},
                               {"wall contacts/particle", "wall_contacts_per_particle", "1", "%.2f"},
                               {"integration (both half-kicks) %", "integration_share", "%", "%.0f"},
                               {"neighbours %", "neighbours_share", "%", "%.0f"},
                               {"pairs %", "pairs_share", "%", "%.0f"},
                               {"walls %", "walls_share", "%", "%.0f"}});
  // A case of the user's (--case) is what is timed: the peers' settled beds stand in for cases/pdbox only.
  const bool own_case = !opt.case_dir.empty();
  if (own_case)
    std::fprintf(table.prose(), "Benchmark of %s (its particles.bed.count and cavity.max set per size); energy tallies %s; median of %d runs; wall clock\n",
                 case_dir.c_str(), opt.energy ? "on" : "off", opt.repeats);
  else
    std::fprintf(table.prose(), "PD-box benchmark (steel 4 mm, 1 mm at 30 Hz, dt 2e-7 s); energy tallies %s; median of %d runs; wall clock\n",
                 opt.energy ? "on" : "off", opt.repeats);
  table.header();
  for (int N : opt.sizes) {
    const std::string data = own_case ? std::string() : peers_bed(peers, N);
    if (data.empty() && !own_case)
      std::fprintf(stderr, "note: %s/runs/N%d.vib1.data not found; generating and settling the bed (0.05 s, not timed)\n",
                   peers.c_str(), N);
    // From the peers' state: cases/pdbox-peers; otherwise cases/pdbox generates and settles the bed.
    const Scene scene = load_case(data.empty() ? case_dir : src + "/cases/pdbox-peers", pdbox_overrides(N, data));
    const long long base = N <= 100 ? 1000000 : N <= 1000 ? 300000 : 40000;
    const long long steps = std::max(100LL, static_cast<long long>(base * opt.step_scale));
    for (const std::string& method : opt.methods) {
      const Scene sc = with_method(scene, method, opt.energy);
      for (int th : opt.threads) {
        const Timing t = time_repeats(sc, steps, th, opt.repeats, true);
        table.row({static_cast<double>(sc.particles.size()), static_cast<double>(steps), method, static_cast<double>(th), t.median,
                   t.lo, t.hi, static_cast<double>(t.builds), t.load.pairs, 100 * t.load.crossing, t.load.pair_contacts,
                   t.load.wall_contacts, 100 * t.load.integrate, 100 * t.load.neighbours, 100 * t.load.pair_stage,
                   100 * t.load.wall_stage});
      }
    }
  }
  std::fprintf(table.prose(), "\nPeers on this machine (../shared/peers/README.md, 1 rank): LIGGGHTS 115.7 / 95.7 / 126.9, "
              "LAMMPS 83.3 / 87.9 / 113.9 ns per particle-step at N = 100 / 1000 / 10000.\n");
  return 0;
}

// The bagged scene: cases/box-beanbag (100 balls of 4 mm in a film bag tied in a shaken box) at
// each film resolution. The bag settles first (not timed); then the stages are timed over the
// shaken part, and their shares are reported: the balls' own (integration, neighbours, pairs,
// walls), the ball-film contacts, and the film (membrane, strings, film-wall contacts).
int run_bag_bench(const BenchOptions& opt) {
  const std::string case_dir = opt.case_dir.empty() ? std::string(BAGDEM_SOURCE_DIR) + "/cases/box-beanbag" : opt.case_dir;
  const BenchTable table(opt, {{"film triangles", "film_triangles", "1", "%.0f"},
                               {"nodes", "film_nodes", "1", "%.0f"},
                               {"balls", "balls", "1", "%.0f"},
                               {"dt (s)", "dt", "s", "%.3g"},
                               {"steps", "steps", "1", "%.0f"},
                               {"threads", "threads", "1", "%.0f"},
                               {"us/step (median)", "time_per_step", "us", "%.2f"},
                               {"balls %", "balls_share", "%", "%.0f"},
                               {"ball-film contacts %", "ball_film_contacts_share", "%", "%.0f"},
                               {"film %", "film_share", "%", "%.0f"},
                               {"neighbour builds", "neighbour_builds", "1", "%.0f"}});
  std::fprintf(table.prose(), "Bagged-scene benchmark (%s); energy tallies %s; median of %d runs; wall clock\n", case_dir.c_str(),
               opt.energy ? "on" : "off", opt.repeats);
  table.header();
  std::map<int, std::vector<std::pair<double, double>>> fits;  // threads -> (film nodes, film us/step)
  for (int tri : opt.film_triangles) {
    const Scene scene = load_case(case_dir, Overrides().set(keys::triangles, tri).sets());
    refuse_several_dampers(scene, "bagdem bench --bag", "times one bag");
    const long long steps = std::max(100LL, static_cast<long long>(20000 * opt.step_scale));
    Scene sc = scene;
    sc.models.energy = opt.energy;
    for (int th : opt.threads) {
      omp_set_num_threads(th);
      std::vector<double> us;
      StageTimes last;
      std::uint64_t builds = 0;
      for (int r = 0; r < opt.repeats; ++r) {
        Simulation sim(sc);
        const auto settle_steps = static_cast<long long>(std::llround(sc.settle / sc.dt));
        sim.advance(static_cast<std::uint64_t>(settle_steps));
        const std::uint64_t b0 = sim.neighbour_builds();
        sim.set_profiling(true);
        const auto t0 = std::chrono::steady_clock::now();
        sim.advance(static_cast<std::uint64_t>(steps));
        us.push_back(1e6 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / static_cast<double>(steps));
        last = sim.stage_times();
        builds = sim.neighbour_builds() - b0;
      }
      std::vector<double> sorted = us;
      std::sort(sorted.begin(), sorted.end());
      const StageTimes& t = last;
      const double total = t.integrate + t.neighbours + t.pairs + t.walls + t.triangles + t.film + t.guards;
      table.row({static_cast<double>(sc.bag->rest.triangles.size()), static_cast<double>(sc.bag->rest.vertices.size()),
                 static_cast<double>(sc.bag->balls), sc.dt, static_cast<double>(steps), static_cast<double>(th),
                 sorted[sorted.size() / 2], 100 * (t.integrate + t.neighbours + t.pairs + t.walls + t.guards) / total,
                 100 * t.triangles / total, 100 * t.film / total, static_cast<double>(builds)});
      // The film's own cost per step (ball-film contacts and film stages), against its node count.
      fits[th].emplace_back(static_cast<double>(sc.bag->rest.vertices.size()),
                            sorted[sorted.size() / 2] * (t.triangles + t.film) / total);
    }
  }
  for (const auto& [th, pts] : fits) {
    if (pts.size() < 2) continue;
    std::vector<double> x, y;
    for (const auto& [n, us] : pts) x.push_back(n), y.push_back(us);
    std::fprintf(table.prose(), "%d thread(s): the film's cost per step (ball-film contacts + film) grows as nodes^a, a = %.3f\n", th,
                 log_log_slope(x, y));
  }
  std::fprintf(table.prose(), "\nShares are of the timed stages of the last run (integration of balls and film nodes and the neighbour\n"
              "lists are counted with the balls).\n");
  return 0;
}

}  // namespace bagdem
