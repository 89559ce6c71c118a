// tools/plot through the command line: synthetic output tables (the columns bagdem's runs and
// studies write) in a temporary directory, the script run on them with std::system, and its PNGs
// checked: every expected file listed on stdout and present, a complete PNG (the 8-byte signature,
// an IHDR chunk first, an IEND chunk last), 1125 pixels wide (7.5 in at 150 dpi) and far larger
// than a blank figure of that size (5 kB; empty axes 14 kB: the threshold is 40 kB). Bad input
// must end with exit code 2 and a message naming the file, the column and the value, and write no
// figure.
//
// The synthetic sets are shaped like the pipe experiment (docs/reference-study.md, section 3): mode 1 at
// 85.56 Hz as a single degree of freedom, bare peak 1.088e-3 m/N (zeta = 0.5%), with a bag of 8%
// of the modal mass and C_b/(M_b w) = 0.33 a peak near 3.2e-4 m/N. Receptance of the linear
// system (3) of the study: H = 1 / (K - (M + M_b) w^2 + i w (C_p + C_b)); accelerance w^2 |H|.
// The figures themselves are looked at by hand (tools/plot's header says what each shows).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "support.hpp"

namespace fs = std::filesystem;
using bagdem::testing::CmdResult;
using bagdem::testing::shell_quote;
using bagdem::testing::slurp;
using bagdem::testing::TempDir;

namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;
constexpr std::uintmax_t kNonTrivialBytes = 40000;  // a blank 1125 x 720 figure: 5 kB, empty axes: 14 kB
constexpr unsigned kWidthPixels = 1125;             // 7.5 in x 150 dpi

// The pipe's mode 1 as a single degree of freedom at the response point.
struct PipeMode {
  double f_n = 85.56;                                      // bare natural frequency [Hz]
  double zeta = 0.005;                                     // bare damping ratio [1]
  double K = 1.0 / (2 * 0.005 * 1.088e-3);                 // stiffness [N/m]: bare peak 1/(2 zeta K)
  double M = K / ((kTwoPi * 85.56) * (kTwoPi * 85.56));    // modal mass [kg]
  // Receptance [m/N] with a bag of mass ratio mu and C_b/(M_b w) = cb (mu = 0: the bare mode).
  std::complex<double> receptance(double f, double mu, double cb) const {
    const double w = kTwoPi * f;
    const double C = 2 * zeta * std::sqrt(K * M) + cb * mu * M * w;
    return 1.0 / std::complex<double>(K - M * (1 + mu) * w * w, w * C);
  }
};

// A CSV table: the header line, then `row(r)` for r = 0 .. rows - 1.
std::string table(const std::string& header, int rows, const std::function<std::string(int)>& row) {
  std::ostringstream s;
  s << header << "\n";
  for (int r = 0; r < rows; ++r) s << row(r) << "\n";
  return s.str();
}

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

// The sweep frequencies of the pipe case: 7 planned points over 77-94 Hz, then 2 refinement points
// appended out of order, as run/stepped_sine.cpp writes them.
std::vector<double> sweep_frequencies() {
  std::vector<double> f;
  for (int k = 0; k < 7; ++k) f.push_back(77.0 + 17.0 * k / 6);
  f.push_back(83.4);
  f.push_back(82.6);
  return f;
}

