// Confidence intervals of the reduced figures (reduce/interval.hpp): Student's t quantiles against
// tables, the interval of independent values against a hand computation, and batch means against
// their purpose: on correlated series (first-order autoregressive, as a bed's cycles) the 95%
// interval covers the true mean close to 95% of the time, where the naive sd/sqrt(n) interval
// does not.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "bagdem/reduce/interval.hpp"

using namespace bagdem;

TEST(Interval, StudentQuantilesMatchTheTables) {
  // t_{0.975, dof} from the tables (Abramowitz & Stegun 26.10; R's qt(0.975, dof)).
  const std::pair<std::size_t, double> table[] = {{1, 12.7062}, {2, 4.3027}, {4, 2.7764}, {9, 2.2622}, {10, 2.2281},
                                                  {11, 2.2010}, {15, 2.1314}, {20, 2.0860}, {30, 2.0423}, {60, 2.0003},
                                                  {120, 1.9799}, {1000, 1.9623}};
  for (const auto& [dof, t] : table) EXPECT_NEAR(student_t_975(dof), t, 1.5e-4) << "dof " << dof;
  EXPECT_TRUE(std::isnan(student_t_975(0)));
}

TEST(Interval, IndependentValuesByHand) {
  // 1..5: mean 3, sd sqrt(2.5), se sqrt(2.5/5), ci95 = t_{0.975,4} se.
  const Interval r = independent_interval({1, 2, 3, 4, 5});
  EXPECT_DOUBLE_EQ(r.mean, 3);
  EXPECT_NEAR(r.se, std::sqrt(0.5), 1e-14);
  EXPECT_NEAR(r.ci95, 2.7764 * std::sqrt(0.5), 1e-4);
  EXPECT_EQ(r.repeats, 5u);
  EXPECT_TRUE(std::isnan(independent_interval({1.0}).ci95));
}

TEST(Interval, BatchMeansByHand) {
  // 10 values: 3 batches of 3 after the oldest one; batch means 2, 5, 8 -> se = 3 / sqrt(3).
  const Interval r = batch_means_interval({100, 1, 2, 3, 4, 5, 6, 7, 8, 9});
  EXPECT_DOUBLE_EQ(r.mean, 14.5);  // the mean keeps every value
  EXPECT_EQ(r.repeats, 3u);
  EXPECT_NEAR(r.se, 3 / std::sqrt(3.0), 1e-13);
  EXPECT_NEAR(r.ci95, 4.3027 * 3 / std::sqrt(3.0), 1e-3);
  EXPECT_TRUE(std::isnan(batch_means_interval({1, 2, 3}).ci95));  // too few for two batches of two
}

namespace {

// The share of `reps` AR(1) series x_k = rho x_{k-1} + eps_k (n values after a burn-in; true mean 0)
// whose interval covers 0: by batch means, and by the naive 1.96 sd / sqrt(n).
std::pair<double, double> coverage(std::size_t n, double rho, int reps, std::mt19937_64& rng) {
  std::normal_distribution<double> eps;
  int batch = 0, naive = 0;
  for (int r = 0; r < reps; ++r) {
    std::vector<double> x;
    double y = eps(rng) / std::sqrt(1 - rho * rho);  // stationary start
    for (std::size_t k = 0; k < n; ++k) x.push_back(y = rho * y + eps(rng));
    const Interval b = batch_means_interval(x);
    batch += std::abs(b.mean) <= b.ci95;
    double ss = 0;
    for (double v : x) ss += (v - b.mean) * (v - b.mean);
    naive += std::abs(b.mean) <= 1.96 * std::sqrt(ss / static_cast<double>(n - 1) / static_cast<double>(n));
  }
  return {static_cast<double>(batch) / reps, static_cast<double>(naive) / reps};
}

}  // namespace

TEST(Interval, BatchMeansCoverCorrelatedCycles) {
  std::mt19937_64 rng(29);
  const int reps = 4000;
  struct Case {
    std::size_t n;
    double rho, at_least;
  };
  // Independent cycles: both near 95%. Correlated ones: batch means stay near 95% (short windows
  // lose some, the batches being short against the correlation), the naive interval collapses.
  for (const Case c : {Case{100, 0.0, 0.92}, Case{100, 0.5, 0.91}, Case{10, 0.3, 0.91}, Case{400, 0.7, 0.91}}) {
    const auto [batch, naive] = coverage(c.n, c.rho, reps, rng);
    std::printf("  n = %zu, rho = %.1f: coverage of the 95%% interval %.3f by batch means, %.3f naive\n", c.n, c.rho, batch, naive);
    EXPECT_GE(batch, c.at_least) << "n " << c.n << " rho " << c.rho;
    EXPECT_LE(batch, 0.99) << "n " << c.n << " rho " << c.rho;  // not wider than it needs to be
    if (c.rho >= 0.5) EXPECT_LT(naive, 0.80) << "the naive interval should miss correlated cycles";
  }
}
