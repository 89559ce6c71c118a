// Pairs of bags on one structure (study/design.hpp, predict_pairs): two candidates at two places,
// predicted together from their maps.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "bagdem/case/load_case.hpp"
#include "bagdem/case/overrides.hpp"
#include "bagdem/error.hpp"
#include "bagdem/reduce/predict.hpp"
#include "bagdem/study/design.hpp"
#include "bagdem/study/study.hpp"

namespace bagdem::study {

namespace {
// A TOML basic string of any text.
std::string toml_string(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}
}  // namespace

std::string second_damper(const std::vector<std::pair<std::string, std::string>>& keys, double attach) {
  std::string set;
  for (const auto& [key, value] : keys) set += toml_string(key + " = " + value) + ", ";
  return "[{name = \"2\", set = [" + set + toml_string("primary.attach = \"" + short_text(attach) + " m\"") + "]}]";
}

namespace {

// A single row's structure: its candidate's case at its place (the cavity's mass in the mass matrix).
struct Place {
  std::shared_ptr<const Primary> primary;
  std::string error;  // why it does not load
};

// The pair's figures at `points` frequencies a band.
void predict_pair(const Primary& P, const std::vector<MappedDamper>& d, const std::vector<int>& modes, int points, Checks checks, DesignRow& r) {
  r.status = {};
  set_predicted_modes(predict_modes(P, d, P.amplitude, P.stepped_sine->frequencies, points, checks), modes, checks, r);
}

}  // namespace

std::vector<DesignRow> predict_pairs(const std::filesystem::path& case_dir, const std::vector<std::vector<std::string>>& sets,
                                     const std::vector<const EffectiveMap*>& maps, const std::vector<DesignRow>& singles,
                                     const std::vector<int>& modes, double budget_mass, std::size_t& overlapping) {
  // Each ranked single's structure, loaded once.
  std::map<std::pair<std::size_t, double>, Place> places;
  auto place = [&](const DesignRow& r) -> const Place& {
    auto [it, fresh] = places.try_emplace({r.candidate, r.position});
    if (fresh) try {
        Overrides o(sets.at(r.candidate));
        o.set(keys::attach, r.attach);
        it->second.primary = load_case(case_dir.string(), std::move(o).sets()).primary;
      } catch (const InputError& e) {
        it->second.error = e.what();
      }
    return it->second;
  };
  std::vector<const DesignRow*> usable;
  for (const DesignRow& r : singles)
    if (r.status.ranked() && std::isfinite(r.attach) && maps.at(r.candidate)) usable.push_back(&r);
  std::vector<DesignRow> pairs;
  std::vector<std::vector<MappedDamper>> dampers;  // each pair's, for the second prediction
  std::vector<Primary> structures;
  overlapping = 0;
  for (const DesignRow* a : usable)
    for (const DesignRow* b : usable) {
      if (!(a->position < b->position) || a->added_mass + b->added_mass > budget_mass * (1 + 1e-9)) continue;
      const Place &pa = place(*a), &pb = place(*b);
      if (pa.primary && pb.primary && b->attach - a->attach < pa.primary->half_extent + pb.primary->half_extent) {
        ++overlapping;  // two cavities in one stretch of the beam: not a pair of places
        continue;
      }
      DesignRow r = *a;
      r.pair = true, r.candidate2 = b->candidate, r.given2 = b->given, r.position2 = b->position, r.attach2 = b->attach, r.map2 = b->map;
      r.added_mass = a->added_mass + b->added_mass, r.mass_ratio = a->mass_ratio + b->mass_ratio;
      r.dem_db.clear(), r.dem_db_ci95.clear(), r.dem_objective = r.dem_objective_ci95 = NAN, r.dem_seeds = 0, r.rank = 0, r.pareto = false;
      Primary P;
      if (!pa.primary || !pb.primary) {
        r.status = {Standing::does_not_load, pa.primary ? pb.error : pa.error};
      } else {
        P = *pa.primary;
        P.carry_cavity(pb.primary->cavity_mass, pb.primary->at_cavity);
        dampers.push_back({{maps[a->candidate], pa.primary->at_cavity, "1"}, {maps[b->candidate], pb.primary->at_cavity, "2"}});
        predict_pair(P, dampers.back(), modes, kPairScreenPoints, Checks::none, r);
      }
      if (!pa.primary || !pb.primary) dampers.emplace_back();
      structures.push_back(std::move(P));
      pairs.push_back(std::move(r));
    }
  // The best screened, predicted again in full.
  std::vector<std::size_t> order(pairs.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    const bool rx = pairs[x].status.ranked(), ry = pairs[y].status.ranked();
    return rx != ry ? rx : rx && pairs[x].objective > pairs[y].objective;
  });
  for (std::size_t k = 0; k < order.size() && pairs[order[k]].status.ranked(); ++k) {
    const std::size_t i = order[k];
    if (k < kPairsChecked)
      predict_pair(structures[i], dampers[i], modes, 400, Checks::all, pairs[i]);
    else
      pairs[i].status = {Standing::screened, std::to_string(kPairScreenPoints) + " frequencies a band, not among the best " +
                                                 std::to_string(kPairsChecked)};
  }
  rank_rows(pairs);
  return pairs;
}

}  // namespace bagdem::study
