// The continuum model against the full simulation (docs/reference-study.md, section 2): for each frequency of a
// coupled sweep, the response amplitude at x_a that the DEM produced next to what the linear
// models predict with the DEM-derived bag parameters of that frequency (reduced.csv):
//   model:  the structure's whole modal model with the bag as a point mass M_eff and dashpot C_eff
//           at x_b (continuum::modal_receptance): the exact linear equivalent of the measured
//           impedance; its error shows what the linearisation (one harmonic, one point) leaves out;
//   eq7:    the study's SDOF, Eq. (3)/(7), of the mode nearest the frequency seen at the bag
//           (M_p = M_r / phi_r(x_b)^2, continuum::modal_sdof), mu = M_bag / M_p with the bag's real
//           mass and C_b / (M_b w) from the DEM (docs/reference-study.md, section 2), mapped back to x_a by
//           phi_r(x_a) / phi_r(x_b);
//   eq20:   the same SDOF with C_b / (M_b w) from the impact restitution e and phase phi through
//           Eq. (19a), i.e. the study's Eq. (20), in the form chosen (consistent by default).
// An SDOF primary is its own single mode. Errors are (model - DEM) / DEM.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "bagdem/reduce/continuum_model.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "bagdem/structure/primary.hpp"

namespace bagdem {

struct CompareRow {
  double frequency = 0;                                     // Hz
  double mode = 0;                                          // the elastic mode number the SDOF models use
  double dem_response = 0;                                  // |Y| at x_a from the DEM (m)
  double bare_response = 0;                                 // |H_bare| F at x_a (m)
  double model_response = 0, model_error = 0;               // the modal model with M_eff, C_eff
  double eq7_response = 0, eq7_error = 0;                   // SDOF, Eq. (7), real bag mass, DEM C_b/(M_b w)
  double eq20_response = 0, eq20_error = 0;                 // SDOF, Eq. (20) from e (the chosen restitution) and phi
};

// One row per reduced row (a sweep's frequencies). force: the drive amplitude F (N).
std::vector<CompareRow> compare_with_continuum(const Primary& primary, double force, const std::vector<ReducedRow>& rows,
                                               continuum::Form form = continuum::Form::consistent);

// Several dampers on the structure ([[dampers]]): the modal model with every damper's M_eff and
// C_eff at its own place (continuum::modal_receptance with several bags); the SDOF models (eq7,
// eq20) hold one damper and are left NaN. primaries: each damper's (the case's own first; they share
// the structure), rows: each damper's reduced rows, the same frequencies in the same order.
std::vector<CompareRow> compare_with_dampers(const std::vector<const Primary*>& primaries, double force,
                                             const std::vector<std::vector<ReducedRow>>& rows);

// compare.csv (atomically) and a terminal table that names the form used.
void write_compare_csv(const std::filesystem::path& path, const std::vector<CompareRow>& rows);
std::string describe_compare(const std::vector<CompareRow>& rows, continuum::Form form);

}  // namespace bagdem
