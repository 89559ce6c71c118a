// Frequency-response and time-response figures of a primary structure.
//
// Conventions: a harmonic signal is y(t) = Re(Y e^{i w t}); a force F0 sin(w t) is Re(-i F0 e^{i w t});
// the receptance H = Y / F (complex, m/N) and the accelerance -w^2 H (m/s^2/N).
//
// Stepped sine (run/stepped_sine.hpp): each drive frequency is rounded to a whole number N of time steps
// per cycle, and the first harmonic of one cycle's samples is Y = (2/N) sum_n y_n e^{-i theta_n},
// exact for any periodic response with harmonics below N/2 (discrete orthogonality). A frequency
// point is steady when the last K cycles' Y lie within a relative tolerance of the latest.
#pragma once
#include <complex>
#include <cstddef>
#include <deque>
#include <vector>

namespace bagdem {

// Steps per cycle for a requested frequency f (Hz) at step dt (s): N = max(8, round(1/(f dt))); the
// frequency driven is then 1/(N dt).
std::size_t steps_per_cycle(double f, double dt);

// The first harmonic of one drive cycle, Y = (2/N) sum_n y_n e^{-i theta_n} over its N samples
// (y_n after step n, theta_n the force's phase then), with a slow drift taken out. Motion far below
// the drive (a structure swinging on its soft suspension after the contents' release) adds to the
// cycle a drift that the plain sum reads as a first harmonic: a speed v reads as about v / (pi f),
// 1 um at 320 Hz for 1 mm/s, as large as a well-damped mode's response off resonance. The drift
// is measured by the cycle means (a whole cycle's mean holds no harmonic of the drive): through
// this cycle's mean m_c and the two before (same N), a parabola in the sample index, of slope
// s = (3 m_c - 4 m_{c-1} + m_{c-2}) / (2N) and curvature a = (m_c - 2 m_{c-1} + m_{c-2}) / N^2 at
// the cycle's middle u = n - (N+1)/2 (with only m_{c-1}: s = (m_c - m_{c-1}) / N, a = 0; with
// neither, nothing is taken out); its projection (2/N) sum_n (s u + a u^2 / 2) e^{-i theta_n} is
// subtracted. Exact for a periodic response plus a quadratic drift (a periodic response alone: the
// means agree, Y unchanged); a drift at f_d leaves about (2 pi f_d / f)^3 / 10 of its amplitude
// (with one mean before: pi f_d / f of the drift's reading, the backward difference's lag).
class CycleHarmonic {
 public:
  void add(double y, std::complex<double> e_minus_i_theta);  // the next sample, n = 1, 2, ...
  double mean() const;                                         // m_c, the mean of the samples
  // The drift through the previous cycles' means (NaN: no such cycle), per sample: y ~ s u + a u^2 / 2.
  struct Drift {
    double slope = 0, curvature = 0;
    double at(std::size_t n, std::size_t N) const;  // s u + a u^2 / 2 at sample n of N (1-based)
  };
  Drift drift(double before, double before_that) const;
  // Y with the drift's projection removed.
  std::complex<double> harmonic(const Drift& d) const;

