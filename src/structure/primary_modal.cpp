// Primary kind "modal": a structure given by its modes (structure/modal_table.hpp), from any
// finite-element code. Mass-normalised coordinates as for the beams (primary_beam.cpp): M = I
// (+ the cavity mass), K = diag(omega_k^2), C = diag(2 zeta_k omega_k), the shapes psi = phi /
// sqrt(modal mass).
#include <cmath>
#include <numbers>
#include <sstream>

#include "bagdem/structure/modal_table.hpp"

namespace bagdem {

Primary make_modal_primary(const ModalPrimarySpec& spec) {
  const std::vector<ModalRow>& rows = spec.table.rows;
  const auto N = static_cast<Eigen::Index>(rows.size());
  Primary p;
  p.kind = "modal";
  p.cavity_mass = spec.cavity_mass;
  p.structure_mass = spec.structure_mass;
  p.follow_slope = spec.follow_slope;
  p.half_extent = spec.half_extent;
  p.stiffness.resize(N), p.damping.resize(N);
  p.at_force.resize(N), p.at_response.resize(N), p.at_cavity.resize(N), p.slope_at_cavity.resize(N);
  std::size_t elastic = 0, rigid = 0;
  for (Eigen::Index k = 0; k < N; ++k) {
    const ModalRow& r = rows[static_cast<std::size_t>(k)];
    const double w = 2 * std::numbers::pi * r.frequency, scale = 1 / std::sqrt(r.modal_mass);
    p.stiffness[k] = w * w;
    p.damping[k] = 2 * r.damping_ratio * w;
    p.natural_frequency.push_back(r.frequency);
    p.damping_ratio.push_back(r.damping_ratio);
    p.rigid_body.push_back(r.rigid_body);
    p.dof_names.push_back(r.rigid_body ? "rigid mode " + std::to_string(++rigid) : "mode " + std::to_string(++elastic));
    p.at_force[k] = scale * r.shape_force;
    p.at_response[k] = scale * r.shape_response;
    p.at_cavity[k] = scale * r.shape_attach;
    p.slope_at_cavity[k] = spec.follow_slope ? scale * r.slope_attach : 0.0;
  }
  p.q0 = p.v0 = Eigen::VectorXd::Zero(N);
  finish_primary(p, {p.at_cavity, p.at_cavity, p.at_cavity}, 0.0);
  // The load's fit over the cavity (structure/primary.hpp) is the shape's Taylor series at x_b:
  // phi + phi' s + phi'' s^2 / 2, with the cavity turning (follow_slope), else phi alone.
  if (spec.follow_slope)
    for (Eigen::Index k = 0; k < N; ++k) {
      const ModalRow& r = rows[static_cast<std::size_t>(k)];
      const double scale = 1 / std::sqrt(r.modal_mass);
      p.load_fit(k, 1) = scale * r.slope_attach;
      p.load_fit(k, 2) = 0.5 * scale * r.curvature_attach;
    }
  std::ostringstream d;
  d.precision(5);
  d << "modal: " << N << " modes from " << spec.source << " (" << elastic << " elastic";
  if (rigid > 0) d << ", " << rigid << " rigid-body on a suspension";
  d << "), at";
  for (Eigen::Index k = 0; k < N; ++k) d << (k ? ", " : " ") << p.natural_frequency[static_cast<std::size_t>(k)];
  d << " Hz";
  if (spec.follow_slope) d << "; the cavity turns with the slope";
  if (spec.cavity_mass > 0) d << "; cavity mass " << spec.cavity_mass << " kg";
  p.description = d.str();
  return p;
}

}  // namespace bagdem