// One run's tables (sweep.csv, bare_curve.csv, peaks.csv, reduced.csv, compare.csv) in `dir`.
void write_run_tables(const fs::path& dir) {
  const PipeMode p;
  const double mu = 0.08, cb = 0.33;
  const std::vector<double> f = sweep_frequencies();
  const int n = static_cast<int>(f.size());
  // Unknown columns (requested_frequency, wall_time) must be ignored.
  std::ofstream(dir / "sweep.csv") << table(
      "requested_frequency [Hz],frequency [Hz],receptance_re [m/N],receptance_im [m/N],bare_receptance_re [m/N],"
      "bare_receptance_im [m/N],accelerance_abs [m/s^2/N],bare_accelerance_abs [m/s^2/N],steady [1],spread [1],wall_time [s]",
      n, [&](int r) {
        const auto h = p.receptance(f[r], mu, cb), hb = p.receptance(f[r], 0, 0);
        const double w2 = (kTwoPi * f[r]) * (kTwoPi * f[r]);
        return num(f[r]) + "," + num(f[r]) + "," + num(h.real()) + "," + num(h.imag()) + "," + num(hb.real()) + "," +
               num(hb.imag()) + "," + num(w2 * std::abs(h)) + "," + num(w2 * std::abs(hb)) + "," + (r == 4 ? "0" : "1") +
               "," + num(0.02 + 0.005 * r) + ",12.5";
      });
  std::ofstream(dir / "bare_curve.csv") << table(
      "frequency [Hz],bare_receptance_abs [m/N],bare_accelerance_abs [m/s^2/N]", 400, [&](int r) {
        const double fr = 77.0 + 17.0 * r / 399;
        const double h = std::abs(p.receptance(fr, 0, 0));
        return num(fr) + "," + num(h) + "," + num((kTwoPi * fr) * (kTwoPi * fr) * h);
      });
  // The damped peak by a fine scan (the figure only draws it).
  double f_peak = 77, h_peak = 0;
  for (int k = 0; k <= 17000; ++k) {
    const double fr = 77.0 + 0.001 * k, h = std::abs(p.receptance(fr, mu, cb));
    if (h > h_peak) f_peak = fr, h_peak = h;
  }
  const double bare_peak = std::abs(p.receptance(p.f_n, 0, 0));
  const double db = 20 * std::log10(bare_peak / h_peak);
  std::ofstream(dir / "peaks.csv") << table(
      "mode [1],bare_frequency [Hz],bare_peak [m/N],frequency [Hz],peak [m/N],reduction_dB [dB],reduction_percent [%]", 1,
      [&](int) {
        return "1," + num(p.f_n) + "," + num(bare_peak) + "," + num(f_peak) + "," + num(h_peak) + "," + num(db) + "," +
               num(100 * (1 - std::pow(10, -db / 20)));
      });
  std::ofstream(dir / "reduced.csv") << table(
      "frequency [Hz],cavity_amplitude [m],gamma [1],clearance_ratio [1],bag_mass [kg],mass_ratio [1],M_eff [kg],M_eff_se [kg],"
      "M_eff_ratio [1],Cb_over_Mbw [1],Cb_over_Mbw_se [1],e_impact [1],e_impact_sd [1],e_eq19a [1],e_drop [1],impact_phase [rad],"
      "e_method [text]",
      n, [&](int r) {
        const double X = 0.2 * std::abs(p.receptance(f[r], mu, cb)), w = kTwoPi * f[r];
        const double gamma = X * w * w / 9.81, bag = mu * p.M;
        return num(f[r]) + "," + num(X) + "," + num(gamma) + "," + num(0.001 / X) + "," + num(bag) + "," + num(mu) + "," +
               num(0.62 * bag) + "," + num(0.02 * bag) + ",0.62," + num(cb * (1 + 0.05 * r)) + ",0.02," +
               num(0.10 + 0.01 * r) + ",0.04," + num(0.12 + 0.008 * r) + ",0.037,1.1,impact";
      });
  std::ofstream(dir / "compare.csv") << table(
      "frequency [Hz],dem_response [m],model_response [m],model_error [1],eq20_response [m],eq20_error [1],bare_response [m]", 7,
      [&](int r) {
        const double fr = f[r], model = 0.2 * std::abs(p.receptance(fr, mu, cb)), dem = model * (1 + 0.03 * (r % 3 - 1));
        const double eq20 = 1.15 * model;
        return num(fr) + "," + num(dem) + "," + num(model) + "," + num((model - dem) / dem) + "," + num(eq20) + "," +
               num((eq20 - dem) / dem) + "," + num(0.2 * std::abs(p.receptance(fr, 0, 0)));
      });
}

