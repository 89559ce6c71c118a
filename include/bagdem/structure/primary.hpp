// The primary system: the linear structure that carries the cavity and that the contents' forces act
// back on (two-way coupling). One form covers every kind:
//
//     M a + C v + K q = phi_f f(t) + Q_contents,      cavity displacement u = (phi_b . q) e,
//
// with q the n generalized coordinates, e the transverse direction the structure moves in (the
// excitation direction; gravity is independent of it), phi_f and phi_b the shapes at the force
// point x_f and at the cavity's attachment x_b. Kinds (src/structure/primary_*.cpp, one file each;
// the case keys are in src/case/primary_kinds.cpp):
//   sdof     one mass M_p on a spring K_p and dashpot C_p: n = 1, q = the mass's displacement,
//            phi = 1 everywhere.
//   beam     Euler-Bernoulli beam by modal superposition (analytic shapes, structure/modes.hpp):
//            q = modal coordinates of mass-normalised modes, K = diag(omega_k^2), C = diag(2 zeta_k
//            omega_k), M = I.
//   fe-beam  the same with the modes of a finite-element beam (stepped sections, lumped masses).
// A rigid mass m_c carried by the cavity (primary.cavity_mass: the cavity's own structure, or
// contents replaced by a rigid mass) adds m_c phi_b phi_b^T to M: it moves with the cavity.
//
// The contents' load. Each force F the contents put on the cavity at axial position s (along the
// beam) does the virtual work (F . e) sum_k phi_k(s) dq_k, so Q_k = sum (F . e) phi_k(s): the bag is
// felt over its length (follow_slope, the default; a cavity that only translates takes its load at
// x_b, the projection that matches its motion, G = [phi_b, 0, 0]). The stepper tallies, per step,
// the moments m_j = sum (F . e) s^j (j = 0, 1, 2; s measured from x_b) of the transverse load, and
// Q = G m, where row k of G holds the
// coefficients of the quadratic through phi_k at x_b - l, x_b and x_b + l (l: half the cavity's
// axial extent). The interpolation error is third order in l, 7e-4 of the load for mode 3 of the
// pipe at l = 20 mm. The cavity moves with the beam at x_b and, with follow_slope, turns with its
// slope theta = phi'(x_b) . q (about axis x e), linearised as a shear: a point at axial coordinate
// s moves by (w_b + theta s) e, so the walls' motion matches the load's projection to second order
// in the cavity's length.
//
// Integration: velocity Verlet with the contents (src/step/stage.hpp), the damping force from the velocity
// predicted to the end of the step as the contact dashpots do. Verlet's frequency error is
// (omega dt)^2/24, 4.8e-8 at 85.6 Hz with dt = 2 us; stability needs omega_max dt < 2, checked
// when the case is loaded.
#pragma once
#include <algorithm>
#include <Eigen/Dense>
#include <complex>
#include <memory>
#include <string>
#include <vector>

#include "bagdem/vec3.hpp"

namespace bagdem {

class ModeSet;
class Excitation;

struct Primary {
  std::string kind;                  // "sdof", "beam", "fe-beam"
  std::string description;           // one line for `bagdem check`
  Vec3 direction = Vec3::UnitY();    // e: the transverse direction the structure moves in (unit vector)
  Vec3 axis = Vec3::UnitX();         // along the beam (unit vector, normal to e); the cavity frame's
                                     // origin sits at x_b on it
  double length = 0;                 // beam length (unit: m); 0 for sdof
  double attach = 0;                 // x_b, where the cavity is attached (unit: m)
  double force_at = 0;               // x_f, where the external force acts (unit: m)
  double response_at = 0;            // x_a, where the response is measured (unit: m)
  double cavity_mass = 0;            // rigid mass carried by the cavity (unit: kg)
  double structure_mass = 0;         // the structure's own mass (bag.balls.mass_ratio refers to it) (unit: kg)

