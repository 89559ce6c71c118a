// The growth benchmark's fit (run/bench.hpp): the exponent of y ~ x^a by least squares in log-log.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "bagdem/run/bench.hpp"

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
