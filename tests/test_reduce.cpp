// The reduction of runs to effective parameters (reduce/reduce.hpp), the drop test
// (run/drop_test.hpp), the comparison with the continuum model (reduce/compare.hpp) and the
// export (reduce/export.hpp), through real runs:
//  - a rigid mass glued to the cavity (a steel ball squeezed 10 um between two walls, so that it
//    follows the cavity far below its contact resonance): M_eff equals its mass and C_eff is zero;
//  - the same ball in an SDOF primary's cavity, swept: the DEM response, the reduced M_eff, and the
//    continuum model fed with them agree;
//  - the drop test of a single ball returns the contact law's restitution;
//  - export round trip: what export writes reads back equal to reduced.csv; bad input exits 2.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "bagdem/case/load_case.hpp"
#include "bagdem/contact/restitution.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/reduce/compare.hpp"
#include "bagdem/run/drop_test.hpp"
#include "bagdem/reduce/export.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "bagdem/run/runner.hpp"
#include "bagdem/run/stepped_sine.hpp"
#include "case_texts.hpp"
#include "h5_read.hpp"
#include "support.hpp"

using namespace bagdem;
using bagdem::testing::CaseText;
using bagdem::testing::kNoGravity;
using bagdem::testing::quoted;
using bagdem::testing::steady_sdof_sweep;
using bagdem::testing::steel_scene;
using bagdem::testing::TempDir;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRadius = 5e-3;  // the squeezed ball (case_texts.hpp): 10 mm, 10 um into each x wall

double ball_mass() { return 7800 * 4.0 / 3.0 * kPi * std::pow(kRadius, 3); }

// One steel ball squeezed between two walls normal to x (free in y and z), no gravity (case_texts.hpp);
// `more` adds the motion or the primary.
std::string squeezed_ball(const CaseText& more, const std::string& duration) {
  return bagdem::testing::squeezed_ball(duration).merge(more);
}

// Run options writing to d/out, without progress output, on every core.
RunOptions quiet_in(const TempDir& d) { return bagdem::testing::quiet_run(d.path / "out", 0); }

}  // namespace

TEST(Reduce, RigidMassGluedToTheCavityHasItsMassAndNoDamping) {
  TempDir d;
  d.write("case.toml", squeezed_ball(CaseText().harmonic("0.1 mm", "20 Hz", "[1, 0, 0]"), "0.25 s"));
  const Scene s = load_case(d.str());
  const RunOptions o = quiet_in(d);
  const RunReport r = run_scene(s, o);
  ASSERT_TRUE(r.complete) << r.message;
  ASSERT_EQ(r.reduced.size(), 1u) << r.reduce_message;
  const ReducedRow& row = r.reduced.front();
  const double m = ball_mass(), w = 2 * kPi * 20;
  std::printf("  glued mass: M_eff %.9g kg (mass %.9g), C_eff/(m w) %.3g, %g cycles, %g impacts per cycle\n", row.M_eff, m,
              row.C_eff / (m * w), row.cycles, row.impacts_per_cycle);
  EXPECT_NEAR(row.M_eff / m, 1.0, 1e-4);
  EXPECT_LT(std::abs(row.C_eff) / (m * w), 1e-4);
  EXPECT_NEAR(row.bag_mass, m, 1e-12);
  EXPECT_NEAR(row.cavity_amplitude, 1e-4, 1e-9);
  EXPECT_GE(row.cycles, 3);
  // reduced.csv holds the same row, and `bagdem reduce` writes it again identically.
  const std::vector<ReducedRow> back = read_reduced_csv(d.path / "out" / "reduced.csv");
  ASSERT_EQ(back.size(), 1u);
  EXPECT_NEAR(back.front().M_eff, row.M_eff, 1e-12 * m);
  const std::string written = bagdem::testing::slurp(d.path / "out" / "reduced.csv");
  const auto cli = bagdem::testing::run_bagdem({"reduce", d.str()}, d.path);
  EXPECT_EQ(cli.code, 0) << cli.err;
  EXPECT_NE(cli.out.find("M_eff/M_bag"), std::string::npos) << cli.out;
  EXPECT_EQ(bagdem::testing::slurp(d.path / "out" / "reduced.csv"), written);
  // Without the energy tallies (they do not change the motion) the run reduces the same.
  RunOptions quiet = quiet_in(d);
  quiet.out_dir = (d.path / "out-no-energy").string();
  const RunReport r2 = run_scene(load_case(d.str(), {"output.energy=false"}), quiet);
  ASSERT_EQ(r2.reduced.size(), 1u) << r2.reduce_message;
  EXPECT_EQ(r2.reduced.front().M_eff, row.M_eff);
}

