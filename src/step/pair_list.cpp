// The neighbours stage (stage.hpp): the Verlet pair list renewed with its contact histories carried
// over, the walls near each ball, and the pair list cut into the threads' ranges (PairState).
#include <algorithm>
#include <cmath>

#include "loops.hpp"
#include "stepper.hpp"

namespace bagdem {

// ---- neighbours --------------------------------------------------------------------------------
void Stepper::update_neighbours(bool force_rebuild) {
  const std::size_t n = p_.size();
  if (!force_rebuild && !nb_.needs_rebuild && !meshes_need_rebuild()) return;
  ++nb_.builds;
  nb_.x_at_build = p_.x;
  // The new list and its histories go into spare buffers (kept between rebuilds, so a rebuild
  // reuses their memory), then swap places with the current ones.
  CandidatePairs& fresh = nb_.spare.pairs;
  nb_.broad->find(p_.x, p_.radius, scene_.skin, fresh);

  // Carry contact histories over: merge the old and new partner lists of each i (both sorted).
  ContactHistories& carried = nb_.spare.hist;
  carried.assign(fresh.size(), scene_.models.tangential, scene_.models.rolling, scene_.models.energy);
  if (carried.any_role() && !ps_.pairs.partner.empty()) {
    parallel_for(n, [&](std::size_t i) {
      std::uint32_t a = ps_.pairs.begin[i], b = fresh.begin[i];
      const std::uint32_t a_end = ps_.pairs.begin[i + 1], b_end = fresh.begin[i + 1];
      while (a < a_end && b < b_end) {
        if (ps_.pairs.partner[a] < fresh.partner[b]) { ++a; continue; }
        if (ps_.pairs.partner[a] > fresh.partner[b]) { ++b; continue; }
        carried.carry(b, ps_.hist, a);
        ++a, ++b;
      }
    });
  }
  std::swap(ps_.pairs, nb_.spare.pairs);
  ps_.hist.swap(nb_.spare.hist);
  derive_pair_buffers();
  cavity_.pos_at_build = cavity_.now.position;
  cavity_.shear_at_build = cavity_.now.shear;
  find_near_walls();
  if (!mesh_.surfaces.empty()) build_mesh_candidates(p_.x, film_.x, cavity_.now.position);
}

// The walls within skin of each ball's surface at the build (nb_.x_at_build, the cavity where it was
// then). Until the next build neither moves more than skin/2, so no other wall can be touched.
// A ball with no wall near touched none at the last step either (that wall would be near): it has
// no wall history to close (wall_contacts).
void Stepper::find_near_walls() {
  const std::size_t n = p_.size(), nw = scene_.walls.size();
  CavityState at_build = cavity_.now;
  at_build.position = cavity_.pos_at_build;
  at_build.shear = cavity_.shear_at_build;
  // Near the bounds: the centre within skin of them (it moves less than skin relative to the cavity
  // before the next build, so the others stay inside).
  std::vector<std::uint8_t>& in_reach = walls_.near_scratch;
  in_reach.resize(n);
  parallel_for(n, [&](std::size_t p) {
    const Vec3 x = nb_.x_at_build[p];
    const double s = structure_.tilt ? (x - at_build.position - scene_.cavity_reference).dot(structure_.load_axis) : 0.0;
    const Vec3 x_local = x - at_build.position - s * at_build.shear;
    std::uint32_t near = 0;
    for (std::size_t w = 0; w < nw; ++w) {
      Vec3 normal;
      if (wall_distance(scene_.walls[w], x_local, normal) - p_.radius[p] < scene_.skin) near |= 1u << w;
    }
    walls_.near[p] = near;
    const double d_bounds = std::min((x_local - scene_.cavity_lo).minCoeff(), (scene_.cavity_hi - x_local).minCoeff());
    in_reach[p] = near != 0 || d_bounds < scene_.skin;
  });
  walls_.near_balls.clear();
  for (std::size_t p = 0; p < n; ++p) {
    if (in_reach[p]) walls_.near_balls.push_back(static_cast<std::uint32_t>(p));
    else if (structure_.couple && mesh_.surfaces.empty()) structure_.cavity_load[p].setZero();  // as the wall stage leaves a ball without a wall near
  }
}

// From the installed pair list and its histories: the per-pair buffers.
void Stepper::derive_pair_buffers() {
  const std::size_t n = p_.size();
  const std::size_t np = ps_.pairs.size();
  // A pair whose history was carried over may be touching; a fresh pair is not (all-zero history).
  ps_.touching.assign(np, 0);
  ps_.wake.assign(np, 0.0f);  // every pair looked at in the next pair stage (nb_.travel >= 0)
  nb_.travel = 0.0;
  nb_.far_check_at = -1.0;       // the next drift checks the distances from nb_.x_at_build (near_skin_edge)
  nb_.near_edge = false;         // every ball is where it was at the build
  for (std::size_t k = 0; k < np; ++k) ps_.touching[k] = ps_.hist.holds(k);
  ps_.first.resize(np);
  ps_.reach = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t k = ps_.pairs.begin[i]; k < ps_.pairs.begin[i + 1]; ++k) {
      ps_.first[k] = static_cast<std::uint32_t>(i);
      ps_.reach = std::max<std::size_t>(ps_.reach, ps_.pairs.partner[k] - i);
    }
  ps_.ranges = 0;  // cut into ranges at the next pair stage, for its thread count (derive_ranges)
}