 private:
  std::complex<double> sum_{0, 0}, e0_{0, 0}, e1_{0, 0}, e2_{0, 0};  // sum y e, sum e, sum n e, sum n^2 e
  double total_ = 0;
  std::size_t n_ = 0;
};

// Steady state of a sequence of cycle amplitudes Y_i (complex first harmonics). A granular damper's
// response is chaotic from cycle to cycle (scatter of several percent at the impacts, tens of
// percent at mode 3), so single cycles are not compared: the mean of the last K amplitudes, m_b,
// is compared with the mean of the K before, m_a. The point is steady when either
//   (a) |m_b - m_a| <= rel_tol |m_b| (a periodic response, or a transient that has died out), or
//   (b) the two means do not differ beyond the cycles' own scatter: a two-sample test of equal
//       means at the 5 % level, |m_b - m_a|^2 <= chi2_{2, 0.95} (s_a^2 + s_b^2) / (2 K), with
//       s^2 = sum |Y_i - m|^2 / (K - 1) each half's scatter of the complex amplitude (its real and
//       imaginary parts taken as of equal variance: |d|^2 / (var / 2) ~ chi2 with 2 degrees of
//       freedom; chi2_{2, 0.95} = -2 ln 0.05 = 5.99). Cycles are correlated (the bed carries its
//       state), which makes this s / sqrt(K) small and the test strict: it errs towards running on.
// (b) applies only to scatter that looks like chaos, not like a transient. A linear structure's
// transient is a free vibration beating against the forced response: it rotates the first
// harmonic by 2 pi (f_n - f)/f a cycle and decays, and the halves' means can agree by chance in
// mid-beat. So (b) asks that the scatter be stationary and uncorrelated: the first half's scatter
// not above the second's by more than a one-sided F test at 10 % allows (a decaying beat), and the
// deviations' lag-1 autocorrelation over the window (about each half's mean) not above 0.3
// (kMaxScatterCorrelation; a slow beat), and their moduli varying as noise's do, mean |d|^4 /
// (mean |d|^2)^2 at least 1.3 (kMinScatterKurtosis; 2 for complex Gaussian scatter, 1 for a phasor
// turning at a constant modulus: a fast beat, the free vibration of a mode far from the drive).
// Otherwise (a) alone decides, as for a smooth decay.
// (b) lets a chaotic response settle where (a) would wait for a drift below the scatter of a
// K-cycle mean; a slow drift smaller than that scatter passes it, and shows in the interval the
// sweep reports for the window (receptance_ci95, batch means).
inline constexpr double kMaxScatterCorrelation = 0.3, kMinScatterKurtosis = 1.3;
class SteadyStateDetector {
 public:
  SteadyStateDetector(std::size_t K, double rel_tol) : K_(K), tol_(rel_tol) {}
  void add(std::complex<double> Y);
  bool steady() const;
  // |mean_last - mean_before| / |mean_last| (1 until 2K values were seen).
  double last_change() const;
  // Whether the halves' means agree within their scatter (test (b); false until 2K values).
  bool within_scatter() const;
  // Mean of the last K amplitudes (of those seen, when fewer).
  std::complex<double> mean() const;
  // Scatter of the last K amplitudes: RMS of |Y_i - mean| / |mean|.
  double spread() const;

 private:
  std::complex<double> block_mean(std::size_t first, std::size_t count) const;
  std::size_t K_;
  double tol_;
  std::deque<std::complex<double>> window_;  // the last 2K values
};

// Analytic receptance of a viscously damped SDOF: 1 / (K - w^2 M + i w C) (unit: m/N).
std::complex<double> sdof_receptance(double M, double C, double K, double w);

// Peak reduction: dB = 20 log10(bare_peak / damped_peak); percent = 100 (1 - 10^(-dB/20))
// (docs/reference-study.md, section 3).
double reduction_db(double bare_peak, double damped_peak);
double reduction_percent(double db);

// Peak of |H| over sampled frequencies inside [f_lo, f_hi]: the largest sample, refined by the
// parabola through it and its two neighbours in (f^2, 1/|H|^2) when it is not at an end of the
// range; exact for a single mode (a viscously damped SDOF) at any spacing of the samples.
struct Peak {
  double frequency = 0, magnitude = 0;  // (unit: Hz, as the magnitudes)
};
Peak find_peak(const std::vector<double>& f, const std::vector<double>& mag, double f_lo, double f_hi);

struct Primary;
// The peak of the bare structure's receptance |H| at x_a over [lo, hi] (Hz): the largest of a
// 400-point scan, refined by golden section (unit: Hz, m/N).
Peak bare_peak(const Primary& p, double lo, double hi);

// Free decay of a sampled response y (uniform dt, after t_skip): its positive peaks (local maxima,
// each refined by a parabola), a least-squares line through ln(peak) against time: the decay rate
// sigma (1/s); the damped frequency from the mean peak spacing; zeta = sigma / sqrt(sigma^2 + w_d^2);
// the time to fall by `factor` (default 10: 20 dB), ln(factor) / sigma, and the measured time from
// the first peak until the peaks stay below first / factor (0 if they never do).
struct DecayFit {
  double rate = 0, damped_frequency = 0, zeta = 0, decay_time = 0, measured_decay_time = 0;
  std::size_t peaks = 0;
};
DecayFit fit_decay(const std::vector<double>& y, double dt, double factor = 10, double t_skip = 0);

// Root mean square of a sampled signal after t_skip.
double rms(const std::vector<double>& y, double dt, double t_skip = 0);

// Root mean square of the part of a sampled signal (after t_skip) inside the band [lo, hi] (Hz):
// the DFT of the last n samples, n the largest 2^a 3^b 5^c not above those after t_skip, Y_k = sum_j y_j exp(-2 pi i k j / n), over the bins k / (n dt) in
// the band (0 < k < n / 2; Eigen's FFT), by Parseval RMS^2 = sum 2 |Y_k|^2 / n^2. What a random force's band
// drives, without the slow swing of a hung structure or a mode outside the band.
double band_rms(const std::vector<double>& y, double dt, double lo, double hi, double t_skip = 0);

}  // namespace bagdem
