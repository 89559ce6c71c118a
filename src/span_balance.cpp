#include "bagdem/span_balance.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace bagdem {

void SpanBalance::reset(std::vector<std::uint32_t> cuts) {
  cuts_ = std::move(cuts);
  time_.assign(spans(), Slot{});
  steps_ = 0;
}

bool SpanBalance::end_step() {
  if (spans() < 2 || ++steps_ < window_) return false;
  std::vector<double> seconds(spans());
  double slowest = 0, sum = 0;
  for (std::size_t r = 0; r < spans(); ++r) {
    seconds[r] = time_[r].seconds;
    slowest = std::max(slowest, seconds[r]);
    sum += seconds[r];
    time_[r].seconds = 0;
  }
  steps_ = 0;
  if (!(slowest > (1.0 + tolerance_) * sum / static_cast<double>(spans()))) return false;
  std::vector<std::uint32_t> moved = balanced_cuts(cuts_, seconds);
  if (moved == cuts_) return false;
  cuts_ = std::move(moved);
  ++moves_;
  return true;
}

std::vector<std::uint32_t> balanced_cuts(const std::vector<std::uint32_t>& cuts, const std::vector<double>& seconds) {
  const std::size_t spans = cuts.size() - 1;
  const double items = static_cast<double>(cuts.back() - cuts.front());
  if (spans < 2 || items <= 0) return cuts;
  // Each span's speed (items per second), where it was measured.
  std::vector<double> speed(spans, 0.0);
  double known = 0;
  std::size_t measured = 0;
  for (std::size_t r = 0; r < spans; ++r) {
    const double size = static_cast<double>(cuts[r + 1] - cuts[r]);
    if (size > 0 && seconds[r] > 0) speed[r] = size / seconds[r], known += speed[r], ++measured;
  }
  if (measured == 0) return cuts;
  for (double& s : speed)
    if (s == 0) s = known / static_cast<double>(measured);
  double all = 0;
  for (double s : speed) all += s;
  // Shares by speed, each at most doubled or halved (an empty span counts as one item): clamped and
  // scaled to sum 1 until no clamp is left active.
  std::vector<double> share(spans), lo(spans), hi(spans);
  for (std::size_t r = 0; r < spans; ++r) {
    const double before = std::max(1.0, static_cast<double>(cuts[r + 1] - cuts[r])) / items;
    lo[r] = 0.5 * before, hi[r] = 2.0 * before;
    share[r] = speed[r] / all;
  }
  for (int pass = 0; pass < 64; ++pass) {
    double total = 0;
    bool clamped = false;
    for (std::size_t r = 0; r < spans; ++r) {
      const double s = std::clamp(share[r], lo[r], hi[r]);
      clamped = clamped || s != share[r];
      share[r] = s, total += s;
    }
    for (double& s : share) s /= total;
    if (!clamped) break;
  }
  std::vector<std::uint32_t> out(cuts.size());
  out.front() = cuts.front();
  out.back() = cuts.back();
  double at = 0;
  for (std::size_t r = 1; r < spans; ++r) {
    at += share[r - 1];
    const auto c = cuts.front() + static_cast<std::uint32_t>(std::llround(at * items));
    out[r] = std::clamp(c, out[r - 1], cuts.back());
  }
  return out;
}

}  // namespace bagdem
