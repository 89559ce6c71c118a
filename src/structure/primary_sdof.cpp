// Primary kind "sdof": one mass M on a spring K and a dashpot C (structure/primary.hpp). The one
// generalized coordinate is the mass's displacement; its shape is 1 everywhere.
#include <cmath>
#include <numbers>
#include <sstream>

#include "bagdem/structure/primary.hpp"

namespace bagdem {

Primary make_sdof_primary(double M, double K, double C, double cavity_mass) {
  Primary p;
  p.kind = "sdof";
  p.mass = Eigen::MatrixXd::Constant(1, 1, M);
  p.stiffness = Eigen::VectorXd::Constant(1, K);
  p.damping = Eigen::VectorXd::Constant(1, C);
  p.at_force = p.at_response = p.at_cavity = Eigen::VectorXd::Ones(1);
  p.slope_at_cavity = Eigen::VectorXd::Zero(1);
  p.cavity_mass = cavity_mass;
  p.structure_mass = M;
  p.dof_names = {"mode 1"};  // its one mode, named as a beam's are
  const double wn = std::sqrt(K / M);
  p.natural_frequency = {wn / (2 * std::numbers::pi)};
  p.damping_ratio = {C / (2 * std::sqrt(K * M))};
  p.rigid_body = {false};
  p.q0 = p.v0 = Eigen::VectorXd::Zero(1);
  finish_primary(p, {p.at_cavity, p.at_cavity, p.at_cavity}, 0.0);
  std::ostringstream d;
  d.precision(4);
  d << "sdof: M = " << M << " kg, K = " << K << " N/m, C = " << C << " N s/m (f_n = " << p.natural_frequency[0]
    << " Hz, zeta = " << p.damping_ratio[0] << ")";
  if (cavity_mass > 0) d << ", cavity mass " << cavity_mass << " kg";
  p.description = d.str();
  return p;
}

}  // namespace bagdem
