// The growth benchmark's fit (run/bench.hpp): the exponent of y ~ x^a by least squares in log-log;
// and tools/growth_peers.py, the tiling and fit of tools/growth-peers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
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

// tools/growth_peers.py, the helper of tools/growth-peers (growth side by side with LIGGGHTS and
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
  const std::string tool = shell_quote(std::string(BAGDEM_SOURCE_DIR) + "/tools/growth_peers.py");
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
