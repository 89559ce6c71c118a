// The growth benchmark's fit (run/bench.hpp): the exponent of y ~ x^a by least squares in log-log;
// bagdem bench --format csv, and its reader in the peers' scripts (tools/peers/bench_csv.py);
// tools/peers/growth.py, the tiling and fit of tools/peers/growth; and tools/peers/compare.py, the
// jittered starts and the intervals of tools/peers/compare --starts K.
#include <gtest/gtest.h>
#include <zlib.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bagdem/run/bench.hpp"
#include "support.hpp"

TEST(Bench, LogLogSlopeRecoversAPowerLaw) {
  const std::vector<double> n = {1e3, 4e3, 1.6e4, 4.9e4, 1e5};
  std::vector<double> t, m;
  for (double x : n) {
    t.push_back(2.5e-7 * std::pow(x, 1.03));
    m.push_back(1800 * x);
  }
  EXPECT_NEAR(bagdem::log_log_slope(n, t), 1.03, 1e-12);
  EXPECT_NEAR(bagdem::log_log_slope(n, m), 1.0, 1e-12);
  // Noise that is not a power law tilts the fit: a constant overhead makes small N look dearer.
  std::vector<double> with_overhead;
  for (double x : n) with_overhead.push_back(1e-3 + 1e-7 * x);
  EXPECT_LT(bagdem::log_log_slope(n, with_overhead), 0.95);
}

// bagdem bench --format csv on tiny runs: a bed of `n` balls of 4 mm on a lattice 4.2 mm apart,
// `per_row` a row, in the peers' layout (PEERS/runs/N<n>.vib1.data, a LAMMPS data file), so that
// no bed is generated and settled, and 100 steps are timed.
namespace {
void write_lattice_bed(const std::filesystem::path& peers, int n, int per_row) {
  std::filesystem::create_directories(peers / "runs");
  std::ostringstream bed;
  bed.precision(17);
  bed << "lattice\n\n" << n << " atoms\n1 atom types\n\nAtoms\n\n";
  for (int i = 0; i < n; ++i)
    bed << i + 1 << " 1 0.004 7800 " << 0.0021 + 0.0042 * (i % per_row) << " " << 0.0021 + 0.0042 * (i / per_row % per_row) << " "
        << 0.0021 + 0.0042 * (i / (per_row * per_row)) << " 0 0 0\n";
  std::ofstream(peers / "runs" / ("N" + std::to_string(n) + ".vib1.data")) << bed.str();
}

// bagdem bench on a bed of 8 balls in DIR/peers (written here): 100 timed steps, one thread, one
// repeat, and `args` (--format, --methods).
bagdem::testing::CmdResult tiny_bench(const bagdem::testing::TempDir& dir, const std::vector<std::string>& args) {
  write_lattice_bed(dir.path / "peers", 8, 2);
  std::vector<std::string> all = {"bench", "--sizes", "8", "--threads", "1", "--repeats", "1", "--steps", "1e-9", "--peers", dir.str() + "/peers"};
  all.insert(all.end(), args.begin(), args.end());
  return bagdem::testing::run_bagdem(all, dir.path);
}

std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::vector<std::string> cells;
    std::istringstream f(line);
    std::string cell;
    while (std::getline(f, cell, ',')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

// Every cell of the rows a number, but those of the columns named in `text`.
void expect_numbers(const std::vector<std::vector<std::string>>& rows, const std::vector<std::string>& text = {}) {
  for (std::size_t i = 1; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), rows[0].size()) << "row " << i;
    for (std::size_t k = 0; k < rows[i].size(); ++k) {
      if (std::find(text.begin(), text.end(), rows[0][k]) != text.end()) continue;
      std::size_t used = 0;
      double v = NAN;
      EXPECT_NO_THROW(v = std::stod(rows[i][k], &used)) << rows[0][k] << " = '" << rows[i][k] << "'";
      EXPECT_EQ(used, rows[i][k].size()) << rows[0][k] << " = '" << rows[i][k] << "'";
      EXPECT_TRUE(std::isfinite(v)) << rows[0][k] << " = '" << rows[i][k] << "'";
    }
  }
}

double cell(const std::vector<std::vector<std::string>>& rows, std::size_t row, const std::string& column) {
  const auto at = std::find(rows[0].begin(), rows[0].end(), column);
  if (at == rows[0].end()) ADD_FAILURE() << "no column " << column;
  return at == rows[0].end() ? NAN : std::stod(rows[row][static_cast<std::size_t>(at - rows[0].begin())]);
}
}  // namespace