// A study's merged tables: `points` points, each with its varied keys' strings and SI values
// (`keys_header` and `point_keys(point)`), one peaks row per mode (1 and 3) and one reduced and
// sweep row per sweep frequency; point `failed` (if >= 0) failed.
void write_study_tables(const fs::path& dir, const std::string& keys_header, int points, int seeds,
                        const std::function<std::string(int)>& point_keys, const std::function<double(int)>& cb_of,
                        int failed) {
  const PipeMode p;
  const std::vector<double> f = sweep_frequencies();
  const int nf = static_cast<int>(f.size());
  const std::string lead = "point,status,seed," + keys_header + ",";
  auto lead_of = [&](int run) {
    const int point = run / seeds;
    return std::to_string(run) + "," + (point == failed ? "failed" : "done") + "," + std::to_string(run % seeds + 1) + "," +
           point_keys(point) + ",";
  };
  auto peak_db = [&](int run, int mode) {
    const double cb = cb_of(run / seeds) * (1 + 0.03 * (run % seeds));
    double h = 0;
    for (int k = 0; k <= 2000; ++k) h = std::max(h, std::abs(p.receptance(77.0 + 0.0085 * k, 0.08, cb)));
    return 20 * std::log10(std::abs(p.receptance(p.f_n, 0, 0)) / h) * (mode == 1 ? 1.0 : 0.6);
  };
  const int runs = points * seeds;
  std::ofstream(dir / "peaks.csv") << table(
      lead + "mode [1],bare_frequency [Hz],bare_peak [m/N],frequency [Hz],peak [m/N],reduction_dB [dB],reduction_percent [%]",
      2 * runs, [&](int r) {
        const int run = r / 2, mode = r % 2 ? 3 : 1;
        if (run / seeds == failed) return lead_of(run) + std::to_string(mode) + ",,,,,,";
        const double db = peak_db(run, mode);
        return lead_of(run) + std::to_string(mode) + "," + num(mode == 1 ? p.f_n : 462.4) + ",1.088e-3," +
               num(mode == 1 ? 82.5 : 460.1) + ",3e-4," + num(db) + "," + num(100 * (1 - std::pow(10, -db / 20)));
      });
  std::ofstream(dir / "reduced.csv") << table(
      lead + "frequency [Hz],gamma [1],Cb_over_Mbw [1],Cb_over_Mbw_se [1],M_eff_ratio [1],e_impact [1]", runs * nf,
      [&](int r) {
        const int run = r / nf, k = r % nf;
        const double cb = cb_of(run / seeds);
        return lead_of(run) + num(f[k]) + "," + num(0.2 * std::abs(p.receptance(f[k], 0.08, cb)) * std::pow(kTwoPi * f[k], 2) / 9.81) +
               "," + num(cb * (1 + 0.02 * k)) + ",0.02,0.6," + num(0.1 + 0.01 * k);
      });
  std::ofstream(dir / "sweep.csv") << table(
      lead + "frequency [Hz],accelerance_abs [m/s^2/N],bare_accelerance_abs [m/s^2/N],steady [1],spread [1]", runs * nf,
      [&](int r) {
        const int run = r / nf, k = r % nf;
        const double w2 = std::pow(kTwoPi * f[k], 2);
        return lead_of(run) + num(f[k]) + "," + num(w2 * std::abs(p.receptance(f[k], 0.08, cb_of(run / seeds)))) + "," +
               num(w2 * std::abs(p.receptance(f[k], 0, 0))) + ",1,0.03";
      });
}

