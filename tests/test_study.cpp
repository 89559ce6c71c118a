// Parameter studies (`bagdem sweep`, study/study.hpp), through the real binary:
//  - values, grid order and SI numbers of the plan, in-process;
//  - a grid and a zip: points, directories, merged rows, the inputs columns, the point's own cells
//    copied exactly, and the runs' receptance against the analytic SDOF one (so each point's
//    overrides did reach its run);
//  - refusals before anything runs (unknown key, zip of unequal lengths, J x T > C);
//  - a sweep killed with its children, then resumed: done points untouched, the half-run one run
//    again, the final table that of an uninterrupted sweep; a changed plan is refused;
//  - a failing point is reported, the others finish, exit 3;
//  - an ensemble over seeds: mean, sd, se and ci95 against the rows;
//  - MPI ranks share the points and merge the serial sweep's table.
// The case is tiny: an SDOF (20 Hz, 2 kg) swept at 19 and 21 Hz with one ball that never touches a
// wall (the setting of StructureSdof.SweptReceptanceMatchesTheAnalyticOneWithoutContents), about
// half a second per point.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numbers>
#include <fstream>
#include <thread>

#include <toml++/toml.h>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/output_lock.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/study/study.hpp"
#include "h5_read.hpp"
#include "case_texts.hpp"
#include "support.hpp"

using namespace bagdem;
using bagdem::testing::CmdResult;
using bagdem::testing::CaseText;
using bagdem::testing::kNoGravity;
using bagdem::testing::quoted;
using bagdem::testing::TempDir;
using bagdem::testing::vec;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kMass = 2, kStiffness = 31583;  // f_n = 20.0 Hz

// The SDOF without contents: the steady state starts the first frequency, no peak refinement.
std::string tiny_case() {
  return CaseText()
      .simulation("1 s", kNoGravity)
      .set("simulation", "steps_per_contact", 10)
      .material("soft", "7800 kg/m^3", "10 MPa", 0.3)
      .interactions(0.5, 0.3)
      .box("soft", vec("-20 mm", "-20 mm", "-20 mm"), vec("20 mm", "20 mm", "20 mm"))
      .sdof(kMass, kStiffness, 0.05)
      .set("excitation", {{"kind", quoted("stepped-sine")}, {"amplitude", "20 N"}, {"frequencies", R"(["19 Hz", "21 Hz"])"},
                          {"refine", 0}, {"start", quoted("steady")}, {"steady_tolerance", 0.01}, {"max_cycles", 60}})
      .placed("ball", "soft", "5 mm", "[[0, 0, 0]]")
      .output("energy", "true");
}

std::string make_case(const TempDir& d) {
  fs::create_directories(d.path / "case");
  d.write("case/case.toml", tiny_case());
  return (d.path / "case").string();
}

// A CSV without quoted cells (what the runs and the sweep write for these cases), read
// independently of the sweep's reader.
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::size_t col(const std::string& name) const {
    for (std::size_t k = 0; k < header.size(); ++k)
      if (header[k] == name) return k;
    ADD_FAILURE() << "no column '" << name << "'";
    return 0;
  }
  const std::string& at(std::size_t r, const std::string& name) const { return rows.at(r).at(col(name)); }
  double num(std::size_t r, const std::string& name) const { return std::strtod(at(r, name).c_str(), nullptr); }
};

Csv read_csv(const fs::path& p) {
  Csv c;
  std::istringstream in(bagdem::testing::slurp(p));
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::string cell;
    for (char ch : line) {
      if (ch == ',') cells.push_back(cell), cell.clear();
      else cell += ch;
    }
    cells.push_back(cell);
    if (c.header.empty()) c.header = cells;
    else c.rows.push_back(cells);
  }
  return c;
}

CmdResult sweep(const TempDir& d, std::vector<std::string> args) {
  args.insert(args.begin(), "sweep");
  return bagdem::testing::run_bagdem(args, d.path);
}

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& more) {
  a.insert(a.end(), more.begin(), more.end());
  return a;
}

// Two merged tables are equal in every cell except the columns named in `except`.
void expect_same_table(const Csv& a, const Csv& b, const std::string& except) {
  ASSERT_EQ(a.header, b.header);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  std::size_t compared = 0;
  for (std::size_t r = 0; r < a.rows.size(); ++r)
    for (std::size_t c = 0; c < a.header.size(); ++c)
      if (a.header[c] != except) {
        EXPECT_EQ(a.rows[r][c], b.rows[r][c]) << "row " << r << ", " << a.header[c];
        ++compared;
      }
  std::printf("  %zu cells compared (%zu rows), all equal; %s excepted\n", compared, a.rows.size(), except.c_str());
}

std::string point_dir(const std::string& out, int k) {
  char b[16];
  std::snprintf(b, sizeof b, "point-%03d", k);
  return (fs::path(out) / b).string();
}

// Variable-length strings of a dataset.
std::vector<std::string> read_strings(hid_t file, const std::string& name) {
  std::vector<std::string> out;
  hid_t ds = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(ds, 0) << name;
  if (ds < 0) return out;
  hid_t type = H5Dget_type(ds), space = H5Dget_space(ds);
  std::vector<char*> p(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  EXPECT_GT(H5Tis_variable_str(type), 0) << name;
  if (!p.empty() && H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, p.data()) >= 0)
    for (char* s : p) out.emplace_back(s ? s : ""), H5free_memory(s);
  H5Sclose(space);
  H5Tclose(type);
  H5Dclose(ds);
  return out;
}

}  // namespace