// The particles cut into `ranges` ranges, the cross pairs and their records (PairState). Redone
// after each neighbour build, when the thread count changes and when the pair stage's balance moved
// its cuts. The cuts are the balance's (SpanBalance), at first of about equal pair counts.
void Stepper::derive_ranges(std::uint32_t ranges) {
  const std::size_t n = p_.size(), np = ps_.pairs.size();
  const CandidatePairs& pairs = ps_.pairs;
  if (balance_.spans() != ranges || balance_.cuts().back() != n) {
    std::vector<std::uint32_t> cuts(ranges + 1, static_cast<std::uint32_t>(n));
    cuts[0] = 0;
    for (std::uint32_t r = 1; r < ranges; ++r) cuts[r] = ps_.first[np * r / ranges];
    balance_.reset(cuts);
  }
  ps_.ranges = ranges;
  ps_.range_first = balance_.cuts();
  ps_.cross.clear();
  ps_.is_cross.assign(np, 0);
  for (std::uint32_t r = 0; r < ranges; ++r)
    for (std::uint32_t k = pairs.begin[ps_.range_first[r]]; k < pairs.begin[ps_.range_first[r + 1]]; ++k)
      if (pairs.partner[k] >= ps_.range_first[r + 1]) {
        ps_.cross.push_back(k);
        ps_.is_cross[k] = 1;
      }
  ps_.j_side.clear();
  for (std::size_t c = 0; c < ps_.cross.size(); ++c)
    ps_.j_side.push_back({pairs.partner[ps_.cross[c]], static_cast<std::uint32_t>(c)});
  // By j; for one j by i, as the cross list is.
  std::stable_sort(ps_.j_side.begin(), ps_.j_side.end(),
                   [](const PairState::JSide& a, const PairState::JSide& b) { return a.particle < b.particle; });
  ps_.j_side_range.resize(ranges + 1);
  for (std::uint32_t r = 0; r <= ranges; ++r)
    ps_.j_side_range[r] = static_cast<std::uint32_t>(
        std::lower_bound(ps_.j_side.begin(), ps_.j_side.end(), ps_.range_first[r],
                         [](const PairState::JSide& e, std::uint32_t p) { return e.particle < p; }) -
        ps_.j_side.begin());
  // The cross pairs by j's range (each range's thread computes those into it), and where each
  // range's own pairs first need records (PairState).
  auto range_of = [&](std::uint32_t p) {
    return static_cast<std::uint32_t>(std::upper_bound(ps_.range_first.begin(), ps_.range_first.end(), p) - ps_.range_first.begin() - 1);
  };
  ps_.cross_into_range.assign(ranges + 1, 0);
  ps_.records_upto.resize(ranges);
  ps_.records_from.resize(ranges);
  ps_.cross_from.resize(ranges);
  for (std::uint32_t r = 0; r < ranges; ++r) {
    ps_.records_upto[r] = ps_.cross_from[r] = r;
    ps_.records_from[r] = pairs.begin[ps_.range_first[r + 1]];
  }
  for (const std::uint32_t k : ps_.cross) {
    const std::uint32_t i = ps_.first[k], ri = range_of(i), rj = range_of(pairs.partner[k]);
    ++ps_.cross_into_range[rj + 1];
    ps_.records_upto[ri] = std::max(ps_.records_upto[ri], rj);
    ps_.cross_from[rj] = std::min(ps_.cross_from[rj], ri);
    ps_.records_from[ri] = std::min(ps_.records_from[ri], k);
  }
  for (std::uint32_t r = 0; r < ranges; ++r) ps_.cross_into_range[r + 1] += ps_.cross_into_range[r];
  ps_.cross_into.resize(ps_.cross.size());
  std::vector<std::uint32_t> fill(ps_.cross_into_range.begin(), ps_.cross_into_range.end() - 1);
  for (std::size_t c = 0; c < ps_.cross.size(); ++c)
    ps_.cross_into[fill[range_of(pairs.partner[ps_.cross[c]])]++] = static_cast<std::uint32_t>(c);
  ps_.cross_done = std::vector<PairContacts::CrossStamp>(ranges);
  pipe_.progress = std::vector<RangeProgress>(ranges);
  ps_.rec.assign(2 * ps_.cross.size(), {Vec3::Zero(), Vec3::Zero()});
  ps_.rec_diss.assign(scene_.models.energy ? ps_.cross.size() : 0, Vec3::Zero());
}

}  // namespace bagdem
