// The film of a bag: a membrane of constant-strain triangles with a tension field, a small bending
// stiffness across edges, and Kelvin-Voigt material damping. docs/reference-study.md, section 6.
//
// Membrane (per triangle, reference area A0, thickness t): Green-Lagrange strain Eg = (F^T F - I)/2
// of the in-plane deformation gradient F (3x2, from the rest shape's 2-D frame), plane-stress St.
// Venant-Kirchhoff energy W = t A0 (1/2) Eg : C : Eg (C: plane stress from E, nu) and node forces
// f = -dW/dx (Belytschko, Liu & Moran, Nonlinear Finite Elements, 2000, ch. 9 for the CST).
// Tension field (wrinkling; on by default): with principal Green strains e1 >= e2,
//   taut      (C:Eg has no negative principal stress): the full energy above;
//   wrinkled  (e1 > 0 but the stress along e2 would be compressive): uniaxial tension,
//             W = t A0 (1/2) E e1^2 (the film buckles freely across e1);
//   slack     (e1 <= 0): W = 0.
// The relaxed energy is continuously differentiable, so forces stay conservative (Roddeman et al.,
// J. Appl. Mech. 54, 1987; Mansfield's tension-field theory).
// Bending: per interior edge, W_b = k_e (theta - theta_0)^2 with theta the angle between the
// normals of its two triangles, theta_0 at rest, k_e = D |e|^2 / (2 (A1 + A2)), D = bending
// stiffness (the edge weight |e|^2 / (A1 + A2) of Grinspun et al., "Discrete Shells", SCA 2003);
// gradient of theta after Bridson, Marino & Fedkiw, SCA 2003. The constant 1/2 calibrates it to the
// plate: a sheet of near-equilateral triangles (as the film's) bent into a cylinder of curvature
// kappa about any axis stores 0.92-0.99 x the plate energy D kappa^2 A / 2, tending to 1 as the mesh
// is refined (the boundary's half hinges are missing); right-triangle sheets do so bent about a leg
// and store up to 1.5 x bent at 45 degrees (tests/test_membrane_bending.cpp). For a film
// D = E t^3 / (12 (1 - nu^2)) x a factor; it only removes the membrane's zero-energy modes and does
// not carry the balls.
// A hinge fades with its wings' areas: W_b = k_e s(u_A) s(u_B) (theta - theta_0)^2, u = (A / (0.1
// A_rest))^2 and s(u) = u^2 (3 - 2u) below 1, 1 above (C1). A wing collapsing to a line (the tension
// field lets a crushed triangle shrink to no area: the Gamma-100 bag of 10-mm balls) turns its
// normal as fast as 1/A, and theta's gradient with it: unfaded, the hinge's stiffness grows as
// 1/A^2 past any step. Faded, its force stays bounded and goes to 0 with the area; a hinge whose
// wings keep a tenth of their area is unchanged (the same bits).
// Or (bending_model Quadratic) the quadratic model of Bergou et al. 2006, W_b = k_e |s_e|^2 with s_e
// a fixed weighted sum of the edge's four nodes, flat at rest, its force linear in the positions
// (src/bag/quadratic_bending.hpp); no fade is needed.
// Damping: viscous stress S_v = beta C : dEg/dt, with beta = damping time (s), in the same regime
// as the elastic stress (none when slack, uniaxial when wrinkled); returned separately so the
// energy budget can tally its work.
// Node masses: each triangle's mass rho t A0 split equally among its three nodes.
// Determinism: each triangle and hinge writes its own record; nodes sum their records in a fixed
// order, so forces are bitwise equal for any thread count.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "bagdem/mesh/triangle_mesh.hpp"
#include "bagdem/vec3.hpp"

