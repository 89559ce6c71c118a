// Dynamic load balance of a stage that runs on several threads, one contiguous span of items per
// thread. The spans start equal and their cuts move by the clock: each thread times its own span,
// and every `window` steps the cuts are moved so that each thread gets items in proportion to the
// speed it showed (items per second). Equal cuts are not enough because
//  - the cores of a shared machine do not run equally fast: one core can run a third slower than the
//    other while both are busy, and which one varies between runs;
//  - the work per item is uneven: balls at the walls, touching pairs, the dense bottom of a bed.
// Every item writes only its own slots and the pair stage's records keep its sums in one order
// (PairState), so where the cuts lie changes no result: moving them by the clock keeps every run
// bitwise the same for any thread count (Determinism tests run with cuts moved at every step).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace bagdem {

class SpanBalance {
 public:
  static constexpr std::uint32_t kWindow = 64;  // steps timed before the cuts may move
  static constexpr double kTolerance = 0.03;    // they move when the slowest span took 3% more than the mean

  // Spans [cuts[r], cuts[r + 1]), r < cuts.size() - 1; the timing starts afresh.
  void reset(std::vector<std::uint32_t> cuts);
  std::size_t spans() const { return cuts_.empty() ? 0 : cuts_.size() - 1; }
  const std::vector<std::uint32_t>& cuts() const { return cuts_; }
  std::uint32_t begin(std::size_t r) const { return cuts_[r]; }
  std::uint32_t end(std::size_t r) const { return cuts_[r + 1]; }
  // Time spent on span r this step (unit: s). Threads call it for distinct spans at once.
  void add(std::size_t r, double seconds) { time_[r].seconds += seconds; }
  // At the end of a step: once `window` steps are timed, moves the cuts when the spans' times
  // differ by more than the tolerance. Returns whether they moved.
  bool end_step();
  // Steps until the end of the window (end_step looks at the clocks then).
  std::uint32_t steps_to_window() const { return window_ > steps_ ? window_ - steps_ : 1; }
  // Tests: move after every `window` steps when the times differ at all (tolerance 0).
  void set_window(std::uint32_t window, double tolerance) { window_ = window, tolerance_ = tolerance; }
  std::uint64_t moves() const { return moves_; }

 private:
  struct alignas(64) Slot {  // one cache line per thread
    double seconds = 0;
  };
  std::vector<std::uint32_t> cuts_;
  std::vector<Slot> time_;
  std::uint32_t steps_ = 0;
  std::uint32_t window_ = kWindow;
  double tolerance_ = kTolerance;
  std::uint64_t moves_ = 0;
};

// New cuts of [cuts.front(), cuts.back()) for spans that took seconds[r]: span r's share is
// proportional to its speed, (its items) / seconds[r], and at most doubles or halves in one move
// (a thread held up by the system once does not give its work away). A span without items or
// time is given the mean speed of the others.
std::vector<std::uint32_t> balanced_cuts(const std::vector<std::uint32_t>& cuts, const std::vector<double>& seconds);

}  // namespace bagdem
