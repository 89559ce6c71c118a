// Confidence intervals of the reduced figures: over the correlated cycles of one run, and over the
// perturbed starts of an ensemble.
//
// Cycles of a granular damper are not independent repeats: the bed carries its state from one
// cycle to the next, so the naive standard error sd / sqrt(n) understates the uncertainty. The
// per-cycle values are therefore grouped in batches of consecutive cycles and the batch means are
// treated as the independent repeats (the method of batch means; Flegal & Jones, Ann. Statist. 38,
// 2010, with B = floor(sqrt(n)) batches of b = floor(n / B) cycles, the batch size that makes the
// estimator consistent): with x_bar_k the batch means,
//     se   = sd(x_bar_1 .. x_bar_B) / sqrt(B)
//     ci95 = t_{0.975, B-1} se                    (Student t, B - 1 degrees of freedom)
// The n - B b oldest cycles are left out of the batches (the end of the window is the steadiest).
// An ensemble of S perturbed starts (seeds) gives S independent means m_s: their interval
//     ci95 = t_{0.975, S-1} sd(m_1 .. m_S) / sqrt(S)
// covers both the cycle-to-cycle scatter and the start-to-start spread of a chaotic bed.
#pragma once
#include <cstddef>
#include <vector>

namespace bagdem {

// t_{0.975, dof}: the two-sided 95% quantile of Student's t with dof >= 1 degrees of freedom
// (exact to 4 decimals from tables up to 10; the Cornish-Fisher expansion above, Abramowitz &
// Stegun 26.7.5, within 1e-4). NaN for dof < 1.
double student_t_975(std::size_t dof);

struct Interval {
  double mean = 0;          // over all values (unit: as the values)
  double se = 0;            // standard error of the mean (unit: as the values); NaN with too few values
  double ci95 = 0;          // half-width of the 95% interval (unit: as the values); NaN with too few values
  std::size_t repeats = 0;  // the independent repeats behind se: batches, or starts
};

// Batch means over consecutive, possibly correlated values (cycles). Needs at least 4 values for
// an interval (2 batches of 2); with fewer, se and ci95 are NaN. Throws nothing; NaN values make
// every figure NaN.
Interval batch_means_interval(const std::vector<double>& values);

// The interval of independent values (the means of an ensemble's starts). At least 2 values; with
// fewer, se and ci95 are NaN.
Interval independent_interval(const std::vector<double>& values);

}  // namespace bagdem
