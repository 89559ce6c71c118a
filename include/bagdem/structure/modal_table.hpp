// A structure described by its modes (primary.kind = "modal"): the table that lets a model from any
// finite-element code carry the cavity. One row per mode, CSV with "name [unit]" headers:
//   frequency [Hz]          natural frequency f_k (> 0; a free structure's rigid-body modes are
//                           given the frequency of their suspension)
//   damping_ratio [1]       zeta_k, in [0, 1)
//   modal_mass [kg]         m_k = phi_k^T M phi_k in the shapes' own normalisation (> 0)
//   shape_attach [1]        phi_k at the cavity's attachment x_b, along primary.direction
//   shape_force [1]         phi_k where the force acts (x_f)
//   shape_response [1]      phi_k where the response is measured (x_a)
//   slope_attach [1/m]      optional: d phi_k / ds at x_b along primary.axis (the cavity then turns
//                           with it, and the contents' load is taken over the cavity's length)
//   curvature_attach [1/m^2] optional: d^2 phi_k / ds^2 at x_b (the load's quadratic part)
//   rigid_body [1]          optional: 1 for a rigid-body mode on its suspension, else 0 (mode
//                           numbers, e.g. excitation.around_modes, count the elastic modes only)
// The shapes are scaled to mass-normalised ones, psi_k = phi_k / sqrt(m_k), so that M = I,
// K = diag(omega_k^2), C = diag(2 zeta_k omega_k) (Craig & Kurdila, Fundamentals of Structural
// Dynamics, 2006, sec. 10.3). `bagdem modes` writes this table for any primary.
#pragma once
#include <filesystem>
#include <vector>

#include "bagdem/structure/primary.hpp"

namespace bagdem {

struct ModalRow {
  double frequency = 0, damping_ratio = 0, modal_mass = 1;  // (unit: Hz, 1, kg)
  double shape_attach = 0, shape_force = 0, shape_response = 0;  // (unit: 1)
  double slope_attach = 0, curvature_attach = 0;  // (unit: 1/m, 1/m^2)
  bool rigid_body = false;
};
struct ModalTable {
  std::vector<ModalRow> rows;
  bool has_slope = false, has_curvature = false;
};

// Reads and checks a modal table; InputError naming the file, the column (and its unit) or the row
// and what is allowed.
ModalTable read_modal_table(const std::filesystem::path& path);

// Writes the table of a primary's DOFs (mass-normalised: modal_mass 1 kg; the structure alone,
// without primary.cavity_mass), with every digit a double holds, so that a modal primary read from
// it has the same modes (the slope, and the curvature of the load's quadratic fit over the cavity,
// included).
void write_modal_table(const std::filesystem::path& path, const Primary& primary);

// The primary of a modal table: cavity_mass carried by the cavity, structure_mass the structure's
// mass (for bag.balls.mass_ratio; 0 when unknown), follow_slope (needs the slope column),
// half_extent the cavity's half length along the axis (unit: m).
struct ModalPrimarySpec {
  ModalTable table;
  double cavity_mass = 0, structure_mass = 0, half_extent = 0;
  bool follow_slope = false;
  std::string source;  // the table's file, for the description
};
Primary make_modal_primary(const ModalPrimarySpec& spec);

}  // namespace bagdem
