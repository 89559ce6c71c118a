// First-harmonic projection of sampled signals, and the contents' effective mass and damping.
//
// Conventions: SI units; a harmonic signal is y(t) = Re(Y e^{i w t}), w = 2 pi f (as in
// structure/response.hpp), so y = Re(Y) cos(w t) - Im(Y) sin(w t). Samples are uniformly spaced by
// Delta and come in two kinds (results.h5, io/results_file.hpp):
//   Sampling::point          y_k = y(t_k)                          (the cavity position)
//   Sampling::interval_mean  y_k = (1/Delta) integral_{t_k - Delta}^{t_k} y dt   (the contents' force:
//                            impulse / interval, so impacts are not aliased; docs/reference-study.md, section 5)
//
// The fit. Each whole cycle is fitted by linear least squares on the basis {1, c_k, s_k}:
//   point:          c_k + i s_k = e^{i w t_k}
//   interval_mean:  c_k + i s_k = (1/Delta) integral_{t_k-Delta}^{t_k} e^{i w t} dt
//                               = e^{i w (t_k - Delta/2)} sin(w Delta/2) / (w Delta/2)
// and Y = a - i b for the fitted y ~ offset + a c_k + b s_k. The two bases span the same functions
// (the interval-mean basis is the point basis times one complex constant), so the fitted curve is the
// same and only the reading of Y differs: the interval-mean basis recovers a clean interval-mean
// signal exactly, while the point basis would return it multiplied by sinc(w Delta/2) e^{-i w Delta/2}
// (amplitude low by (w Delta)^2/24, phase late by half an interval; the phase lag alone raises C_eff
// by (w Delta/2) w M_eff, 20% for 200 samples per period in the test).
// Least squares rather than a discrete Fourier sum: a signal of the form offset + Re(Y e^{iwt}) is
// recovered exactly over any span of samples, whole cycle or not; other harmonics and noise leak in
// only through the cycle's window: not at all when a cycle is a whole number N of samples and the
// harmonic's order m is not +-1 modulo N (discrete orthogonality; m = N +- 1 aliases onto the first
// harmonic whatever the method).
//
// Cycles. P = 1 / (f Delta) samples per period (at least 3). The first analysed sample i0 is the first
// with t >= t_skip; cycle j holds the samples i0 + n with n in [j P, (j + 1) P), i.e. the samples
// whose time lies in [t_c, t_c + T) with t_c = t_i0 + j T; the boundaries j P are taken with a
// tolerance of 1e-6 of a sample, so a whole P gives exactly P samples per cycle whatever the
// round-off in T / Delta. When P is not whole, cycles hold floor(P) or ceil(P) samples, each
// boundary within one sample of t_i0 + j T (the cycles do not drift), and the fit uses the samples'
// true times, so a clean first harmonic is still exact; other harmonics then leak in by O(1/P).
// Only the whole cycles that end at or before the last sample are used.
//
// Uncertainty: the amplitude is the mean of the per-cycle Y_j; its standard error is (sd of Re Y_j,
// sd of Im Y_j) / sqrt(n) (sample standard deviation, n - 1), which assumes uncorrelated cycles. The
// effective parameters below take batch means instead (reduce/interval.hpp): a granular bed carries
// its state from cycle to cycle.
//
// Effective parameters (docs/reference-study.md, section 5; the study's Eq. (3) with the contents as M_b, C_b):
// the contents' force on the cavity F ~ -M_eff x'' - C_eff x', so for each cycle
//     F_j = (w^2 M_eff - i w C_eff) X_j,  M_eff = Re(F_j / X_j) / w^2,  C_eff = -Im(F_j / X_j) / w,
// the energy the contents dissipate per cycle E = -integral F x' dt = -pi Im(F_j conj X_j)
// = pi C_eff w |X_j|^2, and the loss factor C_eff / (M_eff w). For a prescribed x = X sin(w t) these
// are the projections of docs/reference-study.md, section 5: M_eff = (2/(nT w^2 X)) integral F sin(wt) dt and
// C_eff = -(2/(nT w X)) integral F cos(wt) dt.
#pragma once
#include <complex>
#include <cstddef>
#include <vector>

namespace bagdem {

enum class Sampling { point, interval_mean };  // y_k = y(t_k), or y_k = mean of y over [t_k - Delta, t_k]

// The sample interval Delta of uniformly spaced, increasing times (unit: s): the mean spacing
// (t_last - t_0) / (S - 1), equal to t_1 - t_0 for uniform samples. Throws std::invalid_argument for
// fewer than 2 samples, a non-positive spacing, or a sample further than 1e-6 Delta from t_0 + k Delta.
double sample_interval(const std::vector<double>& t);

struct HarmonicFit {
  std::complex<double> amplitude;              // Y: mean over the cycles (unit: as y)
  std::complex<double> standard_error;         // standard error of the mean over cycles, (SE of Re, SE of Im);
                                               // NaN with one cycle
  double offset = 0;                           // mean value (constant term of the fit, mean over cycles) (unit: as y)
  std::vector<std::complex<double>> per_cycle; // Y of each whole cycle (unit: as y)
  double t_begin = 0, t_end = 0;               // the span fitted: t_i0 and t_i0 + cycles T (unit: s)
};

// First harmonic of y at frequency f (Hz) over the whole cycles that fit in [t_skip, last sample].
// Throws std::invalid_argument for sizes that differ, non-uniform t, f <= 0, fewer than 3 samples
// per period, or fewer than one whole cycle.
HarmonicFit first_harmonic(const std::vector<double>& t, const std::vector<double>& y, double f, double t_skip,
                           Sampling sampling);

struct EffectiveParameters {
  double frequency = 0;                // f (unit: Hz)
  std::complex<double> displacement;   // X_hat, mean over the cycles (unit: m)
  std::complex<double> force;          // F_hat, mean over the cycles (unit: N)
  // Each with the standard error and the 95% half-width of batch means over the cycles
  // (reduce/interval.hpp): cycles of a granular bed are correlated.
  double mass = 0, mass_se = 0, mass_ci95 = 0;           // M_eff (unit: kg)
  double damping = 0, damping_se = 0, damping_ci95 = 0;  // C_eff (unit: N s/m)
  double energy_per_cycle = 0, energy_per_cycle_se = 0, energy_per_cycle_ci95 = 0;  // pi C_eff w |X|^2, dissipated by the contents (unit: J)
  double loss_factor = 0;              // C_eff / (M_eff w), from the means (unit: 1)
  std::size_t cycles = 0;              // whole cycles used
};

// Effective mass and damping of the contents from the cavity displacement x (point samples, or
// interval means as results.h5 records it: displacement_sampling) and the contents' force on the
// cavity F (interval means), both the components along the excitation
// direction, at times t. Per cycle, then averaged; standard errors and intervals by batch means over
// the cycles (NaN with fewer than 4 cycles). Throws std::invalid_argument as first_harmonic
// does, and when a cycle of x has no first harmonic (X_j = 0).
EffectiveParameters effective_parameters(const std::vector<double>& t, const std::vector<double>& x,
                                         const std::vector<double>& force, double f, double t_skip,
                                         Sampling displacement_sampling = Sampling::point);

// Phase theta of a cavity motion written |X| cos(theta) (docs/reference-study.md, section 2: the study's phase of
// impact phi is theta at the impact): for x = Re(X_hat e^{i w t}), theta = w t + arg(X_hat), wrapped
// to [0, 2 pi) (unit: rad).
double motion_phase(std::complex<double> X_hat, double w, double t);

}  // namespace bagdem