TEST(Bench, CsvFormatNamesEachColumnWithItsUnitAndHasARowPerConfiguration) {
  using namespace bagdem::testing;
  const TempDir dir;
  const CmdResult r = tiny_bench(dir, {"--format", "csv", "--methods", "hash", "kdtree"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = csv_rows(r.out);
  ASSERT_EQ(rows.size(), 3u) << r.out;  // the header, then hash and kdtree
  const std::vector<std::string> header = {
      "particles [1]", "steps [1]", "method [text]", "threads [1]", "ns_per_particle_step [ns]", "ns_per_particle_step_min [ns]",
      "ns_per_particle_step_max [ns]", "neighbour_builds [1]", "pairs_per_particle [1]", "pairs_across_threads [%]",
      "pair_contacts_per_particle [1]", "wall_contacts_per_particle [1]", "integration_share [%]", "neighbours_share [%]",
      "pairs_share [%]", "walls_share [%]"};
  EXPECT_EQ(rows[0], header);
  expect_numbers(rows, {"method [text]"});
  EXPECT_EQ(rows[1][2], "hash");
  EXPECT_EQ(rows[2][2], "kdtree");
  for (std::size_t i : {1u, 2u}) {
    EXPECT_EQ(cell(rows, i, "particles [1]"), 8);
    EXPECT_EQ(cell(rows, i, "steps [1]"), 100);  // 1e-9 of the default, at least 100
    EXPECT_EQ(cell(rows, i, "threads [1]"), 1);
    const double ns = cell(rows, i, "ns_per_particle_step [ns]");
    EXPECT_GT(ns, 0);
    // One repeat: its median, least and greatest are the one run.
    EXPECT_EQ(cell(rows, i, "ns_per_particle_step_min [ns]"), ns);
    EXPECT_EQ(cell(rows, i, "ns_per_particle_step_max [ns]"), ns);
    const double shares = cell(rows, i, "integration_share [%]") + cell(rows, i, "neighbours_share [%]") +
                          cell(rows, i, "pairs_share [%]") + cell(rows, i, "walls_share [%]");
    EXPECT_GT(shares, 0);
    EXPECT_LE(shares, 100 + 1e-9);
  }
  // stdout holds the CSV alone: the title goes to stderr.
  EXPECT_EQ(r.out.find('|'), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("PD-box benchmark"), std::string::npos) << r.err;

  // The default is the Markdown table, with the same figures.
  const CmdResult t = tiny_bench(dir, {"--methods", "hash"});
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_EQ(t.out.rfind("PD-box benchmark", 0), 0u) << t.out;
  EXPECT_NE(t.out.find("\n| N | steps | method | threads | ns/particle-step (median) | min-max | neighbour builds |"), std::string::npos) << t.out;
  // Its row: the counts as the CSV's (the times differ from run to run).
  char counts[96];
  std::snprintf(counts, sizeof counts, " | %.0f | %.2f | ", cell(rows, 1, "neighbour_builds [1]"), cell(rows, 1, "pairs_per_particle [1]"));
  const auto row = t.out.find("\n| 8 | 100 | hash | 1 | ");
  ASSERT_NE(row, std::string::npos) << t.out;
  EXPECT_NE(t.out.substr(row, t.out.find('\n', row + 1) - row).find(counts), std::string::npos) << counts << " not in\n" << t.out;
}

// A gzipped bed in a peers' directory whose name holds quotes, an escape and a command: read
// in-process (zlib), so nothing is run and nothing is cached outside the run. The bench used to build
// `gunzip -c '<dir>...'` for std::system, which ran the command in the name.
TEST(Bench, AGzippedBedIsReadInProcessWhateverTheDirectorysName) {
  using namespace bagdem::testing;
  const TempDir dir;
  const std::filesystem::path marker = std::filesystem::current_path() / "bagdem_bench_injected";
  std::filesystem::remove(marker);
  // A quote, a double quote and a TOML escape in the name: the case must read this very directory
  // (the name used to go into a TOML string unescaped: \u0041 read another directory).
  const std::filesystem::path peers = dir.path / "pe'e\"rs\\u0041; touch bagdem_bench_injected; '";
  write_lattice_bed(peers, 8, 2);
  const std::filesystem::path plain = peers / "runs" / "N8.vib1.data";
  const std::string text = slurp(plain);
  gzFile f = gzopen((plain.string() + ".gz").c_str(), "wb");
  ASSERT_NE(f, nullptr);
  ASSERT_EQ(gzwrite(f, text.data(), static_cast<unsigned>(text.size())), static_cast<int>(text.size()));
  ASSERT_EQ(gzclose(f), Z_OK);
  std::filesystem::remove(plain);
  const CmdResult r = run_bagdem({"bench", "--sizes", "8", "--threads", "1", "--repeats", "1", "--steps", "1e-9", "--methods", "hash",
                                  "--format", "csv", "--peers", peers.string()},
                                 dir.path);
  const bool injected = std::filesystem::exists(marker);
  std::filesystem::remove(marker);
  EXPECT_FALSE(injected) << "the directory's name ran as a command";
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = csv_rows(r.out);
  ASSERT_EQ(rows.size(), 2u) << r.out;
  EXPECT_EQ(cell(rows, 1, "particles [1]"), 8) << "the bed was not the peers' (8 balls)";
}

TEST(Bench, GrowthCsvHasARowPerSize) {
  using namespace bagdem::testing;
  const TempDir dir;
  write_lattice_bed(dir.path / "peers", 1000, 15);  // 15 x 15 a layer, as the peers' box of 63 mm
  const CmdResult r = run_bagdem({"bench", "--growth", "--format", "csv", "--tiles", "1", "2", "--threads", "1", "--methods", "hash",
                                  "--repeats", "1", "--steps", "1e-9", "--peers", dir.str() + "/peers"},
                                 dir.path);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = csv_rows(r.out);
  ASSERT_EQ(rows.size(), 3u) << r.out;
  const std::vector<std::string> header = {
      "particles [1]", "tiles [1]", "method [text]", "threads [1]", "ns_per_particle_step [ns]", "ns_per_particle_step_min [ns]",
      "ns_per_particle_step_max [ns]", "neighbour_builds [1]", "build_time [ms]", "peak_memory [MiB]", "memory_per_particle [B]"};
  EXPECT_EQ(rows[0], header);
  expect_numbers(rows, {"method [text]"});
  EXPECT_EQ(cell(rows, 1, "particles [1]"), 1000);
  EXPECT_EQ(cell(rows, 2, "particles [1]"), 4000);
  EXPECT_EQ(cell(rows, 2, "tiles [1]"), 2);
  // The fitted exponents are prose: on stderr with the title.
  EXPECT_NE(r.err.find("Fitted exponents"), std::string::npos) << r.err;
}

TEST(Bench, FormatOtherThanTableOrCsvIsBadInput) {
  using namespace bagdem::testing;
  const TempDir dir;
  const CmdResult r = run_bagdem({"bench", "--format", "json", "--sizes", "8"}, dir.path);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--format"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("json"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
  const CmdResult help = run_bagdem({"bench", "--help"}, dir.path);
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("--format"), std::string::npos) << help.out;
  EXPECT_NE(help.out.find("csv"), std::string::npos) << help.out;
}

// The peers' scripts read bagdem's figures by column name from the CSV (tools/peers/prologue.sh,
// bench_ns): bench_csv.py picks the ns per particle-step of the one row that matches.
TEST(BenchPeers, ReadsTheNsPerParticleStepOfBagdemBenchCsvByColumnName) {
  using namespace bagdem::testing;
  const TempDir dir;
  const CmdResult r = tiny_bench(dir, {"--format", "csv", "--methods", "hash", "kdtree"});
  ASSERT_EQ(r.code, 0) << r.err;
  dir.write("bench.csv", r.out);
  const auto rows = csv_rows(r.out);
  ASSERT_EQ(rows.size(), 3u) << r.out;
  const std::string tool = shell_quote(std::string(BAGDEM_SOURCE_DIR) + "/tools/peers/bench_csv.py");
  const auto pick = [&](const std::string& where, int* code) {
    const int st = std::system((tool + " ns_per_particle_step " + where + " < " + shell_quote(dir.str() + "/bench.csv") + " > " +
                                shell_quote(dir.str() + "/picked.txt") + " 2> " + shell_quote(dir.str() + "/said.txt"))
                                   .c_str());
    *code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return slurp(dir.path / "picked.txt");
  };
  int code = -1;
  EXPECT_EQ(std::stod(pick("particles=8 method=kdtree", &code)), cell(rows, 2, "ns_per_particle_step [ns]"));
  EXPECT_EQ(code, 0) << slurp(dir.path / "said.txt");
  EXPECT_EQ(std::stod(pick("particles=8.0 method=hash threads=1", &code)), cell(rows, 1, "ns_per_particle_step [ns]"));
  EXPECT_EQ(code, 0) << slurp(dir.path / "said.txt");
  // No row, two rows, or a column the table does not have: exit code 2 and a message, no figure.
  for (const std::string where : {"particles=100", "particles=8", "size=8"}) {
    EXPECT_EQ(pick(where, &code), "") << where;
    EXPECT_EQ(code, 2) << where;
    EXPECT_NE(slurp(dir.path / "said.txt").find("bench_csv.py: "), std::string::npos) << where;
  }
}

// tools/peers/growth.py, the helper of tools/peers/growth (growth side by side with LIGGGHTS and
// LAMMPS): its tiling of the peers' N = 1000 bed and its fit of each code's exponent, on a
// synthetic bed and synthetic timings.
TEST(GrowthPeers, TilesTheBedAndFitsEachCodesExponent) {
  using namespace bagdem::testing;
  const TempDir dir;
  std::filesystem::create_directories(dir.path / "peers/runs");
  std::filesystem::create_directories(dir.path / "peers/inputs");
  std::ostringstream bed;
  bed << "synthetic\n\n1000 atoms\n\nAtoms\n\n";
  for (int i = 1; i <= 1000; ++i) bed << i << " 1 0.004 7800 " << 0.001 * (i % 50) << " " << 0.002 + 1e-6 * i << " 0.002 0 0 0\n";
  bed << "\nVelocities\n\n";
  for (int i = 1; i <= 1000; ++i) bed << i << " 0.1 0 0 0 0 " << i << "\n";
  dir.write("peers/runs/N1000.vib1.data", bed.str());
  dir.write("peers/inputs/box.N1000.stl", "solid box\n vertex 0 0.063 0\n vertex 0.063 0 0.048\nendsolid\n");
  const std::string tool = shell_quote(std::string(BAGDEM_SOURCE_DIR) + "/tools/peers/growth.py");
  ASSERT_EQ(std::system((tool + " tile " + shell_quote(dir.str() + "/peers") + " " + shell_quote(dir.str() + "/out") + " 2").c_str()), 0);
  const std::string data = slurp(dir.path / "out/data.k2");
  EXPECT_NE(data.find("\n4000 atoms\n"), std::string::npos);
  EXPECT_NE(data.find("0.129 xlo xhi"), std::string::npos);  // 2 x 63 mm + 3 mm
  // Copies in (x, y) order 00, 01, 10, 11: ball 2001 is ball 1 shifted by L = 63 mm in x, and
  // keeps its velocities.
  std::istringstream lines(data);
  std::string line;
  std::vector<double> ball;
  while (std::getline(lines, line))
    if (line.rfind("2001 1 ", 0) == 0) {
      std::istringstream f(line);
      double v;
      while (f >> v) ball.push_back(v);
      break;
    }
  ASSERT_EQ(ball.size(), 10u);
  EXPECT_NEAR(ball[4], 0.001 + 0.063, 1e-15);
  EXPECT_NEAR(ball[5], 0.002 + 1e-6, 1e-15);
  EXPECT_NE(data.find("\n2001 0.1 0 0 0 0 1\n"), std::string::npos);
  const std::string stl = slurp(dir.path / "out/inputs/box.Nk2.stl");
  EXPECT_NE(stl.find("vertex 0.0 0.126 0\n"), std::string::npos);
  EXPECT_NE(stl.find("vertex 0.126 0.0 0.048\n"), std::string::npos);
  EXPECT_NE(slurp(dir.path / "out/inputs/geom.Nk2.in").find("variable Lbox equal 0.126"), std::string::npos);

  // Timings: bagdem N^1.05 and LIGGGHTS N^1.12 (wall time; ns per particle-step N^0.05 and
  // N^0.12), three rounds 0%, 10% and 20% slower at every size (drift cancels out of a round's fit;
  // the table shows the median, here the middle round, and the range).
  std::ostringstream results;
  for (int round = 0; round < 3; ++round)
    for (double n : {1e3, 4e3, 1.6e4, 4.9e4, 1e5}) {
      const double slow = 1.0 + 0.1 * round;
      results << "bagdem " << n << " " << slow * 25 * std::pow(n / 1e3, 0.05) << "\n";
      results << "liggghts " << n << " " << slow * 90 * std::pow(n / 1e3, 0.12) << "\n";
    }
  dir.write("results.txt", results.str());
  const TempDir capture;
  ASSERT_EQ(std::system((tool + " report " + shell_quote(dir.str() + "/results.txt") + " > " + shell_quote(capture.str() + "/out.txt")).c_str()), 0);
  const std::string report = slurp(capture.path / "out.txt");
  EXPECT_NE(report.find("bagdem: a = 1.050 (medians); round by round 1.050 / 1.050 / 1.050"), std::string::npos) << report;
  EXPECT_NE(report.find("liggghts: a = 1.120 (medians)"), std::string::npos) << report;
  EXPECT_NE(report.find("| 1000 | 27.5 (25.0-30.0) | 99.0 (90.0-108.0) | 3.60 |"), std::string::npos) << report;
}

// tools/peers/compare.py, the helper of tools/peers/compare --starts K (what bagdem and LIGGGHTS
// compute on PD-box, as an ensemble of jittered starts): the jittered bed of start k, and the
// ensemble's intervals on synthetic starts.
namespace {
struct Ball {
  std::vector<double> v;  // id vx vy vz wx wy wz
};
std::vector<Ball> velocities(const std::string& data) {
  std::vector<Ball> balls;
  const auto at = data.find("\nVelocities\n");
  if (at == std::string::npos) return balls;
  std::istringstream lines(data.substr(at + 12));
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream f(line);
    Ball b;
    double x;
    while (f >> x) b.v.push_back(x);
    if (!b.v.empty()) balls.push_back(b);
  }
  return balls;
}
}  // namespace