// Runs tools/plot with `args` (each quoted), its stdout and stderr captured in `capture_dir`.
CmdResult run_plot(const std::vector<std::string>& args, const fs::path& capture_dir, double* seconds = nullptr) {
  const fs::path out = capture_dir / "plot_stdout.txt", err = capture_dir / "plot_stderr.txt";
  std::string cmd = shell_quote(std::string(BAGDEM_SOURCE_DIR) + "/tools/plot");
  // Appended piece by piece: `" >" + string` trips GCC 12's false -Wrestrict (GCC bug 105329).
  for (const auto& a : args) cmd.append(" ").append(shell_quote(a));
  cmd.append(" >").append(shell_quote(out.string())).append(" 2>").append(shell_quote(err.string())).append(" </dev/null");
  const auto t0 = std::chrono::steady_clock::now();
  const int status = std::system(cmd.c_str());
  if (seconds) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CmdResult r;
  r.code = (status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream s(text);
  for (std::string line; std::getline(s, line);)
    if (!line.empty()) out.push_back(line);
  return out;
}

struct PngFacts {
  bool signature = false, ihdr_first = false, iend_last = false;
  unsigned width = 0, height = 0;
  std::uintmax_t bytes = 0;
};

unsigned big_endian(const std::string& b, std::size_t at) {
  return (static_cast<unsigned>(static_cast<unsigned char>(b[at])) << 24) |
         (static_cast<unsigned>(static_cast<unsigned char>(b[at + 1])) << 16) |
         (static_cast<unsigned>(static_cast<unsigned char>(b[at + 2])) << 8) |
         static_cast<unsigned>(static_cast<unsigned char>(b[at + 3]));
}

// The facts a valid, complete PNG shows without decoding it (PNG specification, sections 5.2-5.6).
PngFacts png_facts(const fs::path& path) {
  PngFacts p;
  const std::string b = slurp(path);
  p.bytes = b.size();
  static const std::string kSignature("\x89PNG\r\n\x1a\n", 8);
  static const std::string kIend("\0\0\0\0IEND\xae\x42\x60\x82", 12);  // length 0, type, CRC
  if (b.size() < 8 + 25 + 12) return p;
  p.signature = b.compare(0, 8, kSignature) == 0;
  p.ihdr_first = big_endian(b, 8) == 13 && b.compare(12, 4, "IHDR") == 0;
  p.width = big_endian(b, 16);
  p.height = big_endian(b, 20);
  p.iend_last = b.compare(b.size() - 12, 12, kIend) == 0;
  return p;
}

// Checks every figure `names` was written to `out_dir`, listed on stdout in that order, and valid;
// prints their sizes. `heights`: the expected height in pixels of each (0: not checked).
void expect_figures(const CmdResult& r, const fs::path& out_dir, const std::vector<std::string>& names,
                    const std::vector<unsigned>& heights) {
  ASSERT_EQ(r.code, 0) << "stdout:\n" << r.out << "stderr:\n" << r.err;
  const std::vector<std::string> listed = lines_of(r.out);
  ASSERT_EQ(listed.size(), names.size()) << r.out;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const fs::path path = out_dir / names[k];
    EXPECT_EQ(fs::path(listed[k]), path);
    ASSERT_TRUE(fs::exists(path)) << path;
    const PngFacts p = png_facts(path);
    std::printf("  %-34s %4u x %4u px, %7.1f kB\n", names[k].c_str(), p.width, p.height, p.bytes / 1000.0);
    EXPECT_TRUE(p.signature) << path;
    EXPECT_TRUE(p.ihdr_first) << path;
    EXPECT_TRUE(p.iend_last) << path << ": truncated";
    EXPECT_EQ(p.width, kWidthPixels) << path;
    if (heights[k]) {
      EXPECT_EQ(p.height, heights[k]) << path;
    }
    EXPECT_GT(p.bytes, kNonTrivialBytes) << path << ": no bigger than a blank figure";
  }
}

std::string key_values(const std::string& diameter, double metres, const std::string& material) {
  return diameter + "," + material + "," + num(metres) + ",nan";
}

}  // namespace

TEST(Plot, RunDirectoryGivesTheResponseReducedAndCompareFigures) {
  TempDir dir;
  write_run_tables(dir.path);
  double seconds = 0;
  const CmdResult r = run_plot({dir.str()}, dir.path, &seconds);
  std::printf("  tools/plot on a run directory: exit %d in %.2f s\n", r.code, seconds);
  // Heights: 4.8, 8.4 and 6.6 in at 150 dpi.
  expect_figures(r, dir.path, {"response.png", "reduced.png", "compare.png"}, {720, 1260, 990});
  EXPECT_EQ(r.err, "");
}