  // The n-DOF system. K and C are diagonal (modal or one DOF); M may carry the cavity mass.
  Eigen::MatrixXd mass, mass_inverse;   // (unit: kg for sdof; 1 for mass-normalised modes)
  Eigen::VectorXd stiffness, damping;   // diagonal of K (unit: N/m or 1/s^2) and C (N s/m or 1/s)
  Eigen::VectorXd at_force, at_response, at_cavity;  // phi(x_f), phi(x_a), phi(x_b)
  bool follow_slope = false;         // the cavity also turns with the beam's slope at x_b
  Eigen::VectorXd slope_at_cavity;   // phi'(x_b) (unit: 1/(m sqrt(kg)); zero for sdof)
  double half_extent = 0;            // half the cavity's length along the axis (unit: m)
  Eigen::MatrixXd load_fit;          // n x 3: Q = load_fit * (m0, m1, m2) (see above)
  std::vector<std::string> dof_names;  // "rigid translation", "mode 1", ... (an SDOF: "mode 1")
  std::vector<double> natural_frequency;  // per DOF of the bare structure without cavity mass (unit: Hz)
  std::vector<double> damping_ratio;      // per DOF
  std::vector<bool> rigid_body;           // per DOF: a rigid-body mode of a free-free beam (on its suspension)
  std::shared_ptr<const ModeSet> modes;   // beam kinds: the mode shapes (null for sdof)

  // The external force f(t) at x_f (t counted from the end of settling), and what the run does.
  std::shared_ptr<const Excitation> excitation;
  bool harmonic = false;             // f = amplitude sin(phase), phase advanced with the drive frequency
  double amplitude = 0;              // harmonic force amplitude (unit: N)
  double drive_frequency = 0;        // harmonic: the (first) drive frequency (unit: Hz)
  bool start_steady = false;         // harmonic: start in the bare structure's steady state
  Eigen::VectorXd start_at;          // ... at the phase at which the displacement of start_at . q is
                                     // zero (empty: at_cavity; several dampers: the case's own one's)
  Eigen::VectorXd q0, v0;            // initial state when settling ends (decay, or zero)
  double force_time_scale = 0;       // shortest time the force varies over (a blow's duration, the
                                     // period of the highest random line), 0 if none (unit: s)
  double response_frequency = 0;     // the oscillation the response analysis must resolve: the
                                     // highest drive frequency, the decaying mode's, or else the
                                     // first elastic mode's (unit: Hz); output.cavity_interval
                                     // samples it at least 40 times per period by default
  // A random force's band (excitation.kind = "random"; 0 otherwise) and when its response's
  // in-band RMS starts (excitation.skip): summary.json's band_response_rms_m (unit: Hz, s).
  double random_lo = 0, random_hi = 0, random_skip = 0;
  double random_rms = 0;             // its RMS (unit: N)
  int random_lines = 0;              // its lines in the band
  double expected_cavity_speed = 0;  // largest cavity speed the excitation should cause (bare
                                     // structure), for the time step and impact checks (unit: m/s)

  // Stepped sine (excitation.kind = "stepped-sine"): the drive frequencies in order, each
  // held until the response is steady (run/stepped_sine.hpp).
  struct SteppedSine {
    std::vector<double> frequencies;   // requested (unit: Hz); the run rounds each to a whole number of steps per cycle
    std::vector<std::size_t> modes;    // DOF indices whose peaks are evaluated (around_modes), may be empty
    double tolerance = 0.01;           // steady: amplitude change below this over `cycles` cycles
    std::size_t cycles = 3;            // K
    std::size_t min_cycles = 5;        // at each frequency at least
    std::size_t reduce_cycles = 10;    // the last cycles of a point that its response and reduction are measured over
    std::size_t max_cycles = 200;      // cap (with a warning)
    std::size_t refine = 0;            // extra points per evaluated mode that close in on its peak
    std::size_t chains = 1;            // simulations that share the points, side by side (run/stepped_sine_chains.hpp)
    bool predict = false;              // a point starts from the steady state predicted with the contents measured before
    // The steady test compares the mean response of the last K cycles with the K before, and the
    // point is reduced over those 2K cycles: K = max(cycles, reduce_cycles / 2 rounded up).
    std::size_t half_window() const { return std::max(cycles, (reduce_cycles + 1) / 2); }
    // The least cycles a point runs: the window and the cycle before it (a point's first cycle,
    // right after the drive changed frequency, is never in the window).
    std::size_t least_cycles() const { return std::max(min_cycles, 2 * half_window() + 1); }
  };
  std::shared_ptr<const SteppedSine> stepped_sine;  // null unless stepped-sine

