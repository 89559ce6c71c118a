// Confidence intervals over correlated cycles and over independent starts (reduce/interval.hpp).
#include "bagdem/reduce/interval.hpp"

#include <cmath>
#include <limits>

namespace bagdem {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double mean_of(const std::vector<double>& x) {
  double s = 0;
  for (double v : x) s += v;
  return s / static_cast<double>(x.size());
}

// Sample standard deviation (n - 1), n >= 2.
double sd_of(const std::vector<double>& x, double mean) {
  double ss = 0;
  for (double v : x) ss += (v - mean) * (v - mean);
  return std::sqrt(ss / static_cast<double>(x.size() - 1));
}

}  // namespace

double student_t_975(std::size_t dof) {
  // Tables of t_{0.975, dof} (e.g. Abramowitz & Stegun, Table 26.10).
  static constexpr double kTable[] = {12.7062, 4.3027, 3.1824, 2.7764, 2.5706, 2.4469, 2.3646, 2.3060, 2.2622, 2.2281};
  if (dof < 1) return kNaN;
  if (dof <= std::size(kTable)) return kTable[dof - 1];
  // Cornish-Fisher expansion about the normal quantile z (A&S 26.7.5).
  const double z = 1.959963984540054, n = static_cast<double>(dof);
  const double z3 = z * z * z, z5 = z3 * z * z, z7 = z5 * z * z, z9 = z7 * z * z;
  return z + (z3 + z) / (4 * n) + (5 * z5 + 16 * z3 + 3 * z) / (96 * n * n) +
         (3 * z7 + 19 * z5 + 17 * z3 - 15 * z) / (384 * n * n * n) +
         (79 * z9 + 776 * z7 + 1482 * z5 - 1920 * z3 - 945 * z) / (92160 * n * n * n * n);
}

Interval batch_means_interval(const std::vector<double>& values) {
  Interval r;
  r.se = r.ci95 = kNaN;
  if (values.empty()) {
    r.mean = kNaN;
    return r;
  }
  r.mean = mean_of(values);
  const std::size_t n = values.size();
  if (n < 4) return r;
  const auto B = static_cast<std::size_t>(std::floor(std::sqrt(static_cast<double>(n))));
  const std::size_t b = n / B, skip = n - B * b;
  std::vector<double> batch(B, 0.0);
  for (std::size_t k = 0; k < B; ++k) {
    for (std::size_t j = 0; j < b; ++j) batch[k] += values[skip + k * b + j];
    batch[k] /= static_cast<double>(b);
  }
  r.repeats = B;
  r.se = sd_of(batch, mean_of(batch)) / std::sqrt(static_cast<double>(B));
  r.ci95 = student_t_975(B - 1) * r.se;
  return r;
}

Interval independent_interval(const std::vector<double>& values) {
  Interval r;
  r.se = r.ci95 = kNaN;
  r.mean = values.empty() ? kNaN : mean_of(values);
  r.repeats = values.size();
  if (values.size() < 2) return r;
  r.se = sd_of(values, r.mean) / std::sqrt(static_cast<double>(values.size()));
  r.ci95 = student_t_975(values.size() - 1) * r.se;
  return r;
}

}  // namespace bagdem
