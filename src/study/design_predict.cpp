// A design's candidate predicted at a place from its map (study/design.hpp, predict_row).
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "bagdem/case/load_case.hpp"
#include "bagdem/reduce/predict.hpp"
#include "bagdem/study/design.hpp"

namespace bagdem::study {

// Every chosen mode's predicted reduction of a candidate at a place (its overrides `sets`).
void predict_row(const std::filesystem::path& case_dir, const std::vector<std::string>& sets, const EffectiveMap& map, const std::vector<int>& modes,
                 DesignRow& r) {
  const Scene s = load_case(case_dir.string(), sets);
  refuse_several_dampers(s, "bagdem design", "places one damper");
  const Primary& P = *s.primary;
  r.attach = P.attach;
  if (modes == std::vector<int>{0}) {  // a random force: its RMS in the band
    const RandomPredictionRange p = predict_random_range(P, map, P.random_rms, P.random_lo, P.random_hi, P.random_lines);
    if (!p.mean.outside.empty() || !p.mean.converged) {
      r.status = {Standing::outside_map, "(" + (p.mean.outside.empty() ? std::string("no convergence") : p.mean.outside) + ")"};
      return;
    }
    r.bare_rms = p.mean.bare_response_rms;
    r.db[0] = 20 * std::log10(r.bare_rms / p.mean.response_rms);
    r.db_lo[0] = 20 * std::log10(r.bare_rms / p.response_rms_hi), r.db_hi[0] = 20 * std::log10(r.bare_rms / p.response_rms_lo);
    set_objective(r);
    return;
  }
  set_predicted_modes(predict_modes(P, map, P.amplitude, P.stepped_sine->frequencies), modes, Checks::all, r);
}

void set_predicted_modes(const std::vector<PredictedMode>& predicted, const std::vector<int>& modes, Checks checks, DesignRow& r) {
  r.db.assign(modes.size(), NAN), r.db_lo = r.db, r.db_hi = r.db;
  r.at_band_edge = 0;
  r.interpolation_db = checks == Checks::all ? 0.0 : NAN;
  for (const PredictedMode& m : predicted) {
    const auto k = std::find(modes.begin(), modes.end(), static_cast<int>(m.mode));
    if (k == modes.end()) continue;
    const std::size_t i = static_cast<std::size_t>(k - modes.begin());
    if (!m.outside.empty()) {
      const std::string bag = r.pair ? ", bag " + std::to_string(m.outside_damper + 1) : "";
      r.status = {Standing::outside_map, "at mode " + std::to_string(modes[i]) + " (" + m.outside_why + bag + ")"};
      return;
    }
    r.db[i] = m.reduction_db;
    if (checks != Checks::none) r.db_lo[i] = m.reduction_db_lo, r.db_hi[i] = m.reduction_db_hi;
    r.at_band_edge += m.at_band_edge ? 1 : 0;
    if (checks == Checks::all)  // NaN stays NaN
      r.interpolation_db = std::isnan(m.interpolation_db) ? NAN : std::max(r.interpolation_db, m.interpolation_db);
  }
  for (std::size_t i = 0; i < modes.size(); ++i)
    if (!std::isfinite(r.db[i])) {
      r.status = {Standing::mode_not_in_stepped_sine, std::to_string(modes[i])};
      return;
    }
  set_objective(r);
}

}  // namespace bagdem::study
