// Test support of the sweep restart suites (test_stepped_sine_restart.cpp, test_faults.cpp): a small
// coupled sweep and the comparison of two sweeps' outputs.
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>

#include "case_texts.hpp"
#include "results_compare.hpp"
#include "support.hpp"

namespace bagdem::testing {

// A 10-mm steel ball rattling (0.2 mm each side) in the cavity of a 30-Hz SDOF primary, settled
// for 2 ms, swept at three frequencies and refined once at the peak.
inline std::string rattling_ball_sweep(int chains = 0) {
  CaseText c = steel_ball_between_planes("0.1 s", 0.0052, "0.01")
      .set("simulation", "settle", "2 ms")
      .placed("ball", "steel", "0.01", "[[0.0001, 0, 0]]", "[[0.05, 0, 0]]")
      .sdof(0.5, "17765.287921960843", 0.05)
      .set("primary", {{"direction", "[1, 0, 0]"}, {"axis", "[0, 1, 0]"}})
      .set("excitation", {{"kind", quoted("stepped-sine")}, {"amplitude", "0.5 N"}, {"frequencies", "[26, 30, 34]"},
                          {"refine", 1}, {"min_cycles", 4}, {"reduce_cycles", 4}, {"max_cycles", 8}});
  if (chains > 0) c.set("excitation", "chains", chains);  // else the default
  return c;
}

// sweep.csv without its last column (wall_time: the machine's, not the sweep's).
inline std::string without_wall_time(const std::string& csv) {
  std::istringstream in(csv);
  std::string line, out;
  while (std::getline(in, line)) out += line.substr(0, line.rfind(',')) + "\n";
  return out;
}

// Two sweeps' outputs are the same but for the time they took.
inline void expect_same_sweep(const std::filesystem::path& a, const std::filesystem::path& b) {
  auto A = read_all_datasets(a / "results.h5"), B = read_all_datasets(b / "results.h5");
  EXPECT_TRUE(A.count("/sweep/wall_time") && A.count("/sweep/frequency") && A.count("/frames/position"));
  A.erase("/sweep/wall_time"), B.erase("/sweep/wall_time");
  expect_same_datasets(A, a / "results.h5", B, b / "results.h5");
  const std::string sa = slurp(a / "sweep.csv"), sb = slurp(b / "sweep.csv");
  EXPECT_NE(sa.find("wall_time"), std::string::npos);
  EXPECT_EQ(without_wall_time(sb), without_wall_time(sa));
  EXPECT_FALSE(slurp(a / "reduced.csv").empty());
  EXPECT_EQ(slurp(b / "reduced.csv"), slurp(a / "reduced.csv"));
  EXPECT_EQ(slurp(b / "peaks.csv"), slurp(a / "peaks.csv"));
  EXPECT_FALSE(std::filesystem::exists(b / "checkpoint.bin"));
  EXPECT_FALSE(std::filesystem::exists(b / "results.h5.part"));
}

}  // namespace bagdem::testing