// The plan without running anything: values as --vary takes them, SI numbers, the order of a grid
// with seeds, and the zip's refusal.
TEST(Study, ValuesGridOrderAndSiNumbers) {
  const std::vector<study::Value> v = study::parse_value_list("\"4 mm\", 8 mm,[0, 0, -9.81],0.050, hash");
  ASSERT_EQ(v.size(), 5u);
  EXPECT_EQ(v[0].toml, "\"4 mm\"");
  EXPECT_EQ(v[0].given, "4 mm");
  EXPECT_EQ(v[1].toml, "\"8 mm\"");  // a bare word is a string, as --set takes it
  EXPECT_EQ(v[2].toml, "[0, 0, -9.81]");
  EXPECT_EQ(v[3].toml, "0.05");
  EXPECT_EQ(v[3].given, "0.050");
  EXPECT_EQ(v[4].toml, "\"hash\"");

  std::string unit;
  const double d = study::si_number("20 mm", &unit);
  std::printf("  \"20 mm\" -> %.15g %s; \"5 %%\" -> %.15g; \"30 Hz\" -> %.15g\n", d, unit.c_str(), study::si_number("5 %", nullptr),
              study::si_number("30 Hz", nullptr));
  EXPECT_NEAR(d, 0.02, 1e-17);
  EXPECT_EQ(unit, "m");
  EXPECT_NEAR(study::si_number("5 %", &unit), 0.05, 1e-17);
  EXPECT_EQ(unit, "1");
  EXPECT_EQ(study::si_number("30 Hz", &unit), 30.0);
  EXPECT_EQ(unit, "1/s");
  EXPECT_EQ(study::si_number("0.05", &unit), 0.05);
  EXPECT_EQ(unit, "");
  EXPECT_TRUE(std::isnan(study::si_number("hash", &unit)));
  EXPECT_EQ(study::si_number("2 m^5", &unit), 2.0);  // any dimension its unit has
  EXPECT_EQ(unit, "m^5");

  study::StudySpec spec;
  spec.case_dir = "/nowhere", spec.out_dir = "/nowhere/out", spec.source = "test";
  spec.vary = {{"a.x", study::parse_value_list("1,2")}, {"b.y", study::parse_value_list("10,20,30")}};
  spec.sets = {"c.z=5"};
  spec.seeds = 2;
  const study::Plan plan = study::make_plan(spec);
  ASSERT_EQ(plan.points.size(), 12u);  // 2 x 3 combinations x 2 seeds
  const study::Point& p = plan.points[5];  // combination 2 (a = 1, b = 30), seed 2
  EXPECT_EQ(p.name, "point-005");
  EXPECT_EQ(p.combination, 2u);
  EXPECT_EQ(p.seed, 2);
  EXPECT_EQ(p.sets, (std::vector<std::string>{"c.z=5", "a.x=1", "b.y=30", "simulation.seed=2"}));
  EXPECT_EQ(plan.point_dir(p), "/nowhere/out/point-005");
  spec.combine = study::Combine::zip;
  EXPECT_THROW(study::make_plan(spec), InputError);
  // A set spaced as a case file writes it ("key = value", which the case reader applies) is refused
  // as the same key: it passed as another key, and the study's own value silently won.
  spec.combine = study::Combine::grid;
  for (const std::string set : {" a.x = 3", "simulation.seed\t= 5"}) {
    spec.sets = {set};
    EXPECT_THROW(study::make_plan(spec), InputError) << set;
  }
}

