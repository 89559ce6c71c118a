// Primary kinds "beam" and "fe-beam": an Euler-Bernoulli beam by modal superposition over
// mass-normalised modes (structure/modes.hpp): M = I (+ the cavity mass), K = diag(omega_k^2),
// C = diag(2 zeta_k omega_k). The rigid-body modes of a free-free beam hang on a suspension
// (the strings the study's pipe hung from) of frequency f_s and damping ratio zeta_s: far below
// the elastic modes it changes the response there by (f_s/f)^2, and it keeps a net force from
// drifting the beam away.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "bagdem/structure/modes.hpp"
#include "bagdem/structure/primary.hpp"

namespace bagdem {

Primary make_beam_primary(const BeamPrimarySpec& b) {
  const ModeSet& m = *b.modes;
  const std::size_t n = m.size();
  const auto N = static_cast<Eigen::Index>(n);
  Primary p;
  p.kind = b.kind;
  p.modes = b.modes;
  p.length = m.length();
  p.attach = b.attach, p.force_at = b.force_at, p.response_at = b.response_at;
  p.cavity_mass = b.cavity_mass;
  p.structure_mass = b.structure_mass;
  p.follow_slope = b.follow_slope;
  p.half_extent = b.half_extent;
  p.slope_at_cavity.resize(N);
  p.stiffness.resize(N), p.damping.resize(N);
  p.at_force.resize(N), p.at_response.resize(N), p.at_cavity.resize(N);
  std::vector<Eigen::VectorXd> around(3, Eigen::VectorXd(N));
  const double l = b.half_extent;
  std::size_t elastic = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const auto K = static_cast<Eigen::Index>(k);
    const bool rigid = m.rigid(k);
    double w = m.omega(k), zeta;
    if (rigid) {
      w = 2 * std::numbers::pi * b.suspension_frequency;
      zeta = b.suspension_damping;
      p.dof_names.push_back(k == 0 ? "rigid translation" : "rigid rotation");
    } else {
      zeta = b.zeta.empty() ? 0.0 : b.zeta[std::min(elastic, b.zeta.size() - 1)];
      p.dof_names.push_back("mode " + std::to_string(++elastic));
    }
    p.stiffness[K] = w * w;
    p.damping[K] = 2 * zeta * w;
    p.natural_frequency.push_back(w / (2 * std::numbers::pi));
    p.damping_ratio.push_back(zeta);
    p.rigid_body.push_back(rigid);
    p.at_force[K] = m.shape(k, b.force_at);
    p.at_response[K] = m.shape(k, b.response_at);
    p.at_cavity[K] = m.shape(k, b.attach);
    p.slope_at_cavity[K] = m.slope(k, b.attach);
    around[0][K] = m.shape(k, std::max(0.0, b.attach - l));
    around[1][K] = p.at_cavity[K];
    around[2][K] = m.shape(k, std::min(p.length, b.attach + l));
  }
  p.q0 = p.v0 = Eigen::VectorXd::Zero(N);
  // A cavity that only translates takes its load at x_b (the projection that matches its motion);
  // one that turns with the slope takes it where it acts (the quadratic fit over its length).
  finish_primary(p, around, b.follow_slope ? l : 0.0);
  std::ostringstream d;
  d.precision(5);
  d << m.describe() << "; modes at";
  for (std::size_t k = 0; k < n; ++k) d << (k ? ", " : " ") << p.natural_frequency[k];
  d << " Hz";
  if (b.cavity_mass > 0) d << "; cavity mass " << b.cavity_mass << " kg";
  p.description = d.str();
  return p;
}

}  // namespace bagdem