  std::size_t size() const { return static_cast<std::size_t>(stiffness.size()); }
  double omega_max() const;          // largest natural circular frequency of K, M (unit: rad/s)
  // Receptance phi_a^T (K - w^2 M + i w C)^-1 phi_f of the structure without contents (with the
  // cavity mass) (unit: m/N): the bare reference of a stepped sine.
  std::complex<double> bare_receptance(double w) const;
  // Steady state of the structure without contents under f = F sin(w t) at t = 0: q and v.
  void bare_steady_state(double F, double w, Eigen::VectorXd& q, Eigen::VectorXd& v) const;
  // The complex amplitudes Q (q(t) = Re(Q e^{iwt})) of the steady state under f = F sin(w t) with
  // contents of dynamic stiffness Z at the cavity (their force on it Re(-Z U e^{iwt}), U the
  // cavity's amplitude; Z = -w^2 m for a rigid mass m, i w c for a dashpot c).
  Eigen::VectorXcd steady_amplitudes(double F, double w, std::complex<double> Z) const;
  // Another cavity's rigid mass carried too (a case's [[dampers]]): M += mass at at^T, and M^-1.
  void carry_cavity(double mass, const Eigen::VectorXd& at);
  // The same with several cavities (a case's [[dampers]]): contents of dynamic stiffness Z[k] at
  // the cavity of shape at[k] (phi at its x_b), each force Re(-Z[k] U_k e^{iwt}), U_k = at[k] . Q.
  Eigen::VectorXcd steady_amplitudes(double F, double w, const std::vector<Eigen::VectorXd>& at,
                                     const std::vector<std::complex<double>>& Z) const;
  // Amplitude of the cavity's displacement in that steady state (unit: m).
  double bare_cavity_amplitude(double F, double w) const;
  // Its largest value over [f_lo, f_hi] (Hz): the given frequencies and a fine logarithmic scan
  // (4000 points, 0.01% apart over a 10%-wide band), so a sharp resonance between them is found.
  // Returns the amplitude (m) and sets w_at to the circular frequency where it is reached.
  double bare_cavity_amplitude_max(double F, const std::vector<double>& frequencies, double& w_at) const;
  // The elastic DOF whose natural frequency is nearest to f (Hz) in log-frequency (size() when
  // there is none), and its elastic mode number (1 = the first elastic mode) in *number.
  std::size_t nearest_elastic_mode(double f, std::size_t* number = nullptr) const;
  // The elastic mode number of DOF k (1 = the first elastic mode; 0 for a rigid-body DOF).
  std::size_t elastic_mode_number(std::size_t k) const;
  // The DOFs whose peaks a stepped sine over [lo, hi] (Hz) evaluates: the stepped sine's own modes
  // (excitation.around_modes), else every elastic mode inside the band.
  std::vector<std::size_t> evaluated_modes(double lo, double hi) const;
  // Natural frequencies of the structure without contents, cavity mass included (unit: Hz), sorted.
  std::vector<double> bare_frequencies() const;
};

// One mass on a spring and dashpot: M (kg), K (N/m), C (N s/m).
Primary make_sdof_primary(double M, double K, double C, double cavity_mass);

// A beam from its modes (analytic or FE): rigid-body modes hang on a suspension of the given
// frequency and damping ratio, elastic mode k has damping ratio zeta[k] (the last value repeats).
struct BeamPrimarySpec {
  std::string kind;                        // "beam" or "fe-beam"
  std::shared_ptr<const ModeSet> modes;
  std::vector<double> zeta;                // elastic modes' damping ratios
  double suspension_frequency = 0;         // (unit: Hz)
  double suspension_damping = 0;
  double attach = 0, force_at = 0, response_at = 0;  // x_b, x_f, x_a (unit: m)
  double half_extent = 0;                  // half the cavity's length along the axis (unit: m)
  bool follow_slope = false;               // the cavity turns with the beam's slope at x_b
  double cavity_mass = 0;                  // (unit: kg)
  double structure_mass = 0;               // the beam's own mass (unit: kg)
};
Primary make_beam_primary(const BeamPrimarySpec& spec);

// Fills mass (adding the cavity mass), mass_inverse and load_fit from the shapes (half_extent: l
// above, unit: m). Called by the kinds' factories once phi and K, C are set.
void finish_primary(Primary& p, const std::vector<Eigen::VectorXd>& shapes_at_cavity_points, double half_extent);

}  // namespace bagdem