// A grid of 2 ball sizes x 2 force amplitudes: four points, each in its directory; the merged
// table has each point's rows, its inputs as given and in SI, and its own cells exactly.
TEST(Study, GridRunsEveryPointAndMergesItsRows) {
  TempDir d;
  const std::string c = make_case(d), out = (d.path / "grid").string();
  const CmdResult r = sweep(d, {c, "--vary", "particles.ball.diameter=5 mm,20 mm", "--vary", "excitation.amplitude=10 N,20 N", "--jobs",
                                "2", "--cores", "2", "--out", out});
  ASSERT_EQ(r.code, 0) << r.err;
  std::printf("  %s", r.out.c_str());
  for (int k = 0; k < 4; ++k)
    for (const char* f : {"point.toml", "point.done", "log.txt", "sweep.csv", "summary.json", "results.h5"})
      EXPECT_TRUE(fs::exists(fs::path(point_dir(out, k)) / f)) << point_dir(out, k) << "/" << f;
  EXPECT_FALSE(fs::exists(point_dir(out, 4)));

  const Csv m = read_csv(fs::path(out) / "sweep.csv");
  ASSERT_EQ(m.rows.size(), 8u);  // 4 points x 2 frequencies
  const char* diameter[] = {"5 mm", "5 mm", "20 mm", "20 mm"};
  const char* force[] = {"10 N", "20 N", "10 N", "20 N"};  // the grid varies the last key fastest
  for (std::size_t row = 0; row < m.rows.size(); ++row) {
    const auto k = static_cast<std::size_t>(std::stoi(m.at(row, "point")));
    EXPECT_EQ(k, row / 2);
    EXPECT_EQ(m.at(row, "status"), "done");
    EXPECT_EQ(m.at(row, "particles.ball.diameter"), diameter[k]);
    EXPECT_EQ(m.at(row, "excitation.amplitude"), force[k]);
    EXPECT_NEAR(m.num(row, "particles.ball.diameter [m]"), k < 2 ? 0.005 : 0.02, 1e-17);
    EXPECT_EQ(m.num(row, "excitation.amplitude [kg m/s^2]"), k % 2 ? 20.0 : 10.0);
    // The point's own row, copied exactly.
    const Csv own = read_csv(fs::path(point_dir(out, static_cast<int>(k))) / "sweep.csv");
    ASSERT_EQ(own.rows.size(), 2u);
    for (const auto& col : own.header) EXPECT_EQ(m.at(row, col), own.at(row % 2, col)) << col;
  }
  // The overrides reached the runs: twice the force gives twice the response, the same receptance
  // (a linear structure; the ball never touches); the receptance is the analytic one.
  double worst = 0;
  for (std::size_t row = 0; row < 8; ++row) {
    const double w = 2 * kPi * m.num(row, "frequency [Hz]"), zeta = 0.05, C = 2 * zeta * std::sqrt(kStiffness * kMass);
    const std::complex<double> H = 1.0 / std::complex<double>(kStiffness - w * w * kMass, w * C);
    const std::complex<double> got(m.num(row, "receptance_re [m/N]"), m.num(row, "receptance_im [m/N]"));
    worst = std::max(worst, std::abs(got - H) / std::abs(H));
  }
  const double ratio = m.num(2, "response_re [m]") / m.num(0, "response_re [m]");
  std::printf("  response at 20 N / at 10 N: %.6f; receptance against the analytic SDOF: worst error %.2e\n", ratio, worst);
  EXPECT_NEAR(ratio, 2.0, 0.01);
  EXPECT_LT(worst, 0.01);

  // study.h5: the same table, numbers with units, the inputs as written.
  const hid_t f = bagdem::testing::open_read(out + "/study.h5");
  ASSERT_GE(f, 0);
  const auto re = bagdem::testing::read_doubles(f, "/sweep/receptance_re");
  ASSERT_EQ(re.values.size(), 8u);
  for (std::size_t row = 0; row < 8; ++row) EXPECT_EQ(re.values[row], m.num(row, "receptance_re [m/N]"));
  EXPECT_EQ(bagdem::testing::unit_of(f, "/sweep/receptance_re"), "m/N");
  EXPECT_EQ(bagdem::testing::unit_of(f, "/sweep/particles.ball.diameter"), "m");
  EXPECT_EQ(read_strings(f, "/sweep/given/particles.ball.diameter")[7], "20 mm");
  EXPECT_EQ(read_strings(f, "/sweep/status")[0], "done");
  H5Fclose(f);

  // Exported: a varied key's two columns (as written and in SI) under two names. Export used to
  // fail on the second (exit 1, export.h5.part left) and write one JSON key twice.
  const CmdResult ex = bagdem::testing::run_bagdem({"export", out}, d.path);
  ASSERT_EQ(ex.code, 0) << ex.err;
  const std::string json = bagdem::testing::slurp(fs::path(out) / "export.json");
  EXPECT_NE(json.find("\"excitation.amplitude (given)\": \"10 N\""), std::string::npos) << json.substr(0, 2000);
  EXPECT_NE(json.find("\"excitation.amplitude\": 10,"), std::string::npos) << json.substr(0, 2000);
  EXPECT_FALSE(fs::exists(fs::path(out) / "export.h5.part"));
  // reduced.csv edited since the study merged it (one figure): export refuses it, naming study.h5's
  // record, and the earlier export stays.
  {
    const fs::path reduced = fs::path(out) / "reduced.csv";
    const std::string as_merged = bagdem::testing::slurp(reduced), exported = bagdem::testing::slurp(fs::path(out) / "export.csv");
    const TextTable t = read_text_table(reduced);
    const std::size_t col = t.find("M_eff");
    ASSERT_LT(col, t.names.size());
    std::string edited = as_merged;
    const std::size_t line = edited.find('\n') + 1;  // the first row
    std::size_t at = line;
    for (std::size_t k = 0; k < col; ++k) at = edited.find(',', at) + 1;
    edited.insert(at, "9");
    std::ofstream(reduced) << edited;
    const CmdResult refused = bagdem::testing::run_bagdem({"export", out}, d.path);
    EXPECT_EQ(refused.code, 2) << refused.err;
    EXPECT_NE(refused.err.find("differs from study.h5's /reduced at row 1"), std::string::npos) << refused.err;
    EXPECT_EQ(bagdem::testing::slurp(fs::path(out) / "export.csv"), exported);
    std::ofstream(reduced) << as_merged;
  }

  // A point's table changed or removed since its run finished (point.done records each one's
  // fingerprint): the study run again refuses it, naming the point and the table, and its merged
  // tables stay; as they were, it merges again without running. Before, an edited table was merged
  // as the run's (characterize made a map of a C_eff x 2 by hand, exit 0).
  const std::vector<std::string> again = {c, "--vary", "particles.ball.diameter=5 mm,20 mm", "--vary", "excitation.amplitude=10 N,20 N",
                                          "--jobs", "2", "--cores", "2", "--out", out};
  const std::string merged = bagdem::testing::slurp(fs::path(out) / "sweep.csv");
  const fs::path table = fs::path(point_dir(out, 1)) / "sweep.csv", summary = fs::path(point_dir(out, 2)) / "summary.json";
  const std::string own = bagdem::testing::slurp(table), own_summary = bagdem::testing::slurp(summary);
  std::string edited = own;
  edited[edited.rfind('1')] = '2';
  std::ofstream(table) << edited;
  CmdResult refused = sweep(d, again);
  EXPECT_EQ(refused.code, 2) << refused.err;
  EXPECT_NE(refused.err.find(point_dir(out, 1) + " changed since its run finished: sweep.csv is not as its run wrote it"), std::string::npos)
      << refused.err;
  std::ofstream(table) << own;
  fs::remove(summary);
  refused = sweep(d, again);
  EXPECT_EQ(refused.code, 2) << refused.err;
  EXPECT_NE(refused.err.find("summary.json is gone"), std::string::npos) << refused.err;
  EXPECT_EQ(bagdem::testing::slurp(fs::path(out) / "sweep.csv"), merged);
  std::ofstream(summary) << own_summary;
  ASSERT_TRUE(fs::exists(fs::path(out) / "export.csv"));
  const CmdResult merges = sweep(d, again);
  EXPECT_EQ(merges.code, 0) << merges.err;
  EXPECT_EQ(bagdem::testing::slurp(fs::path(out) / "sweep.csv"), merged);
  // The earlier export goes with the earlier tables (it was left beside new ones, stale).
  for (const char* f : {"export.csv", "export.json", "export.h5"}) {
    EXPECT_FALSE(fs::exists(fs::path(out) / f)) << f;
    EXPECT_NE(merges.err.find(std::string("/") + f + ": an export of the earlier tables"), std::string::npos) << merges.err;
  }
}

