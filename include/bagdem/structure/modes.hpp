// Modal library of the primary structure: bending modes of an Euler-Bernoulli beam (pure math, no
// dependency on the DEM stepper).
//
// Model: EI w'''' + rhoA w_tt = 0 on x in [0, L] (Rao, Vibration of Continuous Systems, 2007,
// ch. 11). A mode w = phi(x) sin(omega t) obeys phi'''' = beta^4 phi, beta^4 = rhoA omega^2 / EI,
// so omega = (beta L)^2 sqrt(EI / (rhoA L^4)). End conditions: free (phi'' = phi''' = 0), pinned
// (phi = phi'' = 0), clamped (phi = phi' = 0).
//
// Three ways to get modes, each checked against the others (tests/test_beam_modes.cpp):
//  * analytic_beam_modes: uniform beam, closed-form shapes (Blevins, Formulas for Natural Frequency
//    and Mode Shape, 1979, table 8-1). The textbook forms cosh - sigma sinh lose every digit to
//    cancellation by beta L ~ 30; here the hyperbolic part is written with exponentials decaying
//    from each end, e^(-beta x) and e^(-beta (L - x)), with (1 - sigma) e^(beta L) in closed form, so
//    mode 20 is as accurate as mode 1 (src/structure/beam_analytic.cpp).
//  * fe_beam_modes: cubic Hermite elements with consistent mass (Przemieniecki, Theory of Matrix
//    Structural Analysis, 1968: stiffness ch. 5, consistent mass ch. 11; the standard 4x4 element
//    matrices), stepped sections, point masses and rotary inertias (src/structure/beam_fe.cpp).
//  * lumped_mass_frequencies: exact frequencies of a uniform beam carrying one point mass, from the
//    continuous equations (src/structure/beam_lumped_mass.cpp).
//
// Normalisation: every mode set is mass-normalised (modal mass 1 kg):
//   integral rhoA phi_k phi_l dx + sum_j [m_j phi_k(x_j) phi_l(x_j) + J_j phi_k'(x_j) phi_l'(x_j)]
//     = delta_kl,
// and then integral EI phi_k'' phi_l'' dx = omega_k^2 delta_kl.
// Sign convention (both analytic and FE elastic modes): on a grid of sample points (the FE nodes;
// for analytic modes the uniform grid x_i = i L / n, n = 50 (k + 2), >= 50 points per half-wave)
// the first point, in x order, whose |phi| is within 1e-2 (relative) of max |phi| has phi > 0.
// Peaks of equal height (the mirror peaks of symmetric problems, the equal peaks of a pinned beam)
// are thus a tie won by the first, whatever the grid's offset from them, as long as the grid samples
// each peak within 1% (about 16 points per half-wave): analytic and FE signs then agree.
// (Free-free: phi(0) > 0; clamped-free: tip > 0; pinned-pinned mode n is +sin(n pi x / L).)
// Rigid modes of a free-free beam: translation > 0 and rotation with positive slope about the
// centre of mass (mid-span for a uniform beam): 1/sqrt(m) and sqrt(12 / (m L^2)) (x - L/2) for the
// uniform beam of mass m.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace bagdem {

// End conditions of a beam; clamped_free is clamped at x = 0 and free at x = L.
enum class BeamEnds { free_free, pinned_pinned, clamped_free, clamped_clamped };

// "free-free", "pinned-pinned", "clamped-free", "clamped-clamped".
const char* to_string(BeamEnds);
// Parses the names above (exactly); returns false, leaving `ends` alone, for anything else.
bool parse_beam_ends(const std::string&, BeamEnds&);

// A set of mass-normalised modes of a 1-D structure along its axis coordinate x in [0, L]:
// integral rhoA phi_k phi_l dx + sum over lumped masses m_j phi_k(x_j) phi_l(x_j)
// (+ rotary inertia J_j phi_k' phi_l') = delta_kl. Modes are sorted by frequency.
class ModeSet {
 public:
  virtual ~ModeSet() = default;
  virtual std::size_t size() const = 0;
  virtual double length() const = 0;                        // (unit: m)
  virtual double omega(std::size_t k) const = 0;            // natural circular frequency (unit: rad/s); 0 for rigid-body modes
  virtual bool rigid(std::size_t k) const = 0;              // rigid-body mode of a free-free beam
  virtual double shape(std::size_t k, double x) const = 0;  // (unit: 1/sqrt(kg))
  virtual double slope(std::size_t k, double x) const = 0;  // d shape/dx (unit: 1/(m sqrt(kg)))
  // d^2 shape/dx^2 (unit: 1/(m^2 sqrt(kg))); EI times it is the modal bending moment. FE: linear
  // within an element, discontinuous at nodes (the element to the right of a node is used).
  virtual double curvature(std::size_t k, double x) const = 0;
  virtual std::string describe() const = 0;  // one line for `bagdem check`
};