// The squeezed ball in the cavity of an SDOF primary: a mass m on the structure. The sweep's
// reduction finds M_eff = m, and the continuum model (with that M_eff and C_eff) gives the response
// the DEM produced, as does the exact SDOF with M_p + m.
TEST(Reduce, SweepReducesAGluedMassAndTheModelReproducesTheResponse) {
  TempDir d;
  const double M = 0.5, fn = 30, zeta = 0.2, K = M * std::pow(2 * kPi * fn, 2);
  d.write("case.toml", squeezed_ball(steady_sdof_sweep(M, K, zeta, {{"frequencies", "[25, 30, 35]"}}), "0.1 s"));
  const Scene s = load_case(d.str());
  const RunOptions o = quiet_in(d);
  const SteppedSineReport r = run_stepped_sine(s, o);
  ASSERT_TRUE(r.complete) << r.message;
  ASSERT_EQ(r.reduced.size(), 3u);
  ASSERT_EQ(r.compare.size(), 3u);
  const double m = ball_mass(), C = 2 * zeta * std::sqrt(K * M);
  for (std::size_t k = 0; k < 3; ++k) {
    const ReducedRow& row = r.reduced[k];
    const CompareRow& c = r.compare[k];
    const double w = 2 * kPi * row.frequency;
    const double exact = 0.5 / std::abs(std::complex<double>(K - w * w * (M + m), w * C));
    std::printf("  %.3f Hz: M_eff/m %.6f, C_eff/(m w) %.2g; |Y| DEM %.6e, modal model %.6e (%+.2e), Eq. 7 %.6e, exact SDOF %.6e\n",
                row.frequency, row.M_eff / m, row.C_eff / (m * w), c.dem_response, c.model_response, c.model_error,
                c.eq7_response, exact);
    EXPECT_NEAR(row.M_eff / m, 1.0, 1e-4);
    EXPECT_LT(std::abs(row.C_eff) / (m * w), 1e-5);
    EXPECT_LT(std::abs(c.model_error), 1e-5);
    EXPECT_NEAR(c.dem_response, exact, 1e-5 * exact);
    EXPECT_NEAR(c.eq7_response, exact, 1e-5 * exact);  // Eq. (7) with the real mass and no bag damping
  }
  for (const char* f : {"reduced.csv", "compare.csv", "peaks.csv", "bare_curve.csv", "sweep.csv"})
    EXPECT_TRUE(fs::exists(d.path / "out" / f)) << f;
}

// A single ball launched at a wall: the drop test returns the pair law's restitution at that speed.
TEST(Reduce, DropTestOfOneBallGivesTheContactRestitution) {
  TempDir d;
  d.write("case.toml", steel_scene("0.1 s", kNoGravity)
                           .interactions(0.6, 0.3)
                           .box("steel", "[-0.01, -0.01, -0.01]", "[0.01, 0.01, 0.01]")
                           .harmonic("1 mm", "20 Hz", "[1, 0, 0]")
                           .placed("ball", "steel", "4 mm", "[[-0.002, 0, 0]]"));
  const Scene s = load_case(d.str());
  const DropResult r = run_drop_test(s, 0.2, d.path / "out", true);
  std::printf("  drop: %.4f m/s -> %.4f m/s, e_drop %.5f (requested 0.6), contact %.3g us, gap %.3g mm\n", r.v_before, r.v_after,
              r.restitution, 1e6 * r.duration, 1e3 * r.gap);
  EXPECT_NEAR(r.v_before, 0.2, 1e-9);
  EXPECT_NEAR(r.gap, 0.010, 1e-9);  // launched across the larger gap: +x, from x = 0 to the wall at 10 mm
  EXPECT_NEAR(r.restitution, 0.6, 0.006);  // the calibrated law returns e within 1% at this speed
  EXPECT_TRUE(fs::exists(d.path / "out" / "drop.csv"));
}