// A study and a run each refuse the other's directory, and a study does not clear a point's directory
// that a run started by hand writes now. Before, a sweep into a run's directory replaced its tables
// with the study's (reduce then read the study's first point as the run), a run into a study's
// deleted its merged tables, and a sweep deleted a locked point's directory and merged that
// stranger's rows (all exit 0).
TEST(Study, ARunAndAStudyRefuseEachOthersDirectoriesAndALockedPoint) {
  TempDir d;
  const std::string c = make_case(d);
  const fs::path run = d.path / "run", study = d.path / "study", busy = d.path / "busy";
  ASSERT_EQ(bagdem::testing::run_bagdem({"run", c, "--quiet", "--threads", "1", "--out", run.string()}, d.path).code, 0);
  const std::string reduced = bagdem::testing::slurp(run / "reduced.csv");
  CmdResult r = sweep(d, {c, "--vary", "excitation.amplitude=10 N,20 N", "--jobs", "1", "--out", run.string()});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("holds a run's results.h5"), std::string::npos) << r.err;
  EXPECT_EQ(bagdem::testing::slurp(run / "reduced.csv"), reduced);
  EXPECT_FALSE(fs::exists(run / "study.h5") || fs::exists(run / "point-000"));

  ASSERT_EQ(sweep(d, {c, "--vary", "excitation.amplitude=10 N", "--jobs", "1", "--out", study.string()}).code, 0);
  const std::string merged = bagdem::testing::slurp(study / "sweep.csv");
  r = bagdem::testing::run_bagdem({"run", c, "--quiet", "--threads", "1", "--out", study.string()}, d.path);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("holds a study's study.h5"), std::string::npos) << r.err;
  EXPECT_EQ(bagdem::testing::slurp(study / "sweep.csv"), merged);
  EXPECT_FALSE(fs::exists(study / "results.h5"));
  // Nor into one of its points by hand (the resumed study merged that run under the point's label).
  const std::string point = bagdem::testing::slurp(study / "point-000" / "sweep.csv");
  r = bagdem::testing::run_bagdem({"run", c, "--quiet", "--threads", "1", "--out", (study / "point-000").string()}, d.path);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("holds a study's point.toml"), std::string::npos) << r.err;
  EXPECT_EQ(bagdem::testing::slurp(study / "point-000" / "sweep.csv"), point);

  {
    const bagdem::OutputLock held(busy / "point-000");  // as a run started by hand into it holds it
    std::ofstream(busy / "point-000" / "mine.txt") << "being written\n";
    r = sweep(d, {c, "--vary", "excitation.amplitude=10 N", "--jobs", "1", "--out", busy.string()});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("another bagdem process is writing there now"), std::string::npos) << r.err;
    EXPECT_EQ(bagdem::testing::slurp(busy / "point-000" / "mine.txt"), "being written\n");
  }
  EXPECT_EQ(sweep(d, {c, "--vary", "excitation.amplitude=10 N", "--jobs", "1", "--out", busy.string()}).code, 0) << "the lock outlived its holder";
}

// The merge on a full disk (the full-disk library preloaded, tests/full_disk): the study exits 1 naming
// the reason and leaves no study.h5. Before, HDF5's failed writes went to stderr only and a broken
// study.h5 was renamed into place with "sweep complete" and exit 0 (the close's writes were unchecked).
TEST(Study, AMergeOnAFullDiskExitsOneAndLeavesNoBrokenStudyFile) {
  TempDir d;
  const std::string c = make_case(d), out = (d.path / "full").string();
  const std::vector<std::string> args = {c, "--vary", "excitation.amplitude=10 N,20 N", "--jobs", "1", "--out", out};
  ASSERT_EQ(sweep(d, args).code, 0);
  long long tables = 0;
  for (const auto& e : fs::directory_iterator(out))
    if (e.path().extension() == ".csv") tables += static_cast<long long>(fs::file_size(e.path()));
  const auto h5 = static_cast<long long>(fs::file_size(fs::path(out) / "study.h5"));
  // Every point is done: a second sweep only merges. The disk fills within the tables, and in
  // study.h5 early, half way and near its end.
  for (long long bytes : {tables / 2, tables + 200, tables + h5 / 2, tables + h5 * 9 / 10}) {
    SCOPED_TRACE("disk full after " + std::to_string(bytes) + " bytes");
    fs::remove(fs::path(out) / "study.h5");
    setenv("LD_PRELOAD", BAGDEM_FULL_DISK_LIB, 1);
    setenv("BAGDEM_FULL_DISK_BYTES", std::to_string(bytes).c_str(), 1);
    const CmdResult r = sweep(d, args);
    unsetenv("LD_PRELOAD");
    unsetenv("BAGDEM_FULL_DISK_BYTES");
    EXPECT_EQ(r.code, 1) << r.out << r.err;
    EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(fs::path(out) / "study.h5")) << "a study.h5 the disk could not hold was renamed into place";
  }
  ASSERT_EQ(sweep(d, args).code, 0) << "with room again";
  const hid_t f = bagdem::testing::open_read(out + "/study.h5");
  EXPECT_GE(f, 0);
  if (f >= 0) H5Fclose(f);
}