TEST(Plot, StudyDirectoryGivesAFigurePerVariedKey) {
  // A grid of ball diameter (a quantity: numeric axis) and film material (not a quantity:
  // categorical), 4 x 2 points, one failed; a coupled sweep per point (reduced.csv has a row per
  // frequency: C_b/(M_b w) is taken at each mode's damped peak).
  TempDir dir;
  const std::vector<std::pair<std::string, double>> diameters = {{"4 mm", 0.004}, {"8 mm", 0.008}, {"10 mm", 0.010}, {"20 mm", 0.020}};
  const std::vector<std::string> materials = {"ldpe", "pvc"};
  write_study_tables(dir.path, "bag.balls.diameter,bag.film.material,bag.balls.diameter [m],bag.film.material [1]", 8, 1,
                     [&](int p) { return key_values(diameters[p / 2].first, diameters[p / 2].second, materials[p % 2]); },
                     [&](int p) { return 0.5 * std::pow(0.004 / diameters[p / 2].second, 0.3) * (p % 2 ? 0.8 : 1.0); }, 5);
  double seconds = 0;
  const CmdResult r = run_plot({dir.str()}, dir.path, &seconds);
  std::printf("  tools/plot on a study directory (grid 4 x 2, one point failed): exit %d in %.2f s\n", r.code, seconds);
  expect_figures(r, dir.path, {"response.png", "reduced.png", "study_bag.balls.diameter.png", "study_bag.film.material.png"},
                 {0, 0, 0, 0});
  EXPECT_EQ(r.err, "");
}

TEST(Plot, EnsembleStudyWritesWhereOutSays) {
  // Two keys varied together (zip), two seeds: peaks_ensemble.csv holds the means, sds and
  // standard errors over the seeds. --out sends the figures to a new directory, none to DIR.
  TempDir dir;
  const fs::path study = dir.path / "study", figures = dir.path / "figures" / "png";
  fs::create_directories(study);
  const std::vector<std::pair<std::string, double>> diameters = {{"4 mm", 0.004}, {"8 mm", 0.008}, {"20 mm", 0.020}};
  const std::vector<std::string> counts = {"102", "13", "1"};
  auto keys = [&](int p) { return diameters[p].first + "," + counts[p] + "," + num(diameters[p].second) + "," + counts[p]; };
  write_study_tables(study, "bag.balls.diameter,bag.balls.count,bag.balls.diameter [m],bag.balls.count [1]", 3, 2, keys,
                     [&](int p) { return 0.5 * std::pow(0.004 / diameters[p].second, 0.3); }, -1);
  std::ofstream(study / "peaks_ensemble.csv") << table(
      "bag.balls.diameter,bag.balls.count,bag.balls.diameter [m],bag.balls.count [1],mode_mean [1],mode_sd [1],mode_se [1],"
      "frequency_mean [Hz],frequency_sd [Hz],frequency_se [Hz],reduction_dB_mean [dB],reduction_dB_sd [dB],reduction_dB_se [dB]",
      6, [&](int r) {
        const int p = r / 2, mode = r % 2 ? 3 : 1;
        const double db = (mode == 1 ? 12.0 : 7.0) - 1.5 * p;
        return keys(p) + "," + std::to_string(mode) + ",0,0," + num(mode == 1 ? 82.5 : 460.1) + ",0,0," + num(db) + ",0.8,0.57";
      });
  double seconds = 0;
  const CmdResult r = run_plot({study.string(), "--out", figures.string()}, dir.path, &seconds);
  std::printf("  tools/plot on an ensemble study (zip of 3, 2 seeds) with --out: exit %d in %.2f s\n", r.code, seconds);
  expect_figures(r, figures, {"response.png", "reduced.png", "study_bag.balls.diameter.png", "study_bag.balls.count.png"},
                 {0, 0, 0, 0});
  int pngs_in_study = 0;
  for (const auto& e : fs::directory_iterator(study)) pngs_in_study += e.path().extension() == ".png";
  EXPECT_EQ(pngs_in_study, 0);
}