TEST(Reduce, ExportRoundTripAndRefusals) {
  TempDir d;
  fs::create_directories(d.path / "run");
  ReducedRow a, b;
  a.frequency = 20, a.M_eff = 0.0123456789012, a.C_eff = 1.5, a.e_impact = 0.31, a.e_drop = std::nan("");
  b.frequency = 25, b.M_eff = 0.02, b.C_eff = -0.25, b.e_impact = std::nan(""), b.gamma = 3.5;
  write_reduced_csv(d.path / "run" / "reduced.csv", {a, b});
  const std::vector<std::string> written = export_reduced((d.path / "run").string(), "", {"csv", "json", "h5"});
  ASSERT_EQ(written.size(), 3u);
  const TextTable in = read_text_table(d.path / "run" / "reduced.csv"), out = read_text_table(d.path / "run" / "export.csv");
  ASSERT_EQ(out.rows.size(), 2u);
  for (const ExportColumn& c : export_columns()) {
    const std::size_t i = in.find(c.name), j = out.find(c.name);
    ASSERT_LT(j, out.names.size()) << c.name;
    EXPECT_EQ(out.units[j], in.units[i]) << c.name;
    for (std::size_t r = 0; r < 2; ++r) EXPECT_EQ(out.rows[r][j], in.rows[r][i]) << c.name;
  }
  // HDF5: the numbers equal what the CSV holds, with units.
  {
    const hid_t f = H5Fopen((d.path / "run" / "export.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    const auto m = bagdem::testing::read_doubles(f, "/export/M_eff");
    EXPECT_EQ(m.values, (std::vector<double>{0.0123456789012, 0.02}));
    const auto fr = bagdem::testing::read_doubles(f, "/export/frequency");
    EXPECT_EQ(fr.values, (std::vector<double>{20, 25}));
    EXPECT_EQ(bagdem::testing::unit_of(f, "/export/M_eff"), "kg");
    const hid_t ds = H5Dopen2(f, "/export/M_eff", H5P_DEFAULT);
    ASSERT_GE(ds, 0);
    EXPECT_NE(bagdem::testing::read_string_attribute(ds, "description").find("effective mass"), std::string::npos);
    H5Dclose(ds);
    H5Fclose(f);
  }
  // JSON: Python reads it back to the same numbers (NaN as null).
  const std::string py = "python3 -c \"import json,sys; d=json.load(open(sys.argv[1])); r=d['rows']; "
                         "assert r[0]['M_eff']==0.0123456789012 and r[1]['C_eff']==-0.25 and r[0]['e_drop'] is None; "
                         "assert [c['unit'] for c in d['columns'] if c['name']=='C_eff']==['N s/m']\" " +
                         bagdem::testing::shell_quote(written[1]);
  EXPECT_EQ(std::system(py.c_str()), 0);
  // A directory without reduced.csv, and reduce of a run that does not exist: exit 2 with the file named.
  const auto none = bagdem::testing::run_bagdem({"export", (d.path / "nothing").string()}, d.path);
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("reduced.csv"), std::string::npos) << none.err;
  d.write("case.toml", squeezed_ball(CaseText().set("cavity.motion", {{"kind", quoted("harmonic")}, {"amplitude", "0.1 mm"}, {"frequency", "20 Hz"}}),
                                     "0.1 s"));
  const auto unreduced = bagdem::testing::run_bagdem({"reduce", d.str()}, d.path);
  EXPECT_EQ(unreduced.code, 2);
  EXPECT_NE(unreduced.err.find("results.h5"), std::string::npos) << unreduced.err;
}
