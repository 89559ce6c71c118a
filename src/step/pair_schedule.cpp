// The pairs stage (stage.hpp): which thread computes which pairs, and when (the kernel that computes
// them: pair_kernel.hpp). Each configuration of the model switches is compiled as its own loop
// (with_flags), so no switch is tested per contact.
#include "stepper.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "loops.hpp"
#include "pair_kernel.hpp"

namespace bagdem {

// ---- pair_contacts ---------------------------------------------------------------------------
// The pairs run in (i, j) order and each adds its force to f[i] and f[j] at once, so particle p
// receives its pairs (k, p), k < p ascending, then (p, j) ascending: partner order. On several
// threads each thread does this for its own range of particles, and the pairs across ranges go
// through records first (PairState): the same sums in the same order.
std::uint64_t Stepper::pair_contacts(BallSpan walls, BallSpan drift, std::uint64_t pipelined) {
  const std::size_t threads = static_cast<std::size_t>(std::max(1, omp_get_max_threads()));
  const bool several = p_.size() >= opt_.parallel_balls && ps_.pairs.size() > kParallelMin;
  const auto ranges = static_cast<std::uint32_t>(several ? threads : 1);
  if (ps_.ranges != ranges) derive_ranges(ranges);
  // The contact-law configuration is chosen once here, never inside the loop.
  std::uint64_t done = 0;
  with_flags([&]<bool T, bool R, bool E, bool U>() { done = pair_contacts_impl<T, R, E, U>(walls, drift, pipelined); },
             scene_.models.tangential, scene_.models.rolling, scene_.models.energy, p_.uniform);
  return done;
}

// The pairs and walls stages and the next step's kick_drift in one parallel region, in advance() when no later stage
// adds to the balls' forces (no film, no STL wall; fusable): each thread does its range's pairs,
// then its walls, then moves its balls on to the next step (their kick and drift). The staged step
// takes three regions (a fork and a join each, and each thread waits at each join for the slowest);
// here the threads meet once, and a thread's lead in one stage makes up for its lag in another.
// Why this is sound: pairs run i < j, so once range r's pairs are done no pair of this step reads
// its balls again (the cross pairs into range r were computed before, and r waited for those out of
// it before its last pairs, PairState): their forces are complete, their walls can be done and they
// can move on. The same operations on every ball in the
// same order as the staged step: the same bits (Determinism.FusedStepEqualsStaged).
void Stepper::fused_contacts() {
  pair_contacts(wall_stage(), drift_stage(true));  // the kick of this step is pending (advance)
  ctx_.balls = BallKick::drifted;
  ++pipe_.fused_steps;
}

void Stepper::end_pair_stage(const StageFold& fold, bool fused) {
  guard_.overlap_excess = fold.excess;
  if (fused) {
    end_walls(fold);
    end_drift(fold, p_, scene_.skin, nb_, guard_);
  }
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

// Pipelined steps (pipelined_region): the threads stay in one region for up to `pipelined` steps
// and meet nowhere. Range r goes on to step s once the ranges whose balls its cross pairs reach
// are at step s (RangeProgress::done), and every range's rebuild decision for it is known (the
// positions at step s - 1, Stepper::kSkinStep). A guard that fails ends the steps for all:
// each goes on only up to that step (pipe_.stop_before), so the first failing step is found.
// cross_part and range_part: pair_contacts_impl's parts of a range's step. Returns the steps done.
template <class CrossPart, class RangePart>
std::uint64_t Stepper::pipelined_pair_steps(const CrossPart& cross_part, const RangePart& range_part) {
  const std::uint64_t base = ps_.regions;
  const std::size_t nr = ps_.ranges;
  RangeProgress* progress = pipe_.progress.data();
  auto at_least = [progress](std::size_t q0, std::size_t q1, std::uint64_t steps) {
    for (std::size_t q = q0; q < q1; ++q)
      if (progress[q].done.load(std::memory_order_acquire) < steps) return false;
    return true;
  };
#pragma omp parallel
  {
    const auto me = static_cast<std::size_t>(omp_get_thread_num()), team = static_cast<std::size_t>(omp_get_num_threads());
    for (std::uint64_t s = 0;; ++s) {
      auto give_up = [this, s] { return pipe_.stop_before.load(std::memory_order_acquire) <= s; };
      if (s >= 2 && !spin_until([&] { return at_least(0, nr, s - 1); }, give_up)) break;
      if (give_up()) break;
      bool going = true;
      for (std::size_t r = me; going && r < nr; r += team) {
        going = spin_until([&] { return at_least(ps_.cross_from[r], r, s); }, give_up);
        if (going) {
          progress[r].fold = StageFold{};
          progress[r].cross = cross_travel(r, s);
          cross_part(r, progress[r].cross, base + s + 1, progress[r].fold);
        }
      }
      for (std::size_t r = me; going && r < nr; r += team) {
        going = range_part(r, progress[r].travel[s % 4], pipe_.wall_path[s], base + s + 1, progress[r].fold, give_up);
        if (going) end_range_step(r, s);
      }
      if (!going) break;
    }
  }
  return progress[0].done.load(std::memory_order_relaxed);
}

template <bool Tangential, bool Rolling, bool Energy, bool Uniform>
std::uint64_t Stepper::pair_contacts_impl(BallSpan walls, BallSpan drift, std::uint64_t pipelined) {
  const PairKernel<Tangential, Rolling, Energy, Uniform> kernel(ctx_, scene_, p_, ps_);
  // Range r in two parts: its particles' records from the ranges below and its pairs up to its
  // first cross pair; then, with the records of its cross pairs at hand (PairState), its other pairs
  // and, fused (fused_contacts), its walls and its drift. With one range the first part is all pairs.
  auto range_head = [&](std::size_t r, double travel, StageFold& fold) BAGDEM_INLINE_LAMBDA {
    for (std::uint32_t e = ps_.j_side_range[r]; e < ps_.j_side_range[r + 1]; ++e)
      kernel.add_record(ps_.j_side[e].particle, 2 * std::size_t{ps_.j_side[e].cross} + 1);
    kernel.span(ps_.pairs.begin[ps_.range_first[r]], ps_.records_from[r], travel, fold.excess);
  };
  auto range_tail = [&](std::size_t r, double travel, const WallMotion& cavity, StageFold& fold) BAGDEM_INLINE_LAMBDA {
    const std::uint32_t b0 = ps_.range_first[r], b1 = ps_.range_first[r + 1];
    kernel.span(ps_.records_from[r], ps_.pairs.begin[b1], travel, fold.excess);
    if (drift != nullptr) {
      (this->*walls)(b0, b1, cavity, fold);
      (this->*drift)(b0, b1, cavity, fold);
    }
  };
  const std::size_t ranges = ps_.ranges;
  if (ranges == 1) {
    StageFold fold;
    const double travel = nb_.travel;
    const WallMotion cavity = rigid_motion();
    auto one_range = [&](std::size_t r, StageFold& f) BAGDEM_INLINE_LAMBDA {
      range_head(r, travel, f);
      range_tail(r, travel, cavity, f);
    };
    run_items(one_range, 0, 1, fold);
    end_pair_stage(fold, drift != nullptr);
    return 0;
  }
  // On several threads, range r's part of a step in two: first the cross pairs into it (their
  // records; PairState), stamped when done; then the range, which waits for the stamps of the
  // ranges above that its cross pairs reach only when its pairs reach the first of them. Each
  // thread does the first part of all its ranges before the second (one range each; the loops
  // cover them all for any team size), so every stamp comes. `stamp` is the step's own value.
  auto cross_part = [&](std::size_t r, double travel, std::uint64_t stamp, StageFold& f) BAGDEM_INLINE_LAMBDA {
    const double start = omp_get_wtime();
    auto cross_into = [&](std::size_t q, double& excess) BAGDEM_INLINE_LAMBDA {
      const std::uint32_t *cs = ps_.cross_into.data() + ps_.cross_into_range[q], *end = ps_.cross_into.data() + ps_.cross_into_range[q + 1];
      for (; cs < end; cs += kBlock) kernel.cross_block(cs, std::min<std::size_t>(kBlock, static_cast<std::size_t>(end - cs)), travel, excess);
    };
    run_items(cross_into, r, r + 1, f.excess);
    ps_.cross_done[r].region.store(stamp, std::memory_order_release);
    balance_.add(r, omp_get_wtime() - start);
  };
  // false: given up waiting (give_up(); the range is left half done).
  auto range_part = [&](std::size_t r, double travel, const WallMotion& cavity, std::uint64_t stamp, StageFold& f,
                        const auto& give_up) BAGDEM_INLINE_LAMBDA {
    const double start = omp_get_wtime();
    auto head = [&](std::size_t q, StageFold& g) BAGDEM_INLINE_LAMBDA { range_head(q, travel, g); };
    run_items(head, r, r + 1, f);
    const double paused = omp_get_wtime();
    for (std::size_t c = r + 1; c <= ps_.records_upto[r]; ++c)
      if (!spin_until([&] { return ps_.cross_done[c].region.load(std::memory_order_acquire) >= stamp; }, give_up)) return false;
    const double resumed = omp_get_wtime();
    auto tail = [&](std::size_t q, StageFold& g) BAGDEM_INLINE_LAMBDA { range_tail(q, travel, cavity, g); };
    run_items(tail, r, r + 1, f);
    balance_.add(r, (paused - start) + (omp_get_wtime() - resumed));  // its work, not its wait
    return true;
  };
  if (pipelined == 0) {
    StageFold fold;
    const std::uint64_t region = ++ps_.regions;
    const double travel = nb_.travel;
    const WallMotion cavity = rigid_motion();
#pragma omp parallel
    {
      StageFold mine;
      const auto me = static_cast<std::size_t>(omp_get_thread_num()), team = static_cast<std::size_t>(omp_get_num_threads());
      for (std::size_t r = me; r < ranges; r += team) cross_part(r, travel, region, mine);
      for (std::size_t r = me; r < ranges; r += team) range_part(r, travel, cavity, region, mine, [] { return false; });
#pragma omp critical(bagdem_pair_excess)
      fold.merge(mine);
    }
    end_pair_stage(fold, drift != nullptr);
    return 0;
  }
  return pipelined_pair_steps(cross_part, range_part);
}

}  // namespace bagdem