namespace bagdem {

// Bending across the film's edges: the hinge's angle law (the default) or the quadratic model
// (src/bag/quadratic_bending.hpp; bag.film.bending_model).
enum class BendingModel : std::uint8_t { Hinge, Quadratic };

struct MembraneProperties {
  double youngs_modulus = 0;     // (unit: Pa)
  double poisson_ratio = 0;      // (dimensionless)
  double thickness = 0;          // (unit: m)
  double density = 0;            // (unit: kg/m^3)
  bool tension_field = true;     // no compressive principal stress (wrinkling)
  double bending_stiffness = 0;  // D (unit: N m); 0 = no bending
  BendingModel bending_model = BendingModel::Hinge;
  double damping_time = 0;       // beta of the Kelvin-Voigt stress (unit: s); 0 = none
};

class Membrane {
 public:
  // `mesh`: its vertices are the rest (stress-free) shape; its triangles must be consistently
  // oriented, at most two on an edge, none degenerate (std::invalid_argument otherwise). The
  // hinges come from the triangle list itself: the topology fields need not be built.
  Membrane(const TriangleMesh& mesh, const MembraneProperties& props);

  const MembraneProperties& properties() const { return props_; }
  std::size_t nodes() const { return node_mass_.size(); }
  const std::vector<double>& node_mass() const { return node_mass_; }  // (unit: kg)
  const std::vector<double>& rest_area() const { return area0_; }      // per triangle (unit: m^2)

  // Adds the elastic (membrane + bending) forces at positions x to f_elastic and the damping forces
  // at velocities v to f_damping (both sized nodes()). The bending forces are multiplied by
  // bending_weight, 0 leaving them out (the film stage's slower clock for bending: Bag). Returns
  // the elastic energy at x, bending left out with them (unit: J).
  double add_forces(const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& f_elastic,
                    std::vector<Vec3>& f_damping, double bending_weight = 1.0);
  // Elastic energy (membrane + bending) at x (unit: J).
  double elastic_energy(const std::vector<Vec3>& x) const;

  // Largest angular frequency of the membrane at rest, for the time step (Gershgorin bound over
  // the lumped-mass element matrices: an upper bound) (unit: rad/s).
  double max_frequency() const;
  // The same bound over the bending hinges alone: the bending's own highest frequency at rest
  // (unit: rad/s; 0 without bending).
  double bending_frequency() const;

  // Per-triangle state at x, for output and checks: 0 slack, 1 wrinkled, 2 taut (always 2 without
  // the tension field); and the principal Green strains (e1 >= e2).
  struct TriangleState {
    std::uint8_t regime;
    double e1, e2;
  };
  TriangleState triangle_state(const std::vector<Vec3>& x, std::size_t tri) const;

 private:
  MembraneProperties props_;
  std::vector<std::array<std::uint32_t, 3>> tri_;
  std::vector<double> area0_;              // rest area per triangle
  std::vector<Eigen::Matrix2d> dm_inv_;    // inverse of the rest edge matrix in the triangle's 2-D frame
  std::vector<double> node_mass_;
  struct Hinge {
    std::uint32_t v0, v1;  // the shared edge, in the order of the triangle (v0, v1, a)
    std::uint32_t a, b;    // the opposite vertices of its two triangles (v0, v1, a) and (v1, v0, b)
    double theta0;         // rest angle (unit: rad)
    double k;              // stiffness k_e (unit: N m)
    double fade_a, fade_b; // |n|^2 = (2 A)^2 of each wing where its fade begins: (0.1 x 2 A_rest)^2 (unit: m^4)
    std::array<double, 4> w;  // the quadratic model's stencil on (v0, v1, a, b) (unit: 1/m)
  };
  std::vector<Hinge> hinges_;
  double max_frequency_ = 0, bending_frequency_ = 0;  // computed once from the rest shape (unit: rad/s)
  // Per-element records and the node gather CSR (see "Determinism" above).
  std::vector<std::array<Vec3, 3>> tri_elastic_, tri_damping_;
  std::vector<std::array<Vec3, 4>> hinge_force_;
  std::vector<double> tri_energy_, hinge_energy_;  // (unit: J)
  // Per node: entries (record index << 2 | slot), triangles and hinges in two lists, each in
  // ascending record order.
  std::vector<std::uint32_t> tri_gather_begin_, tri_gather_, hinge_gather_begin_, hinge_gather_;

  void build_rest_frames(const std::vector<Vec3>& x0);
  void build_hinges(const std::vector<Vec3>& x0);
  void build_gather();
  void hinge_forces(const std::vector<Vec3>& x, double bending_weight);
  void compute_frequencies(const std::vector<Vec3>& x0);  // max_frequency_ and bending_frequency_
};

}  // namespace bagdem