TEST(ComparePeers, JittersEveryVelocityBy1e6InADirectionDrawnFromTheSeed) {
  using namespace bagdem::testing;
  const TempDir dir;
  std::ostringstream bed;
  bed << "synthetic\n\n1000 atoms\n1 atom types\n\nAtoms\n\n";
  for (int i = 1; i <= 1000; ++i) bed << (1001 - i) << " 1 0.004 7800 " << 0.001 * (i % 50) << " 0.002 " << 1e-6 * i << " 0 0 0\n";
  bed << "\nVelocities\n\n";
  for (int i = 1; i <= 1000; ++i) bed << (1001 - i) << " " << 1e-3 * i << " -2e-5 0 " << 0.5 * i << " 0.25 -3\n";
  dir.write("bed.data", bed.str());
  const std::string tool = shell_quote(std::string(BAGDEM_SOURCE_DIR) + "/tools/peers/compare.py");
  const auto jitter = [&](int seed, const std::string& name) {
    EXPECT_EQ(std::system((tool + " jitter " + shell_quote(dir.str() + "/bed.data") + " " + shell_quote(dir.str() + "/" + name) + " " + std::to_string(seed)).c_str()), 0);
    return slurp(dir.path / name);
  };
  const std::string one = jitter(1, "s1.data"), again = jitter(1, "s1b.data"), two = jitter(2, "s2.data");
  EXPECT_EQ(one, again);  // the seed alone decides the jitter
  EXPECT_NE(one, two);
  const std::string src = bed.str();
  const auto split = src.find("\nVelocities\n");
  EXPECT_EQ(one.substr(0, split), src.substr(0, split));  // header and positions as they were
  const auto before = velocities(src);
  for (const std::string* data : {&one, &two}) {
    const auto after = velocities(*data);
    ASSERT_EQ(after.size(), 1000u);
    double mean[3] = {0, 0, 0};
    for (size_t i = 0; i < after.size(); ++i) {
      ASSERT_EQ(after[i].v.size(), 7u);
      EXPECT_EQ(after[i].v[0], before[i].v[0]);  // the ball's id, in the file's order
      double dv2 = 0;
      for (int c = 1; c <= 3; ++c) {
        const double d = after[i].v[c] - before[i].v[c];
        dv2 += d * d;
        mean[c - 1] += d / 1000;
      }
      EXPECT_NEAR(std::sqrt(dv2), 1e-6, 1e-12) << "ball " << before[i].v[0];
      for (int c = 4; c <= 6; ++c) EXPECT_EQ(after[i].v[c], before[i].v[c]);  // spins untouched
    }
    // Random directions: no drift of the bed (a mean of 1000 unit vectors is ~0.02 a component).
    for (double m : mean) EXPECT_LT(std::abs(m), 1e-7);
  }
  // Each ball its own direction, each seed its own draw.
  const auto a = velocities(one), b = velocities(two);
  EXPECT_GT(std::abs((a[0].v[1] - before[0].v[1]) - (a[1].v[1] - before[1].v[1])), 1e-9);
  EXPECT_GT(std::abs(a[0].v[1] - b[0].v[1]), 1e-9);
}

