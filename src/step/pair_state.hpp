// The candidate pair list with its contact histories, and how the threads share its pairs.
#pragma once
#include <cstdint>
#include <vector>

#include "bagdem/neighbour/broad_phase.hpp"
#include "bagdem/vec3.hpp"
#include "history.hpp"

namespace bagdem {

// Contact histories and per-pair results on the current candidate pair list.
//
// Pair contacts on several threads. The particles are cut into `ranges` contiguous ranges (one per
// thread; at first of about equal pair counts, then moved by the clock, SpanBalance), and each
// range's pairs are summed onto its particles in pair order by one thread, as a single thread sums
// them all. The spatial order of the balls makes the ranges slabs of the bed, so few pairs cross
// between them (1-4% in a packed bed). A pair whose particles lie in two ranges (a cross pair: i's
// range is below j's) is computed first, by the thread of j's range, into two records. i adds
// its record at the pair's place among its own pairs; j adds its records, in the order of their i,
// before its own range reaches it: where a single thread adds them too (j's partners below its range
// come first in partner order). The same operands in the same order: the same bits for any thread
// count. The threads do not meet between the cross pairs and the ranges: a range's thread waits
// for the records of its cross pairs only when its pairs reach the first of them (the range's last
// balls; by then the threads of the ranges above have long computed them), and a thread never
// waits before it has computed the cross pairs into its own ranges, so every wait ends.
struct PairState {
  CandidatePairs pairs;                      // i < j, canonical order
  std::vector<std::uint32_t> first;          // i of each pair
  ContactHistories hist;                     // per pair
  std::vector<std::uint8_t> touching;        // per pair: 1 in contact at the last step (its history may be set), 0 apart
  // Per pair: the value of the neighbours' `travel` (Neighbours) from which on the pair may touch (unit: m). A pair
  // found apart by a gap g when travel was t0 cannot close while travel < t0 + g/2 (each of its
  // balls moved at most travel - t0 since), so the pair stage does not look at it until then. In a
  // shaken bed most candidate pairs sleep for hundreds of steps; they cost one comparison a step.
  // Single precision rounded down (round_down_to_float): a pair may wake a little early, never late.
  std::vector<float> wake;
  // The largest j - i of the pairs: the pair stage at ball i reaches balls up to i + reach, most of
  // them for the first time in the step (their state is fetched ahead: pair_contacts_impl).
  std::size_t reach = 0;

  std::uint32_t ranges = 0;                  // 0: not yet cut for this list (derive_ranges)
  std::vector<std::uint32_t> range_first;    // ranges + 1: range r holds particles [range_first[r], range_first[r + 1])
  std::vector<std::uint32_t> cross;          // the cross pairs, ascending
  std::vector<std::uint8_t> is_cross;        // per pair
  struct JSide {
    std::uint32_t particle, cross;           // j of cross pair `cross`
  };
  std::vector<JSide> j_side;                 // by particle, then by i
  std::vector<std::uint32_t> j_side_range;   // ranges + 1: range r's entries of j_side
  std::vector<std::uint32_t> cross_into;     // the cross pairs (indices into `cross`) by j's range, ascending within each
  std::vector<std::uint32_t> cross_into_range;  // ranges + 1: range r's entries of cross_into
  std::vector<std::uint32_t> records_from;   // per range: its first cross pair (its pairs' end when it has none)
  std::vector<std::uint32_t> records_upto;   // per range: the highest range its cross pairs reach (itself when none)
  std::vector<std::uint32_t> cross_from;     // per range: the lowest range whose balls the cross pairs into it reach (itself when none)
  struct Record {
    Vec3 force;   // on the record's particle: +F on i, -F on j (unit: N)
    Vec3 torque;  // on the record's particle (unit: N m)
  };
  std::vector<Record> rec;                   // per cross pair c: i's (2c) and j's (2c + 1); zero when apart
  std::vector<Vec3> rec_diss;                // per cross pair (energy tally): its (normal, tangential, rolling) dissipation this step, half to each particle (unit: J)
};

}  // namespace bagdem
