// SpanBalance (span_balance.hpp): the threads' spans move so that each thread gets items in
// proportion to the speed it showed. Reference: the cuts computed by hand from the rule (shares by
// items per second, each at most doubled or halved in one move); tolerance: one item (rounding).
// That the cuts change no result is shown by the Determinism tests, which move them at every step.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "bagdem/span_balance.hpp"

using namespace bagdem;

// Two equal spans, the second core 1.4x slower: speeds 500/1.0 and 500/1.4 items per second, so the
// first span gets 1000 x 500 / (500 + 357.14) = 583.3 items. That cut gives both threads the same
// time: 583 / 500 = 1.166 s and 417 x 1.4 / 500 = 1.168 s.
TEST(SpanBalance, CutsFollowTheThreadsSpeeds) {
  const std::vector<std::uint32_t> cuts = balanced_cuts({0, 500, 1000}, {1.0, 1.4});
  ASSERT_EQ(cuts.size(), 3u);
  EXPECT_EQ(cuts.front(), 0u);
  EXPECT_EQ(cuts.back(), 1000u);
  EXPECT_NEAR(cuts[1], 583.3, 1.0);
  // Three spans of a range that does not start at zero: the middle one twice as fast.
  const std::vector<std::uint32_t> three = balanced_cuts({100, 400, 700, 1000}, {1.0, 0.5, 1.0});
  EXPECT_NEAR(three[1], 100 + 900 * 0.25, 1.0);
  EXPECT_NEAR(three[2], 100 + 900 * 0.75, 1.0);
  EXPECT_EQ(three[3], 1000u);
}

// A span that took 100x longer (its thread was held up by the system) gives away at most half its
// items in one move: 500 -> 250, the other 500 -> 750.
TEST(SpanBalance, OneMoveAtMostHalvesOrDoublesASpan) {
  const std::vector<std::uint32_t> cuts = balanced_cuts({0, 500, 1000}, {1.0, 100.0});
  EXPECT_NEAR(cuts[1], 750.0, 1.0);
  // An empty span (no items, no time) gets items again, at most two (its one item, doubled).
  const std::vector<std::uint32_t> empty = balanced_cuts({0, 0, 1000}, {0.0, 1.0});
  EXPECT_GE(empty[1], 1u);
  EXPECT_LE(empty[1], 2u);
}

// The cuts move only once a window of steps is timed, and only when the slowest span took more
// than the tolerance over the mean.
TEST(SpanBalance, MovesAfterTheWindowAndBeyondTheTolerance) {
  SpanBalance b;
  b.set_window(4, 0.03);
  b.reset({0, 500, 1000});
  // Within 2% of each other: no move.
  for (int step = 0; step < 4; ++step) {
    b.add(0, 1.00);
    b.add(1, 1.02);
    EXPECT_FALSE(b.end_step());
  }
  EXPECT_EQ(b.cuts()[1], 500u);
  // 40% apart: no move before the fourth step, then the cut of CutsFollowTheThreadsSpeeds.
  for (int step = 0; step < 4; ++step) {
    b.add(0, 1.0);
    b.add(1, 1.4);
    EXPECT_EQ(b.end_step(), step == 3) << "step " << step;
  }
  EXPECT_NEAR(b.cuts()[1], 583.3, 1.0);
  EXPECT_EQ(b.moves(), 1u);
  // One span: nothing to balance.
  SpanBalance one;
  one.set_window(1, 0.0);
  one.reset({0, 1000});
  one.add(0, 5.0);
  EXPECT_FALSE(one.end_step());
}