// A figure is written only over a figure of tools/plot: a file of the user's under a figure's name
// is refused (exit 2) before any figure is written, and stays; plotting again replaces its own.
TEST(Plot, AFileOfTheUsersUnderAFiguresNameStays) {
  TempDir dir;
  const fs::path run = dir.path / "run", figures = dir.path / "figures";
  fs::create_directories(run);
  write_run_tables(run);
  fs::create_directories(figures);
  std::ofstream(figures / "response.png") << "my own figure\n";
  const CmdResult r = run_plot({run.string(), "--out", figures.string()}, dir.path);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("response.png: holds a file that is not a figure of tools/plot"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(figures / "response.png"), "my own figure\n");
  EXPECT_FALSE(fs::exists(figures / "reduced.png")) << "nothing is written";
  fs::remove(figures / "response.png");
  ASSERT_EQ(run_plot({run.string(), "--out", figures.string()}, dir.path).code, 0);
  const CmdResult again = run_plot({run.string(), "--out", figures.string()}, dir.path);
  EXPECT_EQ(again.code, 0) << again.err;
  for (const auto& e : fs::directory_iterator(figures)) EXPECT_EQ(e.path().string().find(".part"), std::string::npos) << e.path();
}

TEST(Plot, BadInputExitsWithTwoAndSaysWhy) {
  struct Case {
    std::string what;
    std::string file, text;              // a table written into DIR (none if file is empty)
    std::vector<std::string> extra;      // arguments after DIR
    std::vector<std::string> message;    // parts the message must hold
    bool no_dir = false;                 // DIR does not exist
  };
  const std::string sweep_header = "frequency [Hz],accelerance_abs [m/s^2/N]\n";
  const std::vector<Case> cases = {
      {"DIR missing", "", "", {}, {"no-such-dir", "not a directory"}, true},
      {"no table in DIR", "notes.txt", "hello\n", {}, {"nothing to plot", "sweep.csv"}},
      {"a required column missing", "sweep.csv", "freq [Hz],accelerance_abs [m/s^2/N]\n80,1\n", {},
       {"sweep.csv", "'frequency'", "columns found: freq, accelerance_abs"}},
      {"a word in a numeric column", "sweep.csv", sweep_header + "80,1\n81,fast\n", {},
       {"sweep.csv", "line 3", "accelerance_abs [m/s^2/N]", "'fast'", "numbers"}},
      {"a short row", "sweep.csv", sweep_header + "80,1\n81\n", {}, {"sweep.csv", "line 3", "1 cells", "2 columns"}},
      {"a header and no rows", "sweep.csv", sweep_header, {}, {"no rows"}},
      {"--x not a column", "reduced.csv", "gamma [1],Cb_over_Mbw [1],M_eff_ratio [1]\n1,0.5,0.6\n", {"--x", "speed"},
       {"reduced.csv", "--x 'speed'", "allowed: gamma [1], Cb_over_Mbw [1], M_eff_ratio [1]"}},
      {"--x without reduced.csv", "sweep.csv", sweep_header + "80,1\n", {"--x", "gamma"}, {"--x 'gamma'", "reduced.csv"}},
      {"an unknown option", "sweep.csv", sweep_header + "80,1\n", {"--colour", "red"}, {"unrecognized arguments: --colour"}},
  };
  for (const Case& c : cases) {
    TempDir dir;
    const fs::path data = c.no_dir ? dir.path / "no-such-dir" : dir.path / "data";
    if (!c.no_dir) fs::create_directories(data);
    if (!c.file.empty()) std::ofstream(data / c.file) << c.text;
    std::vector<std::string> args = {data.string()};
    args.insert(args.end(), c.extra.begin(), c.extra.end());
    const CmdResult r = run_plot(args, dir.path);
    const std::vector<std::string> said = lines_of(r.err);  // notes or argparse's usage, then the error
    std::printf("  %-28s exit %d: %s\n", c.what.c_str(), r.code, said.empty() ? "" : said.back().c_str());
    EXPECT_EQ(r.code, 2) << c.what << "\n" << r.err;
    for (const std::string& part : c.message) EXPECT_NE(r.err.find(part), std::string::npos) << c.what << ": '" << part << "' not in\n" << r.err;
    EXPECT_EQ(r.out, "") << c.what;
    if (!c.no_dir) {
      for (const auto& e : fs::directory_iterator(data)) EXPECT_NE(e.path().extension(), ".png") << c.what << ": " << e.path();
    }
  }
}