// A uniform beam: length (unit: m), bending stiffness EI (unit: N m^2), mass per length rhoA
// (unit: kg/m).
struct UniformBeam {
  double length = 0;
  double EI = 0;
  double rhoA = 0;
  BeamEnds ends = BeamEnds::free_free;
};

// beta_k L of the k-th elastic mode (k = 0 first), from the frequency equation of the end condition
// (Blevins 1979, table 8-1): free-free and clamped-clamped cos(bL) cosh(bL) = 1, clamped-free
// cos(bL) cosh(bL) = -1, pinned-pinned sin(bL) = 0. Solved in the form cos(bL) -+ 1/cosh(bL) = 0 by
// bisection to the last bit (dimensionless).
double beam_root(BeamEnds ends, std::size_t k);

// Analytic modes of a uniform beam: for free-free, the two rigid-body modes (translation, rotation
// about mid-span) first when include_rigid, then `elastic` elastic modes; sorted by frequency.
// Other end conditions have no rigid modes (include_rigid is ignored).
std::unique_ptr<ModeSet> analytic_beam_modes(const UniformBeam& beam, std::size_t elastic, bool include_rigid = true);

// A uniform stretch [x0, x1] (unit: m) of a stepped beam, EI (unit: N m^2), rhoA (unit: kg/m).
struct BeamSegment {
  double x0 = 0, x1 = 0, EI = 0, rhoA = 0;
};
// A point mass (unit: kg) with rotary inertia (unit: kg m^2) at x (unit: m).
struct LumpedMass {
  double x = 0, mass = 0, inertia = 0;
};
// A beam for the finite-element model: segments must tile [0, length]; `elements` is the target
// number of elements (distributed over the stretches between breakpoints in proportion to their
// length, at least one each).
struct FeBeam {
  double length = 0;
  std::vector<BeamSegment> segments;
  std::vector<LumpedMass> masses;
  BeamEnds ends = BeamEnds::free_free;
  std::size_t elements = 200;
};

// The FE nodes (element boundaries; unit: m): uniform within each stretch between breakpoints
// (0, L, segment ends, lumped-mass positions).
std::vector<double> fe_beam_nodes(const FeBeam& beam);

// Cubic Hermite Euler-Bernoulli elements (consistent mass), element boundaries also at segment ends
// and lumped-mass positions; modes from Eigen::GeneralizedSelfAdjointEigenSolver(K, M); the lowest
// `count` modes. Free-free: the first two are the rigid modes (omega exactly 0, rigid() true), built
// exactly (translation; rotation about the centre of mass) after checking that the solver's two
// lowest eigenvalues are at round-off level; tiny negative eigenvalues are clamped to 0. Shapes,
// slopes and curvatures between nodes come from the element's Hermite functions. Throws
// std::invalid_argument for a malformed beam.
std::unique_ptr<ModeSet> fe_beam_modes(const FeBeam& beam, std::size_t count);

// Static deflection (unit: m) at x of the FE beam (not free-free) under a point force P (unit: N)
// at x_f (a node is placed there), from K u = f. Exact at every x for point loads: the exact
// solution is cubic between loads and supports, which the Hermite elements reproduce. K's condition
// number grows like (L/h)^4, so K is assembled and factorised in long double (round-off ~1e-11 of
// the deflection at 200 elements, against ~5e-8 in double).
double fe_static_deflection(const FeBeam& beam, double x_f, double P, double x);

// Exact (continuous Euler-Bernoulli) natural circular frequencies (unit: rad/s) of a uniform beam
// carrying a point mass m (unit: kg) at x_m in [0, L] (unit: m); the lowest `count`, including
// the two zeros of the rigid modes of a free-free beam. The beam is split at x_m; each side has the
// general solution; continuity of w, w', w'' and the shear jump EI [w'''] = m omega^2 w(x_m) give an
// 8x8 determinant, which factorises as det D0 (1 - m omega^2 alpha(omega)) (D0: bare beam, alpha:
// point receptance at x_m). Its roots are bracketed by the bare roots (Cauchy interlacing for a
// rank-one mass) and bisected; bare modes with a node at x_m are kept unchanged.
std::vector<double> lumped_mass_frequencies(const UniformBeam& beam, double x_m, double m, std::size_t count);

}  // namespace bagdem