TEST(ComparePeers, EnsembleIsEachCodesMeanWithAStudentTIntervalAndThePairedDifference) {
  using namespace bagdem::testing;
  const TempDir dir;
  const std::string tool = shell_quote(std::string(BAGDEM_SOURCE_DIR) + "/tools/peers/compare.py");
  // Start k: offset o = k - 4.5 (sample sd over 8 starts sqrt(6)). LIGGGHTS C = 10 + o, bagdem
  // C = 13 + 2 o, so the paired difference 3 + o; M = 0.005 + 0.001 o and 0.006 - 0.001 o.
  std::string starts;
  for (int k = 1; k <= 8; ++k) {
    const double o = k - 4.5;
    const std::string s = "start" + std::to_string(k);
    std::filesystem::create_directories(dir.path / s / "bagdem");
    std::ostringstream lig, csv;
    lig.precision(17);
    csv.precision(17);
    lig << "{\"cycles\": 30, \"skip_cycles\": 5.0, \"total_mass\": 0.2613, \"M_eff\": " << 0.005 + 0.001 * o << ", \"C_eff\": " << 10 + o << "}";
    csv << "f [Hz],M_eff [kg],M_eff_se [kg],C_eff [N s/m],C_eff_se [N s/m]\n30," << 0.006 - 0.001 * o << ",1," << 13 + 2 * o << ",1\n";
    dir.write(s + "/lig.json", lig.str());
    dir.write(s + "/bagdem/reduced.csv", csv.str());
    dir.write(s + "/lig.seconds", "600\n");
    dir.write(s + "/bagdem.seconds", "180\n");
    ASSERT_EQ(std::system((tool + " record " + shell_quote(dir.str() + "/" + s)).c_str()), 0);
    starts += " " + shell_quote(dir.str() + "/" + s);
  }
  const TempDir capture;
  ASSERT_EQ(std::system((tool + " ensemble 1000" + starts + " > " + shell_quote(capture.str() + "/out.txt")).c_str()), 0);
  const std::string report = slurp(capture.path / "out.txt");
  // Half-width t(0.975, 7) sd / sqrt(8) = 2.364624 x sqrt(6) / sqrt(8) = 2.047824: with 1.96 it would
  // be 1.697, with the standard error for the sd 0.724, with the population sd (n) 1.916, and an
  // unpaired difference would be wider than the codes' own intervals.
  EXPECT_NE(report.find("t(0.975, 7) = 2.365"), std::string::npos) << report;
  EXPECT_NE(report.find("| C_eff (N s/m) | 10 +- 2.048 | 13 +- 4.096 | +3 +- 2.048 (+30.0% +- 20.5% of LIGGGHTS) |"), std::string::npos) << report;
  EXPECT_NE(report.find("| M_eff (kg) | 0.005 +- 0.002048 | 0.006 +- 0.002048 | +0.001 +- 0.004096 (+20.0% +- 81.9% of LIGGGHTS) |"), std::string::npos) << report;
  EXPECT_NE(report.find("| start3 | 0.0035 | 8.5 | 0.0075 | 10 | 600 | 180 |"), std::string::npos) << report;
  EXPECT_NE(report.find("LIGGGHTS 80.0 min, bagdem 24.0 min over the 8 starts (600 s and 180 s a start)"), std::string::npos) << report;

  // Two starts: t(0.975, 1) = 12.706 (n - 1 degrees of freedom, not n: t(0.975, 2) = 4.303).
  ASSERT_EQ(std::system((tool + " ensemble 1000 " + shell_quote(dir.str() + "/start1") + " " + shell_quote(dir.str() + "/start3") + " > " + shell_quote(capture.str() + "/two.txt")).c_str()), 0);
  const std::string two = slurp(capture.path / "two.txt");
  EXPECT_NE(two.find("| C_eff (N s/m) | 7.5 +- 12.71 | 8 +- 25.41 | +0.5 +- 12.71 "), std::string::npos) << two;
  // One start has no interval.
  EXPECT_NE(std::system((tool + " ensemble 1000 " + shell_quote(dir.str() + "/start1") + " 2>/dev/null >/dev/null").c_str()), 0);
}
