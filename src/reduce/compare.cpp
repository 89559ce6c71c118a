// The continuum model against the full simulation (reduce/compare.hpp).
#include "bagdem/reduce/compare.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>

#include "bagdem/io/table_csv.hpp"

namespace bagdem {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The structure as a modal model: unit-stiffness convention k_r = omega_r^2 with its own mass
// matrix (an SDOF: omega = sqrt(K), the mass M; a beam: mass-normalised modes and cavity mass).
continuum::ModalModel modal_model(const Primary& P) {
  continuum::ModalModel m;
  m.omega = P.stiffness.cwiseSqrt();
  m.zeta = (P.damping.array() / (2 * m.omega.array())).matrix();
  m.shape_at_force = P.at_force, m.shape_at_response = P.at_response, m.shape_at_bag = P.at_cavity;
  m.mass = P.mass;
  return m;
}

double relative(double model, double dem) { return dem != 0 ? (model - dem) / dem : kNaN; }

}  // namespace

std::vector<CompareRow> compare_with_dampers(const std::vector<const Primary*>& primaries, double F,
                                             const std::vector<std::vector<ReducedRow>>& rows) {
  const Primary& P = *primaries.front();
  const continuum::ModalModel model = modal_model(P);
  std::vector<CompareRow> out;
  for (std::size_t i = 0; i < rows.front().size(); ++i) {
    const ReducedRow& r = rows.front()[i];
    CompareRow c;
    c.frequency = r.frequency;
    const double w = 2 * std::numbers::pi * r.frequency;
    c.dem_response = r.response_amplitude;
    c.bare_response = std::abs(P.bare_receptance(w)) * F;
    std::vector<continuum::BagAt> bags;
    for (std::size_t d = 0; d < primaries.size(); ++d) bags.push_back({primaries[d]->at_cavity, rows[d][i].M_eff, rows[d][i].C_eff});
    c.model_response = std::abs(continuum::modal_receptance(model, bags, w)) * F;
    c.model_error = relative(c.model_response, c.dem_response);
    std::size_t number = 0;
    P.nearest_elastic_mode(r.frequency, &number);
    c.mode = static_cast<double>(number);
    c.eq7_response = c.eq7_error = c.eq20_response = c.eq20_error = kNaN;
    out.push_back(c);
  }
  return out;
}

std::vector<CompareRow> compare_with_continuum(const Primary& P, double F, const std::vector<ReducedRow>& rows,
                                               continuum::Form form) {
  const continuum::ModalModel model = modal_model(P);
  std::vector<CompareRow> out;
  for (const ReducedRow& r : rows) {
    CompareRow c;
    c.frequency = r.frequency;
    const double w = 2 * std::numbers::pi * r.frequency;
    c.dem_response = r.response_amplitude;
    c.bare_response = std::abs(P.bare_receptance(w)) * F;
    c.model_response = std::abs(continuum::modal_receptance(model, r.M_eff, r.C_eff, w)) * F;
    c.model_error = relative(c.model_response, c.dem_response);
    // The SDOF of the nearest mode seen at the bag; its modal mass includes any cavity mass.
    std::size_t number = 0;
    const std::size_t k = P.nearest_elastic_mode(r.frequency, &number);
    c.mode = static_cast<double>(number);
    c.eq7_response = c.eq7_error = c.eq20_response = c.eq20_error = kNaN;
    if (k < P.size() && P.at_cavity[static_cast<Eigen::Index>(k)] != 0) {
      const auto i = static_cast<Eigen::Index>(k);
      const double Mr = P.mass(i, i), phi_b = P.at_cavity[i] / std::sqrt(Mr);
      const double omega = std::sqrt(P.stiffness[i] / Mr), zeta = P.damping[i] / (2 * omega * Mr);
      const continuum::ModalSdof s = continuum::modal_sdof(omega, zeta, phi_b, P.at_force[i] / std::sqrt(Mr));
      const double Mp = s.system.primary_mass, wn = std::sqrt(s.system.primary_stiffness / Mp);
      const double lambda = w / wn, mu = r.bag_mass / Mp, cp = s.system.primary_damping / (Mp * w);
      const double Xst = std::abs(F * s.force_factor) / s.system.primary_stiffness;
      const double to_response = std::abs(P.at_response[i] / P.at_cavity[i]);
      // The study's model has no negative damping: a value below zero within its 95% interval
      // (scatter), or above -1e-4 (a rigid mass's C_b/(M_b w) from the integrator's phase error is
      // of order 1e-6), counts as zero; a clearly negative one gives no prediction.
      const double ci = std::isfinite(r.Cb_over_Mbw_ci95) ? r.Cb_over_Mbw_ci95 : 0.0;
      if (std::isfinite(r.Cb_over_Mbw) && r.Cb_over_Mbw >= -(ci + 1e-4)) {
        c.eq7_response = Xst * continuum::amplification(lambda, mu, std::max(0.0, r.Cb_over_Mbw), cp, form) * to_response;
        c.eq7_error = relative(c.eq7_response, c.dem_response);
      }
      if (std::isfinite(r.e) && r.e >= 0 && r.e < 1 && std::isfinite(r.impact_phase)) {
        c.eq20_response = Xst * continuum::impact_model(lambda, mu, r.e, r.impact_phase, cp, form).amplification * to_response;
        c.eq20_error = relative(c.eq20_response, c.dem_response);
      }
    }
    out.push_back(c);
  }
  return out;
}

void write_compare_csv(const std::filesystem::path& path, const std::vector<CompareRow>& rows) {
  static const std::vector<TableColumn> columns = {
      {"frequency", "Hz"},      {"mode", "1"},          {"dem_response", "m"},  {"bare_response", "m"},
      {"model_response", "m"},  {"model_error", "1"},   {"eq7_response", "m"},  {"eq7_error", "1"},
      {"eq20_response", "m"},   {"eq20_error", "1"}};
  std::vector<std::vector<double>> values;
  for (const CompareRow& c : rows)
    values.push_back({c.frequency, c.mode, c.dem_response, c.bare_response, c.model_response, c.model_error, c.eq7_response,
                      c.eq7_error, c.eq20_response, c.eq20_error});
  write_table_csv(path, columns, values);
}

std::string describe_compare(const std::vector<CompareRow>& rows, continuum::Form form) {
  std::ostringstream o;
  o << "DEM against the continuum model (response amplitude at response_at; Eq. (7)/(20) in the " << continuum::form_name(form)
    << " form):\n"
    << "    f [Hz]  mode     DEM [m]    bare [m]   modal model [m]  err      Eq.7 [m]   err     Eq.20 [m]   err\n";
  o << std::setprecision(4);
  for (const CompareRow& c : rows)
    o << std::setw(10) << c.frequency << std::setw(6) << c.mode << std::setw(12) << c.dem_response << std::setw(12)
      << c.bare_response << std::setw(16) << c.model_response << std::setw(8) << std::showpos << 100 * c.model_error
      << "%" << std::noshowpos << std::setw(12) << c.eq7_response << std::setw(8) << std::showpos << 100 * c.eq7_error
      << "%" << std::noshowpos << std::setw(12) << c.eq20_response << std::setw(8) << std::showpos << 100 * c.eq20_error
      << "%" << std::noshowpos << "\n";
  return o.str();
}

}  // namespace bagdem
