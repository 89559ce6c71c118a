// Stepped-sine frequency response of a primary structure with its contents (excitation.kind =
// "stepped-sine"). The drive steps through the frequencies in order, the state carried from one to
// the next (the force's phase stays continuous). Each frequency is rounded to a whole number N of
// time steps per cycle, so that the first harmonic of a cycle's N samples,
//     Y = (2/N) sum_n y_n e^{-i theta_n}    (theta_n the force's phase, f = F sin theta),
// is exact for any periodic response. A granular damper's response scatters from cycle to cycle, so
// the point is steady when the mean Y of the last K cycles differs from that of the K before by
// less than the tolerance (SteadyStateDetector); the point's response is that mean, with its
// cycle-to-cycle scatter. At most max_cycles are run, with a warning.
//
// Per point: the complex response at x_a (displacement Y and acceleration -w^2 Y, as the study's
// accelerometer), the receptance H = Y / (-i F), the bare structure's analytic receptance at the
// same frequency (Primary::bare_receptance: the linear structure without contents, with the cavity
// mass; exact in steady state, so no simulation is needed for it), the first harmonics of the
// cavity's displacement and of the contents' force on it, and the energy over the K steady
// cycles: work of the external force W, dissipation in the structure D_s and in the contents
// (the damper) D_c, and the closure (W - D_s - D_c - change of stored energy) / W.
// Per mode (excitation.around_modes, or every elastic mode inside the band): the bare and the
// damped peak of |H| and the reduction in dB and percent (physics brief section 3). A lightly
// damped peak is narrower than any affordable grid (half-power width 2 zeta f), so after the
// planned frequencies the sweep adds `excitation.refine` points per mode, each halfway between
// the largest |H| and its larger neighbour; the damped peak is then the parabola through the
// largest and its neighbours (find_peak), the bare peak that of the analytic receptance.
//
// Files (CASE_DIR/out unless --out): sweep.csv (rewritten after each point), results.h5 with the
// table /sweep (one row per point, columns as in sweep.csv) and a particle frame after each point,
// reduced.csv (the damper's effective parameters per point, reduce/reduce.hpp), peaks.csv (one
// row per mode), bare_curve.csv (the bare structure's analytic response over the band), and
// summary.json with the peaks (written last). checkpoint.bin: written when settling ends and after
// each point; SIGINT/SIGTERM stop the sweep (status "interrupted") and --resume continues it from
// the last point done to the same results as a sweep uninterrupted.
#pragma once
#include <complex>
#include <string>
#include <vector>

#include "bagdem/reduce/compare.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "bagdem/run/runner.hpp"
#include "bagdem/scene.hpp"

namespace bagdem {

struct SweepPoint {
  double requested = 0;                   // requested frequency (unit: Hz)
  double frequency = 0;                   // driven: 1 / (N dt) (unit: Hz)
  std::complex<double> response;         // first harmonic of the displacement at x_a, mean over the last K cycles (unit: m)
  std::complex<double> receptance;       // response / force (unit: m/N)
  std::complex<double> bare;             // the bare structure's receptance (unit: m/N)
  std::complex<double> cavity;           // first harmonic of the cavity's displacement (unit: m)
  std::complex<double> contents_force;   // first harmonic of the contents' transverse force on the cavity (unit: N)
  double work_external = 0;               // per cycle, over the steady cycles (unit: J)
  double dissipated_structure = 0;        // per cycle (unit: J)
  double dissipated_contents = 0;         // per cycle (unit: J)
  double balance = 0;                     // relative closure of the energy balance over those cycles
  std::size_t cycles = 0;                 // cycles run at this frequency
  bool steady = false;                    // reached the tolerance (else max_cycles)
  double change = 0;                      // relative change between the last two K-cycle means
  double spread = 0;                      // cycle-to-cycle scatter of the amplitude over the last K cycles (relative RMS)
  double wall_seconds = 0;
};

struct ModePeak {
  std::string name;                       // "mode 1", ...
  std::size_t mode = 0;                   // elastic mode number (1 = the first elastic mode)
  double bare_frequency = 0, bare_peak = 0;  // peak of |H| of the bare structure (unit: Hz, m/N)
  double frequency = 0, peak = 0;         // peak of |H| with the contents (unit: Hz, m/N)
  double reduction_db = 0, reduction_percent = 0;
};

struct SweepReport {
  bool complete = false;
  std::string message;                    // failure, if any
  int signal = 0;                         // SIGINT or SIGTERM stopped the sweep (a checkpoint was left)
  std::vector<SweepPoint> points;
  std::vector<ModePeak> peaks;
  std::vector<ReducedRow> reduced;        // per point: the damper's effective parameters (reduced.csv)
  std::vector<CompareRow> compare;        // per point: DEM against the continuum model (compare.csv)
  double wall_seconds = 0;
};

// Runs the sweep of a scene whose primary has a stepped-sine excitation (InputError otherwise).
SweepReport run_sweep(const Scene& scene, const RunOptions& options);

// The peaks of a finished sweep (points in any order): per mode of the plan, or per elastic mode
// inside the swept band.
std::vector<ModePeak> sweep_peaks(const Primary& primary, const std::vector<SweepPoint>& points);

}  // namespace bagdem
