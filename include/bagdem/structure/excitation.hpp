// Force time histories f(t) that drive a primary structure at x_f (structure/primary.hpp), t counted
// from the end of settling (unit: N). One class per kind (src/structure/excitation.cpp):
//   harmonic  F sin(2 pi f t + phase). (A run's harmonic drive advances its phase step by step
//             instead, so that a sweep can change f with the phase continuous: src/step/structure.cpp.)
//   impulse   a hammer blow: half-sine pulse of impulse J and duration tau from t0,
//             f = (pi J / (2 tau)) sin(pi (t - t0) / tau) on [t0, t0 + tau] (its integral is J).
//   random    band-limited random force: a random-phase multisine, equal amplitudes on the lines
//             k / T_p inside [f_lo, f_hi], phases uniform from a seeded std::mt19937_64 mapped to
//             [0, 2 pi) by its top 53 bits (identical on every platform), scaled to the requested RMS
//             (Pintelon & Schoukens, System Identification, 2012, sec. 2.4). It is periodic with
//             period T_p (default: 200 lines in the band, T_p = 200 / (f_hi - f_lo)), so its spectrum
//             is exactly zero outside the band over a whole period. Evaluated from a table of one
//             period at spacing 1/(64 f_hi), interpolated with cubic Hermite splines whose slopes are
//             the exact derivative: the relative error is below 1e-5 of the RMS. (A table of more
//             than 2^20 rows, a narrow band at a high frequency, is not built: the sum is evaluated.)
//   none      0 (free decay from an initial displacement)
#pragma once
#include <cstdint>
#include <memory>
#include <string>

namespace bagdem {

class Excitation {
 public:
  virtual ~Excitation() = default;
  virtual double force(double t) const = 0;      // (unit: N)
  virtual std::string describe() const = 0;      // one line for `bagdem check`
  virtual double frequency() const { return 0; } // drive frequency of a harmonic force (unit: Hz)
};

std::unique_ptr<Excitation> make_harmonic_force(double amplitude, double frequency_hz, double phase = 0);
std::unique_ptr<Excitation> make_impulse_force(double impulse, double duration, double start);
std::unique_ptr<Excitation> make_random_force(double rms, double f_lo, double f_hi, std::uint64_t seed, double period = 0);
std::unique_ptr<Excitation> make_no_force();

}  // namespace bagdem