// The response figure's label of a peak carries its interval, and says when the peak is at the
// edge of the swept band (its reduction is then only a bound): peak_text of tools/bagdem_plot/response.py
// on a peaks.csv as a sweep writes it.
TEST(Plot, PeakLabelCarriesTheIntervalAndTheBandEdge) {
  TempDir d;
  std::ofstream(d.path / "peaks.csv")
      << "mode [1],bare_frequency [Hz],bare_peak [m/N],frequency [Hz],peak [m/N],simulated_frequency [Hz],simulated_peak [m/N],"
         "peak_ci95 [m/N],reduction_dB [dB],reduction_dB_ci95 [dB],reduction_percent [%],at_band_edge [1],unsteady_points [1]\n"
         "1,85.5,0.001,84,0.0003,84,0.0003,1e-5,10.46,0.29,70,1,0\n"
         "3,462,0.0001,460,0.00005,460,0.00005,1e-6,6.02,0.17,50,0,0\n";
  const std::string script =
      "import sys\n"
      "sys.path.insert(0, sys.argv[1])\n"
      "from bagdem_plot.response import peak_text\n"
      "from bagdem_plot.tables import read_table\n"
      "t = read_table(sys.argv[2], 'peaks.csv')\n"
      "print(peak_text(t, 0))\n"
      "print(peak_text(t, 1))\n";
  std::ofstream(d.path / "labels.py") << script;
  const std::string cmd = "MPLBACKEND=Agg /usr/bin/python3 " + shell_quote((d.path / "labels.py").string()) + " " +
                          shell_quote(std::string(BAGDEM_SOURCE_DIR) + "/tools") + " " + shell_quote(d.str()) + " > " +
                          shell_quote((d.path / "labels.txt").string()) + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(d.path / "labels.txt");
  const std::vector<std::string> labels = lines_of(slurp(d.path / "labels.txt"));
  ASSERT_EQ(labels.size(), 2u) << slurp(d.path / "labels.txt");
  EXPECT_EQ(labels[0], "mode 1: -10.5 +- 0.3 dB (70%); AT THE BAND'S EDGE");
  EXPECT_EQ(labels[1], "mode 3: -6.0 +- 0.2 dB (50%)");
}

TEST(Plot, CalibrationGivesTheReductionAgainstTheKey) {
  // bagdem calibrate's tables: two targets (modes 1 and 3) at seven forces (mN), the reduction
  // falling as 8 ln(0.2 N / F) dB, one least-squares solution.
  TempDir dir;
  const std::vector<double> force = {50, 70.7, 100, 141, 200, 120, 110};  // mN
  std::ostringstream csv;
  csv << "round [1],excitation.amplitude,excitation.amplitude [kg m/s^2],mode [1],target_db [dB],reduction_db_mean [dB],"
         "reduction_db_ci95 [dB],seeds [1],residual_db [dB],matched [1]\n";
  for (std::size_t i = 0; i < force.size(); ++i)
    for (int mode : {1, 3}) {
      const double target = mode == 1 ? 14.9 : 14.5, mean = 8 * std::log(200 / force[i]) + (mode == 3 ? 1.0 : 0.0);
      csv << (i < 5 ? 0 : i - 4) << ",\"" << force[i] << " mN\"," << force[i] * 1e-3 << ',' << mode << ',' << target << ',' << mean
          << ",0.6,3," << mean - target << ',' << (std::abs(mean - target) <= 0.6 ? 1 : 0) << '\n';
    }
  std::ofstream(dir.path / "calibrate.csv") << csv.str();
  std::ofstream(dir.path / "calibration.json")
      << "{\"key\": \"excitation.amplitude\", \"unit\": \"mN\", \"to_si\": 0.001, \"solutions\": [{\"value\": 110, \"half_width\": 9.5, "
         "\"matched\": false}]}\n";
  const CmdResult r = run_plot({dir.str()}, dir.path);
  expect_figures(r, dir.path, {"calibrate.png"}, {720});
  EXPECT_EQ(r.err, "");
}