// study.toml with combine = "zip": the lists taken together, point.toml recording the overrides,
// and each point's receptance the analytic one of its own damping ratio.
TEST(Study, ZipFromStudyTomlTakesTheListsTogether) {
  TempDir d;
  make_case(d);
  fs::create_directories(d.path / "study");
  d.write("study/study.toml",
          "case = \"../case\"\ncombine = \"zip\"\nset = [\"excitation.steady_tolerance = 0.005\"]\njobs = 2\ncores = 2\n\n[vary]\n"
          "\"primary.damping_ratio\" = [0.03, 0.08]\nexcitation.amplitude = [\"10 N\", \"20 N\"]\n");  // quoted or dotted keys
  const CmdResult r = sweep(d, {(d.path / "study").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string out = (d.path / "study" / "out").string();
  EXPECT_TRUE(fs::exists(point_dir(out, 1)));
  EXPECT_FALSE(fs::exists(point_dir(out, 2)));
  const std::string toml = bagdem::testing::slurp(fs::path(point_dir(out, 1)) / "point.toml");
  EXPECT_NE(toml.find("'primary.damping_ratio=0.08'"), std::string::npos) << toml;
  EXPECT_NE(toml.find("'excitation.amplitude=\"20 N\"'"), std::string::npos) << toml;
  EXPECT_NE(toml.find("'excitation.steady_tolerance=0.005'"), std::string::npos) << toml;

  const Csv m = read_csv(fs::path(out) / "sweep.csv");
  ASSERT_EQ(m.rows.size(), 4u);
  for (std::size_t row = 0; row < 4; ++row) {
    const double zeta = row < 2 ? 0.03 : 0.08;
    EXPECT_EQ(m.at(row, "primary.damping_ratio"), row < 2 ? "0.03" : "0.08");
    EXPECT_EQ(m.num(row, "primary.damping_ratio [SI]"), zeta);  // a plain number: its unit is the case's
    EXPECT_EQ(m.at(row, "excitation.amplitude"), row < 2 ? "10 N" : "20 N");
    const double w = 2 * kPi * m.num(row, "frequency [Hz]"), C = 2 * zeta * std::sqrt(kStiffness * kMass);
    const std::complex<double> H = 1.0 / std::complex<double>(kStiffness - w * w * kMass, w * C);
    const std::complex<double> got(m.num(row, "receptance_re [m/N]"), m.num(row, "receptance_im [m/N]"));
    std::printf("  zeta %.2f at %.4f Hz: |H| %.6e m/N (analytic %.6e), error %.2e\n", zeta, w / (2 * kPi), std::abs(got), std::abs(H),
                std::abs(got - H) / std::abs(H));
    EXPECT_LT(std::abs(got - H) / std::abs(H), 0.01);
  }
}

// Refused before anything runs, with exit 2 and nothing written.
TEST(Study, RefusesBadInputBeforeRunningAnything) {
  TempDir d;
  const std::string c = make_case(d), out = (d.path / "never").string();
  const std::vector<std::string> base = {c, "--out", out, "--cores", "2"};

  CmdResult r = sweep(d, with(base, {"--vary", "primary.damping_rato=0.02,0.05"}));
  std::printf("  unknown key: exit %d: %s", r.code, r.err.c_str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("point-000"), std::string::npos);
  EXPECT_NE(r.err.find("primary.damping_rato"), std::string::npos);

  r = sweep(d, with(base, {"--vary", "primary.damping_ratio=0.02,-1"}));  // the second point's value is out of range
  std::printf("  bad value: exit %d: %s", r.code, r.err.c_str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("point-001"), std::string::npos);
  EXPECT_NE(r.err.find("primary.damping_ratio"), std::string::npos);

  r = sweep(d, with(base, {"--zip", "--vary", "primary.damping_ratio=0.02,0.05", "--vary", "excitation.amplitude=1 N,2 N,3 N"}));
  std::printf("  zip: exit %d: %s", r.code, r.err.c_str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("equal lengths"), std::string::npos);

  r = sweep(d, with(base, {"--vary", "primary.damping_ratio=0.02,0.05", "--jobs", "3", "--threads", "1"}));
  std::printf("  3 x 1 on 2 cores: exit %d: %s", r.code, r.err.c_str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("= 3 threads exceed the 2 cores"), std::string::npos);
  EXPECT_NE(r.err.find("Lower --jobs to 2"), std::string::npos);
  r = sweep(d, with(base, {"--vary", "primary.damping_ratio=0.02,0.05", "--threads", "4"}));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("Lower --threads"), std::string::npos) << r.err;

  EXPECT_FALSE(fs::exists(out));
}

// Killed (the sweep and its children, as one process group) after the first point is done; the
// rerun skips that point without touching it, runs the others again and ends with the table of an
// uninterrupted sweep. A merged table of an earlier sweep does not survive the restart.
TEST(Study, ResumesAfterAKillAndKeepsNoHalfPoint) {
  TempDir d;
  const std::string c = make_case(d), whole = (d.path / "whole").string(), cut = (d.path / "cut").string();
  const std::vector<std::string> plan = {c, "--vary", "excitation.amplitude=10 N,15 N,20 N", "--cores", "2"};
  CmdResult r = sweep(d, with(plan, {"--jobs", "2", "--out", whole}));
  ASSERT_EQ(r.code, 0) << r.err;

  fs::create_directories(cut);
  fs::copy_file(fs::path(whole) / "sweep.csv", fs::path(cut) / "sweep.csv");  // as if from an earlier sweep
  std::vector<std::string> args = with({BAGDEM_BINARY, "sweep"}, with(plan, {"--jobs", "1", "--out", cut}));
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string log = (d.path / "interrupted.txt").string();
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    setpgid(0, 0);
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1), dup2(fd, 2);
    execv(argv[0], argv.data());
    _exit(127);
  }
  setpgid(pid, pid);
  const fs::path first = fs::path(point_dir(cut, 0)) / "point.done";
  const auto t0 = std::chrono::steady_clock::now();
  while (!fs::exists(first) && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  kill(-pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(fs::exists(first)) << bagdem::testing::slurp(log);
  std::printf("  killed %.2f s after the start, with point-000 done\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  EXPECT_FALSE(fs::exists(fs::path(cut) / "sweep.csv"));  // the earlier table is gone, none claims the unfinished points
  EXPECT_FALSE(fs::exists(fs::path(cut) / "study.h5"));
  EXPECT_FALSE(fs::exists(fs::path(point_dir(cut, 1)) / "point.done"));
  EXPECT_FALSE(fs::exists(fs::path(point_dir(cut, 2)) / "point.done"));
  std::map<std::string, fs::file_time_type> before;
  for (const auto& e : fs::directory_iterator(point_dir(cut, 0))) before[e.path().string()] = fs::last_write_time(e.path());

  r = sweep(d, with(plan, {"--jobs", "2", "--out", cut}));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("resuming: 1 of 3 points done by an earlier run, skipped"), std::string::npos) << r.err;
  std::size_t same = 0;
  for (const auto& e : fs::directory_iterator(point_dir(cut, 0))) {
    const auto it = before.find(e.path().string());
    EXPECT_TRUE(it != before.end()) << "new file in a done point: " << e.path();
    if (it != before.end() && it->second == fs::last_write_time(e.path())) ++same;
  }
  std::printf("  point-000 after the resume: %zu of %zu files untouched\n", same, before.size());
  EXPECT_EQ(same, before.size());
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(fs::exists(fs::path(point_dir(cut, k)) / "point.done"));
  expect_same_table(read_csv(fs::path(whole) / "sweep.csv"), read_csv(fs::path(cut) / "sweep.csv"), "wall_time [s]");

  // Another plan over the same OUT: refused.
  r = sweep(d, {c, "--vary", "excitation.amplitude=10 N,15 N,25 N", "--cores", "2", "--out", cut});
  std::printf("  changed plan: exit %d: %s", r.code, r.err.c_str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("the study changed"), std::string::npos);
  EXPECT_NE(r.err.find("point-002"), std::string::npos);

  // A done point whose point.toml records another scene than this bagdem resolves its case to (as a
  // bagdem with another default time step would have written): refused, naming the line, nothing
  // run again; a point.toml without the record (an older bagdem's) is refused too.
  const fs::path toml_path = fs::path(point_dir(whole, 1)) / "point.toml";
  const std::string kept = bagdem::testing::slurp(toml_path.string());
  toml::table t = toml::parse(kept);
  toml::array& scene = *t["scene"].as_array();
  bool changed = false;
  for (auto& line : scene)
    if (line.value<std::string>()->rfind("time step", 0) == 0) line.as_string()->get() = "time step   1e-06 s (auto: as an older bagdem chose it)", changed = true;
  ASSERT_TRUE(changed) << kept;
  std::ofstream(toml_path) << t;
  r = sweep(d, with(plan, {"--jobs", "2", "--out", whole}));
  std::printf("  another scene: exit %d: %s", r.code, r.err.c_str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("point-001"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("resolves its case to another scene"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("was 'time step   1e-06 s"), std::string::npos) << r.err;
  t.erase("scene");
  std::ofstream(toml_path) << t;
  r = sweep(d, with(plan, {"--jobs", "2", "--out", whole}));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("did not record the scene"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(fs::path(point_dir(whole, 1)) / "point.done"));
  std::ofstream(toml_path) << kept;
  r = sweep(d, with(plan, {"--jobs", "2", "--out", whole}));
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("resuming: 3 of 3 points done"), std::string::npos) << r.err;
}

// A force that drives the wall into the ball makes that point's run stop (exit 3): it is reported
// with the end of its log, the other points finish, the table lists it as failed, exit 3.
TEST(Study, FailedPointIsReportedAndTheOthersFinish) {
  TempDir d;
  const std::string c = make_case(d), out = (d.path / "out").string();
  const CmdResult r = sweep(d, {c, "--vary", "excitation.amplitude=10 N,3000 N,20 N", "--jobs", "2", "--cores", "2", "--out", out});
  std::printf("  exit %d; %s", r.code, r.out.c_str());
  EXPECT_EQ(r.code, 3);
  EXPECT_NE(r.err.find("point-001 failed (exit 3: the run went unstable)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("contact overlap"), std::string::npos) << r.err;  // the run's own message, from its log
  EXPECT_NE(r.out.find("1 failed point of 3 (point-001"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(fs::path(point_dir(out, 0)) / "point.done"));
  EXPECT_FALSE(fs::exists(fs::path(point_dir(out, 1)) / "point.done"));
  EXPECT_TRUE(fs::exists(fs::path(point_dir(out, 2)) / "point.done"));
  const Csv m = read_csv(fs::path(out) / "sweep.csv");
  ASSERT_EQ(m.rows.size(), 5u);  // 2 + 1 (no table from the failed point: its own cells empty) + 2
  EXPECT_EQ(m.at(2, "point"), "1");
  EXPECT_EQ(m.at(2, "status"), "failed");
  EXPECT_EQ(m.at(2, "receptance_re [m/N]"), "");
  EXPECT_EQ(m.at(0, "status"), "done");
  EXPECT_EQ(m.at(4, "status"), "done");
  // Exported: refused at the failed point's row, said as a point that did not finish (it read "the
  // table is damaged").
  const CmdResult ex = bagdem::testing::run_bagdem({"export", out}, d.path);
  EXPECT_EQ(ex.code, 2) << ex.err;
  EXPECT_NE(ex.err.find("'row 3, status' = failed: is a point that did not finish"), std::string::npos) << ex.err;
}

// The studies shipped in cases/studies: each plans and loads every point as `bagdem sweep` would
// before running (a key renamed or a bag that stops fitting fails here). The ball-size study keeps
// the mass ratio with whole balls, 102, 13, 7 and 1 (the 20-mm point is one ball, a near-rigid
// slug), and each point's actual ratio is within half a ball of 8%; the mass-ratio study spans
// 5-14%, the position study puts the cavity at the study's x/L, and the clearance study keeps Table 3's
// 64 balls in bags of 8-11 mm.
TEST(Study, ShippedStudiesLoadEveryPoint) {
  const fs::path root = fs::path(BAGDEM_CASES_DIR) / "studies";
  auto plan_of = [&](const std::string& name) {
    study::SweepArgs a;
    a.dir = (root / name).string();
    study::Plan plan = study::make_plan(study::read_spec(a));
    study::validate_plan(plan);
    return plan;
  };
  auto bag_of = [](const study::Plan& plan, const study::Point& p) {
    const Scene s = load_case(plan.spec.case_dir, p.sets);
    double mass = 0;
    for (std::size_t k = s.bag->ball_first; k < s.bag->ball_first + s.bag->balls; ++k)
      mass += 4.0 / 3.0 * kPi * std::pow(s.particles[k].radius, 3) * s.materials[static_cast<std::size_t>(s.particles[k].material)].density;
    return std::make_tuple(s.bag->balls, mass / s.primary->structure_mass, mass / static_cast<double>(s.bag->balls), s.primary->structure_mass);
  };

  const study::Plan size = plan_of("ball-size");
  ASSERT_EQ(size.points.size(), 4u);
  const std::size_t counts[] = {102, 13, 7, 1};
  for (const study::Point& p : size.points) {
    const auto [balls, ratio, ball_mass, primary] = bag_of(size, p);
    EXPECT_EQ(balls, counts[p.index]) << p.name;
    EXPECT_LE(std::abs(ratio - 0.08) * primary, 0.5 * ball_mass + 1e-12) << p.name << ": ratio " << ratio;
  }

  const study::Plan ratio = plan_of("mass-ratio");
  ASSERT_EQ(ratio.points.size(), 10u);
  for (const study::Point& p : ratio.points) {
    const auto [balls, actual, ball_mass, primary] = bag_of(ratio, p);
    const double asked = 0.05 + 0.01 * static_cast<double>(p.index);
    EXPECT_LE(std::abs(actual - asked) * primary, 0.5 * ball_mass + 1e-12) << p.name << ": ratio " << actual;
    EXPECT_NEAR(ball_mass, 7800 * 4.0 / 3.0 * kPi * 8e-9, 1e-12) << p.name << ": 4-mm steel balls";
  }

  const study::Plan position = plan_of("position");
  const double x_over_L[] = {0.095, 0.132, 0.224, 0.316, 0.356, 0.5, 0.644, 0.684, 0.776, 0.868, 0.905};
  ASSERT_EQ(position.points.size(), 11u);
  for (const study::Point& p : position.points) {
    const Scene s = load_case(position.spec.case_dir, p.sets);
    EXPECT_NEAR(s.primary->attach / s.primary->length, x_over_L[p.index], 5e-5) << p.name;
  }

  // The clearance study: Table 3's bag (5%, 64 balls) at five radii inside the 11.75-mm bore.
  const study::Plan clearance = plan_of("clearance");
  const double radius[] = {8e-3, 9e-3, 10e-3, 10.5e-3, 11e-3};
  ASSERT_EQ(clearance.points.size(), 5u);
  for (const study::Point& p : clearance.points) {
    const Scene s = load_case(clearance.spec.case_dir, p.sets);
    EXPECT_EQ(s.bag->balls, 64u) << p.name;
    EXPECT_NEAR(0.5 * s.bag->size.y(), radius[p.index], 1e-12) << p.name;  // the capsule's width is its diameter
  }
}

// Two seeds per force: the ensemble table's mean, sample sd, standard error and 95% half-width of
// each numeric column against the merged rows. The case has no random input, so the physics is the same for
// both seeds (sd 0) while the wall time differs (sd > 0).
TEST(Study, EnsembleOverSeedsGivesMeanSdSeAndInterval) {
  TempDir d;
  const std::string c = make_case(d), out = (d.path / "out").string();
  const CmdResult r = sweep(d, {c, "--seeds", "2", "--vary", "excitation.amplitude=10 N,20 N", "--jobs", "2", "--cores", "2", "--out", out});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(bagdem::testing::slurp(fs::path(point_dir(out, 1)) / "point.toml").find("'simulation.seed=2'"), std::string::npos);
  const Csv m = read_csv(fs::path(out) / "sweep.csv"), e = read_csv(fs::path(out) / "sweep_ensemble.csv");
  ASSERT_EQ(m.rows.size(), 8u);
  ASSERT_EQ(e.rows.size(), 4u);  // 2 forces x 2 rows
  for (std::size_t row = 0; row < 8; ++row) EXPECT_EQ(m.at(row, "seed"), (row / 2) % 2 ? "2" : "1");
  for (std::size_t g = 0; g < 4; ++g) {
    EXPECT_EQ(e.at(g, "excitation.amplitude"), g < 2 ? "10 N" : "20 N");
    EXPECT_EQ(e.at(g, "row"), std::to_string(g % 2));
    EXPECT_EQ(e.at(g, "n"), "2");
    // Merged rows of this group: seed 1 and seed 2 of the force, row g % 2 of each point.
    const std::size_t a = (g / 2) * 4 + g % 2, b = a + 2;
    for (const std::string col : {"receptance_re", "response_im", "wall_time"}) {
      const std::string unit = col == "wall_time" ? " [s]" : col == "response_im" ? " [m]" : " [m/N]";
      const double x1 = m.num(a, col + unit), x2 = m.num(b, col + unit), mean = (x1 + x2) / 2;
      const double sd = std::sqrt(((x1 - mean) * (x1 - mean) + (x2 - mean) * (x2 - mean)) / 1.0), se = sd / std::sqrt(2.0);
      const double got_mean = e.num(g, col + "_mean" + unit), got_sd = e.num(g, col + "_sd" + unit), got_se = e.num(g, col + "_se" + unit);
      EXPECT_NEAR(e.num(g, col + "_ci95" + unit), 12.7062 * se, 1e-4 * se + 1e-14 * std::abs(mean));  // t_{0.975, 1}
      if (g == 0) std::printf("  %s: seeds %.9g, %.9g -> mean %.9g, sd %.3g, se %.3g\n", col.c_str(), x1, x2, got_mean, got_sd, got_se);
      EXPECT_NEAR(got_mean, mean, 1e-14 * std::abs(mean));
      EXPECT_NEAR(got_sd, sd, 1e-12 * std::abs(mean));
      EXPECT_NEAR(got_se, se, 1e-12 * std::abs(mean));
      if (col == "wall_time") EXPECT_GT(got_sd, 0.0);
      else EXPECT_EQ(got_sd, 0.0);
    }
  }
}

// Under mpirun with 2 ranks: rank r runs the points with index % 2 == r, rank 0 merges, and the
// table is that of a serial sweep.
TEST(Study, MpiRanksSharePointsAndMergeTheSerialTable) {
#if defined(BAGDEM_WITH_MPI) && defined(BAGDEM_MPIEXEC)
  TempDir d;
  const std::string c = make_case(d), serial = (d.path / "serial").string(), ranked = (d.path / "ranked").string();
  const std::vector<std::string> plan = {c, "--vary", "excitation.amplitude=10 N,15 N,20 N"};
  CmdResult r = sweep(d, with(plan, {"--jobs", "2", "--cores", "2", "--out", serial}));
  ASSERT_EQ(r.code, 0) << r.err;

  std::vector<std::string> args = {"sweep"};
  for (const auto& a : with(plan, {"--out", ranked})) args.push_back(a);
  const CmdResult m = bagdem::testing::run_bagdem(args, d.path, 2);
  const std::string &out = m.out, &err = m.err;
  std::printf("  mpirun -np 2: %s", out.c_str());
  ASSERT_EQ(m.code, 0) << err;
  for (int k = 0; k < 3; ++k) {
    const std::string done = bagdem::testing::slurp(fs::path(point_dir(ranked, k)) / "point.done");
    EXPECT_NE(done.find("rank = " + std::to_string(k % 2) + "\n"), std::string::npos) << done;
    EXPECT_NE(done.find("ranks = 2\n"), std::string::npos) << done;
  }
  std::size_t summaries = 0;
  for (std::size_t at = out.find("sweep complete"); at != std::string::npos; at = out.find("sweep complete", at + 1)) ++summaries;
  EXPECT_EQ(summaries, 1u);  // rank 0 alone merges and reports
  EXPECT_NE(err.find("[rank 1/2]"), std::string::npos);
  expect_same_table(read_csv(fs::path(serial) / "sweep.csv"), read_csv(fs::path(ranked) / "sweep.csv"), "wall_time [s]");
#else
  GTEST_SKIP() << "built without MPI (configure with -DBAGDEM_MPI=ON to test the ranks)";
#endif
}
