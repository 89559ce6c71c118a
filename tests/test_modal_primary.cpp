// primary.kind = "modal" (structure/modal_table.hpp, src/structure/primary_modal.cpp) and
// `bagdem modes`, which writes a primary's modal table:
//  - fed cases/stepped-beam's modes (an fe-beam; written by this build), the modal case has the
//    fe-beam's bare receptance within 1e-9 (relative) at every frequency of a fine scan over its
//    four modes; the shipped table (written on another CPU) within 1e-3;
//  - a free-free beam (rigid-body modes on their suspension) with a cavity mass, written and read
//    back, the same: frequencies, damping ratios, shapes, mode numbering and the load's fit;
//  - an sdof written as one row of modal mass M_p gives the sdof's receptance;
//  - bad tables are refused naming the file, the column and what is allowed;
//  - `bagdem modes` writes the shipped table (to the CPU-dependent digits), and from the modal case
//    itself byte for byte what it read, and refuses a case without a structure.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/structure/modal_table.hpp"
#include "support.hpp"

using namespace bagdem;
using bagdem::testing::CmdResult;
using bagdem::testing::run_bagdem;
using bagdem::testing::slurp;
using bagdem::testing::TempDir;

namespace {

const std::string kCases = BAGDEM_CASES_DIR;

// The largest relative difference of the bare receptances over a logarithmic scan of [lo, hi] Hz
// (n points, the natural frequencies of `a` added: the peaks themselves).
double worst_receptance_difference(const Primary& a, const Primary& b, double lo, double hi, int n) {
  std::vector<double> f;
  for (int k = 0; k <= n; ++k) f.push_back(lo * std::pow(hi / lo, static_cast<double>(k) / n));
  for (double fk : a.bare_frequencies()) f.push_back(fk);
  double worst = 0;
  for (double x : f) {
    const double w = 2 * std::numbers::pi * x;
    const std::complex<double> ha = a.bare_receptance(w), hb = b.bare_receptance(w);
    worst = std::max(worst, std::abs(ha - hb) / std::abs(ha));
  }
  return worst;
}

// cases/stepped-beam-modal's text with its table at `table` (an absolute path).
std::string modal_case_with(const std::string& table) {
  std::string t = slurp(kCases + "/stepped-beam-modal/case.toml");
  const std::size_t at = t.find("table = \"modes.csv\"");
  t.replace(at, std::string("table = \"modes.csv\"").size(), "table = \"" + table + "\"");
  return t;
}

std::string refusal(const TempDir& d, const std::string& table_text, const std::vector<std::string>& sets = {}) {
  d.write("modes.csv", table_text);
  d.write("case.toml", modal_case_with((d.path / "modes.csv").string()));
  try {
    load_case(d.str(), sets);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

}  // namespace

// Fed the fe-beam's own modes (written by this build), the modal primary gives its bare receptance
// to 1e-9. The shipped table, written on another machine, agrees to 1e-3: the FE eigenproblem's
// smallest eigenvalues carry an absolute error of order eps times the largest (the stepped beam's
// stiffness spans many decades), and -march=native builds order their sums by the CPU's vector
// width, so mode 1's frequency moves by about 1e-6 relative from one CPU to another (measured 6e-7,
// which moves the receptance near the resonance by 1.2e-4).
TEST(ModalPrimary, ShippedTableGivesTheFeBeamsBareReceptance) {
  const Scene fe = load_case(kCases + "/stepped-beam"), shipped = load_case(kCases + "/stepped-beam-modal");
  TempDir d;
  write_modal_table(d.path / "modes.csv", *fe.primary);
  d.write("case.toml", modal_case_with((d.path / "modes.csv").string()));
  const Scene modal = load_case(d.str());
  ASSERT_TRUE(fe.primary && modal.primary && shipped.primary);
  ASSERT_EQ(modal.primary->kind, "modal");
  ASSERT_EQ(fe.primary->size(), modal.primary->size());
  const double worst = worst_receptance_difference(*fe.primary, *modal.primary, 10, 3000, 4000);
  const double across = worst_receptance_difference(*fe.primary, *shipped.primary, 10, 3000, 4000);
  std::printf("  stepped cantilever, %zu modes: largest relative difference of the bare receptance %.2e (the shipped table: %.2e)\n",
              fe.primary->size(), worst, across);
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(across, 1e-3) << "regenerate the table: bagdem modes cases/stepped-beam --to cases/stepped-beam-modal/modes.csv";
  EXPECT_EQ(fe.bag->balls, modal.bag->balls);
  EXPECT_NEAR(modal.primary->structure_mass, fe.primary->structure_mass, 1e-5 * fe.primary->structure_mass);
}

TEST(ModalPrimary, FreeFreeBeamWithACavityMassIsTheSameReadBack) {
  TempDir d;
  const std::vector<std::string> sets = {"primary.ends=\"free-free\"", "primary.cavity_mass=\"0.01 kg\""};
  const Scene fe = load_case(kCases + "/stepped-beam", sets);
  const Primary& a = *fe.primary;
  write_modal_table(d.path / "modes.csv", a);
  d.write("case.toml", modal_case_with((d.path / "modes.csv").string()));
  const Scene modal = load_case(d.str(), {"primary.cavity_mass=\"0.01 kg\""});
  const Primary& b = *modal.primary;
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    const auto K = static_cast<Eigen::Index>(k);
    EXPECT_EQ(b.rigid_body[k], a.rigid_body[k]) << k;
    EXPECT_EQ(b.elastic_mode_number(k), a.elastic_mode_number(k)) << k;
    EXPECT_NEAR(b.natural_frequency[k], a.natural_frequency[k], 1e-14 * a.natural_frequency[k]);
    EXPECT_EQ(b.damping_ratio[k], a.damping_ratio[k]);
    EXPECT_NEAR(b.at_cavity[K], a.at_cavity[K], 1e-14 * a.at_cavity.cwiseAbs().maxCoeff());
    EXPECT_NEAR(b.slope_at_cavity[K], a.slope_at_cavity[K], 1e-14 * a.slope_at_cavity.cwiseAbs().maxCoeff());
    // The load's quadratic part is the same; its linear part is the slope at x_b, where the fe-beam
    // takes the chord over the cavity (they differ by l^2 phi''' / 6).
    EXPECT_NEAR(b.load_fit(K, 2), a.load_fit(K, 2), 1e-12 * a.load_fit.col(2).cwiseAbs().maxCoeff());
  }
  EXPECT_TRUE(b.rigid_body[0] && b.rigid_body[1]);
  EXPECT_EQ(b.dof_names[2], "mode 1");
  const double worst = worst_receptance_difference(a, b, 0.5, 3000, 4000);
  std::printf("  free-free, %zu DOFs (2 rigid), cavity mass 10 g: largest relative difference %.2e\n", a.size(), worst);
  EXPECT_LT(worst, 1e-9);
}

TEST(ModalPrimary, AnSdofIsOneRowOfItsMass) {
  TempDir d;
  const Primary sdof = make_sdof_primary(0.5, 2e5, 3.0, 0.0);
  write_modal_table(d.path / "modes.csv", sdof);
  const ModalTable t = read_modal_table(d.path / "modes.csv");
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_DOUBLE_EQ(t.rows[0].modal_mass, 0.5);
  const Primary m = make_modal_primary({t, 0.0, 0.5, 0.0, false, "modes.csv"});
  const double worst = worst_receptance_difference(sdof, m, 10, 500, 2000);
  std::printf("  sdof as one row: largest relative difference %.2e\n", worst);
  EXPECT_LT(worst, 1e-12);
}

TEST(ModalPrimary, BadTablesAreRefused) {
  TempDir d;
  const std::string head = "frequency [Hz],damping_ratio [1],modal_mass [kg],shape_attach [1],shape_force [1],shape_response [1]\n";
  struct Case {
    std::string table, expect;
  };
  const std::vector<Case> cases = {
      {"frequency [Hz],damping_ratio [1],modal_mass [kg],shape_attach [1],shape_force [1]\n80,0.01,1,1,1\n",
       "key 'shape_response [1]': column missing from the modal table"},
      {"frequency [rad/s],damping_ratio [1],modal_mass [kg],shape_attach [1],shape_force [1],shape_response [1]\n500,0.01,1,1,1,1\n",
       "key 'frequency' = [rad/s]: must be in [Hz]"},
      {head + "0,0.01,1,1,1,1\n", "key 'frequency' = 0: must be > 0 Hz"},
      {head + "80,0.01,1,1,1,1\n60,0.01,1,1,1,1\n", "must not decrease from row to row"},
      {head + "80,1.2,1,1,1,1\n", "key 'damping_ratio' = 1.2: must be in [0, 1) (row 1)"},
      {head + "80,0.01,0,1,1,1\n", "key 'modal_mass' = 0: must be > 0 kg"},
      {head + "80,0.01,1,x,1,1\n", "key 'shape_attach' = x: must be a finite number (row 1)"},
      {head, "has no modes"},
      {"frequency [Hz],damping_ratio [1],modal_mass [kg],shape_attach [1],shape_force [1],shape_response [1],rigid_body [1]\n80,0.01,1,1,1,1,2\n",
       "key 'rigid_body' = 2: must be 0 or 1"},
  };
  for (const Case& c : cases) {
    const std::string m = refusal(d, c.table);
    EXPECT_NE(m.find("modes.csv"), std::string::npos) << m;
    EXPECT_NE(m.find(c.expect), std::string::npos) << m;
  }
  EXPECT_NE(refusal(d, head + "80,0.01,1,1,1,1\n", {"primary.follow_slope=true"}).find("key 'primary.follow_slope'"), std::string::npos);
  EXPECT_EQ(refusal(d, head + "80,0.01,1,1,1,1\n"), "(accepted)");
  d.write("case.toml", modal_case_with((d.path / "none.csv").string()));
  std::string missing;
  try {
    load_case(d.str());
  } catch (const InputError& e) {
    missing = e.what();
  }
  EXPECT_NE(missing.find("key 'primary.table'"), std::string::npos) << missing;
}

TEST(ModalPrimary, ModesCommandWritesTheShippedTable) {
  TempDir d;
  const std::string to = (d.path / "modes.csv").string();
  const CmdResult r = run_bagdem({"modes", kCases + "/stepped-beam", "--to", to}, d.path);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("4 modes"), std::string::npos) << r.out;
  // The shipped table, to the CPU-dependent digits (ShippedTableGivesTheFeBeamsBareReceptance).
  const ModalTable mine = read_modal_table(to), shipped = read_modal_table(kCases + "/stepped-beam-modal/modes.csv");
  ASSERT_EQ(mine.rows.size(), shipped.rows.size()) << "regenerate: bagdem modes cases/stepped-beam --to cases/stepped-beam-modal/modes.csv";
  for (std::size_t k = 0; k < mine.rows.size(); ++k) {
    EXPECT_NEAR(mine.rows[k].frequency, shipped.rows[k].frequency, 1e-5 * shipped.rows[k].frequency);
    EXPECT_NEAR(mine.rows[k].shape_attach, shipped.rows[k].shape_attach, 1e-5 * std::abs(shipped.rows[k].shape_attach));
  }
  // Read back and written again, the table is the same to the last digit.
  ASSERT_EQ(run_bagdem({"modes", kCases + "/stepped-beam-modal", "--to", to}, d.path).code, 0);
  EXPECT_EQ(slurp(to), slurp(kCases + "/stepped-beam-modal/modes.csv"));
  const CmdResult none = run_bagdem({"modes", kCases + "/box-beanbag", "--to", to}, d.path);
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("modes needs a primary structure"), std::string::npos) << none.err;
}