TEST(Plot, DesignGivesTheReductionAgainstTheAddedMass) {
  // bagdem design's design.csv: 3 ranked pairs (2 on the front, 1 checked by DEM) and one refused.
  TempDir dir;
  std::ofstream(dir.path / "design.csv")
      << "rank [1],status,bag.balls.diameter,position_xL [1],added_mass [kg],mass_ratio [1],objective_dB [dB],objective_dB_lo [dB],"
         "objective_dB_hi [dB],pareto [1],dem_seeds [1],dem_objective_dB [dB],dem_objective_dB_ci95 [dB],map\n"
         "1,ranked,4 mm,0.5,0.03,0.09,15.2,13.1,17.0,1,3,14.8,1.2,map-a\n"
         "2,ranked,4 mm,0.45,0.01,0.03,9.5,8.0,10.9,1,0,,,map-b\n"
         "3,ranked,6 mm,0.5,0.03,0.09,8.1,7.0,9.0,0,0,,,map-c\n"
         ",over budget,8 mm,0.5,0.04,0.12,,,,0,0,,,map-d\n";
  const CmdResult r = run_plot({dir.str()}, dir.path);
  expect_figures(r, dir.path, {"design.png"}, {0});
  EXPECT_EQ(r.err, "");
}

TEST(Plot, MapAndPredictionGiveTheirFigures) {
  // bagdem characterize's map.csv (3 Gamma x 2 frequencies) and bagdem predict's predict.csv (a
  // resonance with two branches near its peak).
  TempDir dir;
  std::ostringstream map;
  map << "gamma [1],frequency [Hz],amplitude [m],starts [1],steady_starts [1]";
  for (const char* f : {"M_eff_ratio", "Cb_over_Mbw", "loss_factor", "e"}) map << ',' << f << " [1]," << f << "_ci95 [1]";
  map << ",e_method [text]\n";
  for (double G : {0.5, 2.0, 8.0})
    for (double f : {80.0, 90.0})
      map << G << ',' << f << ",1e-5,3,3," << 1 / (1 + G) << ",0.02," << 0.3 * G / (1 + G) << ",0.03," << 0.5 * G << ",0.05,"
          << 0.6 - 0.02 * G << ",0.04,impact\n";
  std::ofstream(dir.path / "map.csv") << map.str();
  std::ostringstream pred;
  pred << "force [N],mode [1],frequency [Hz],branch [1],cavity_amplitude [m],response [m],bare_response [m]\n";
  for (double f = 80; f <= 90; f += 0.25) {
    const double bare = 1e-3 / std::hypot(1 - std::pow(f / 85, 2), 0.01), damped = 1e-3 / std::hypot(1 - std::pow(f / 85, 2), 0.1);
    pred << "0.2,1," << f << ",0," << damped << ',' << damped << ',' << bare << '\n';
    if (std::abs(f - 85) < 1) pred << "0.2,1," << f << ",1," << 2 * damped << ',' << 2 * damped << ',' << bare << '\n';
  }
  std::ofstream(dir.path / "predict.csv") << pred.str();
  const CmdResult r = run_plot({dir.str()}, dir.path);
  expect_figures(r, dir.path, {"map.png", "predict.png"}, {0, 0});
  EXPECT_EQ(r.err, "");
  // A map without its intervals is refused, naming the file and the column.
  TempDir bad;
  std::ofstream(bad.path / "map.csv") << "gamma [1],frequency [Hz],M_eff_ratio [1]\n1,80,0.5\n";
  const CmdResult b = run_plot({bad.str()}, bad.path);
  EXPECT_EQ(b.code, 2) << b.err;
  EXPECT_NE(b.err.find("map.csv"), std::string::npos) << b.err;
}
