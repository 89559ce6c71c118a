// Stepped-sine frequency response of a primary structure with its contents (excitation.kind =
// "stepped-sine"). The drive steps through the frequencies in order, the state carried from one to
// the next (the force's phase stays continuous; with excitation.predict the structure's state then
// moves to the new frequency's predicted steady state), in `excitation.chains` chains side by side, each
// a simulation from the settled contents through its block of the frequencies (src/run/
// stepped_sine_chains.hpp); the points are written in their order, so the files do not depend on the
// threads. Each frequency is rounded to a whole number N of
// time steps per cycle, so that the first harmonic of a cycle's N samples,
//     Y = (2/N) sum_n y_n e^{-i theta_n}    (theta_n the force's phase, f = F sin theta),
// is exact for any periodic response; a slow drift underneath it (the structure swinging on its
// suspension) is measured by the cycles' means and taken out of Y, of the cavity's harmonic and of
// the cavity's samples the reduction reads (CycleHarmonic, structure/response.hpp). A granular damper's response scatters from cycle to cycle, so
// the point has settled when the mean Y of the last K cycles differs from that of the K before by
// less than the tolerance, or by no more than the cycles' own scatter allows (a 5 % two-sample test:
// a chaotic response; SteadyStateDetector), K = max(steady_cycles, reduce_cycles / 2 rounded
// up), after at least max(min_cycles, 2K + 1) cycles (the first cycle is never in the window); the point's response and the damper's reduction
// are measured over those last 2K cycles (the window judged steady), with a 95% interval over the
// correlated cycles (reduce/interval.hpp). The point is
// steady when it settled, the energy balance over that window closes within 1% and the contents'
// tallied dissipation is not negative; an unsteady point is flagged (steady = 0 in sweep.csv and
// reduced.csv) and kept out of the peaks. At most max_cycles are run, with a warning.
//
// Per point: the complex response at x_a (displacement Y and acceleration -w^2 Y, as the study's
// accelerometer), the receptance H = Y / (-i F), the bare structure's analytic receptance at the
// same frequency (Primary::bare_receptance: the linear structure without contents, with the cavity
// mass; exact in steady state, so no simulation is needed for it), the first harmonics of the
// cavity's displacement and of the contents' force on it, and the energy over the K steady
// cycles: work of the external force W, dissipation in the structure D_s and in the contents
// (the damper) D_c, and the closure (W - D_s - D_c - change of stored energy) / W.
// Per mode (excitation.around_modes, or every elastic mode inside the band): the bare and the
// damped peak of |H| and the reduction in dB and percent (docs/reference-study.md, section 3). A lightly
// damped peak is narrower than any affordable grid (half-power width 2 zeta f), so after the
// planned frequencies the stepped sine adds `excitation.refine` points per mode between the largest |H|
// and its larger neighbour (halfway, or with several chains in rounds of equal parts); the damped peak is then the parabola in
// (f^2, 1/|H|^2) through the largest and its neighbours (find_peak), the bare peak that of the analytic receptance. The
// largest simulated |H| is reported beside the fitted peak; when it is the mode's first or last
// point the peak may lie outside the band: the peak is marked at_band_edge and its reduction is
// only a bound. The reduction's interval is that of the largest point's |H| (its relative
// half-width, in dB).
//
// Files (CASE_DIR/out unless --out): sweep.csv (rewritten after each point), results.h5 with the
// table /sweep (one row per point, columns as in sweep.csv) and a particle frame after each point,
// reduced.csv (the damper's effective parameters per point, reduce/reduce.hpp), peaks.csv (one
// row per mode), bare_curve.csv (the bare structure's analytic response over the band), and
// summary.json with the peaks (written last). checkpoint.bin: written when settling ends and after
// each point written (with every chain's state); SIGINT/SIGTERM stop the stepped sine (status "interrupted") and --resume continues it from
// the last point done to the same results as a stepped sine uninterrupted.
#pragma once
#include <complex>
#include <string>
#include <vector>

#include "bagdem/reduce/compare.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "bagdem/reduce/summary.hpp"
#include "bagdem/run/runner.hpp"
#include "bagdem/scene.hpp"

namespace bagdem {

struct SteppedSinePoint {
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
  double receptance_ci95 = 0;             // 95% half-width of |H| over the window's cycles (unit: m/N)
  std::size_t cycles = 0;                 // cycles run at this frequency
  bool settled = false;                   // reached the tolerance (else max_cycles)
  bool steady = false;                    // settled, and the window's energy balances (see above)
  double change = 0;                      // relative change between the last two K-cycle means
  double spread = 0;                      // cycle-to-cycle scatter of the amplitude over the last K cycles (relative RMS)
  double wall_seconds = 0;
};

struct SteppedSineReport {
  bool complete = false;
  std::string message;                    // failure, if any
  int signal = 0;                         // SIGINT or SIGTERM stopped the sweep (a checkpoint was left)
  std::vector<SteppedSinePoint> points;
  std::vector<ModePeak> peaks;
  std::vector<ReducedRow> reduced;        // per point: the damper's effective parameters (reduced.csv)
  std::vector<CompareRow> compare;        // per point: DEM against the continuum model (compare.csv)
  double wall_seconds = 0;
};

// Runs the stepped sine of a scene whose primary has a stepped-sine excitation (InputError otherwise).
SteppedSineReport run_stepped_sine(const Scene& scene, const RunOptions& options);

// The peaks of a finished stepped sine (points in any order): per mode of the plan, or per elastic mode
// inside the swept band.
std::vector<ModePeak> sweep_peaks(const Primary& primary, const std::vector<SteppedSinePoint>& points);
// The peaks of a finished stepped sine in OUT recomputed from its recorded points (OUT/sweep.csv), the
// bare structure from `primary`: rewrites OUT/peaks.csv and the peaks of OUT/summary.json
// (`bagdem peaks`). InputError when OUT holds no complete stepped sine, or when the bare peaks differ
// from those recorded (the case or its --set differ from the run's).
std::vector<ModePeak> recompute_stepped_sine_peaks(const Primary& primary, const std::filesystem::path& out);
// One line for a mode's peak: the fitted and the largest simulated peak, the reduction with its
// interval, and the band-edge mark.
std::string describe_peak(const ModePeak& peak);
// Why a stepped sine has no peak where one was looked for: a line for a band that holds no natural
// frequency of the structure, and one per mode whose every point was unsteady; none when each
// mode has its peak.
std::vector<std::string> missing_peaks(const Primary& primary, const std::vector<SteppedSinePoint>& points);

}  // namespace bagdem
