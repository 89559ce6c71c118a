// FCC lattice sites lowest first, a batch at a time (fcc_lattice.hpp).
#include "fcc_lattice.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <queue>
#include <sstream>
#include <stdexcept>
#include <string>

namespace bagdem {
namespace {

const Vec3 kBasis[4] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};

// Cells along one axis: indices n with origin + n a <= hi (n counted as a double, as a site's
// coordinate is computed).
std::uint64_t cells(double origin, double a, double hi) {
  if (!(origin <= hi)) return 0;
  auto n = static_cast<std::uint64_t>(std::floor((hi - origin) / a));
  while (origin + static_cast<double>(n + 1) * a <= hi) ++n;
  while (n > 0 && !(origin + static_cast<double>(n) * a <= hi)) --n;
  return n + 1;
}

}  // namespace

FccLattice::FccLattice(const Vec3& lo, const Vec3& hi, double spacing, const Vec3& down, std::size_t wanted)
    : origin_(lo + Vec3::Constant(0.5 * spacing)), hi_(hi), down_(down), a_(spacing * std::numbers::sqrt2) {
  for (int k = 0; k < 3; ++k) n_[static_cast<std::size_t>(k)] = cells(origin_[k], a_, hi_[k]);
  down_.cwiseAbs().maxCoeff(&m_);
  p_ = (m_ + 1) % 3, q_ = (m_ + 2) % 3;
  if (p_ > q_) std::swap(p_, q_);
  if (layer_sites() > kMaxLayerSites) {
    std::ostringstream m;
    m << std::setprecision(3) << layer_sites() << " sites in one layer";
    throw std::length_error(m.str());
  }
  double e_low = INFINITY;
  e_top_ = -INFINITY;
  for (int c = 0; c < 8; ++c) {  // the extreme elevations lie at corners of the lattice's box
    Vec3 corner;
    for (int k = 0; k < 3; ++k) corner[k] = c >> k & 1 ? origin_[k] + a_ * static_cast<double>(n_[static_cast<std::size_t>(k)]) : origin_[k];
    e_low = std::min(e_low, -corner.dot(down_));
    e_top_ = std::max(e_top_, -corner.dot(down_));
  }
  if (!(e_top_ > e_low)) e_top_ = e_low + a_;
  batch_ = std::max<std::size_t>(256, 2 * wanted);
  // The slab that would hold the batch were the sites spread evenly over the elevations, and at
  // least a cell's height (every column meets it: a pass over the columns finds sites).
  slab_ = std::max((e_top_ - e_low) * std::min(1.0, static_cast<double>(batch_) / std::max(1.0, sites())), a_ * std::abs(down_[m_]));
  last_.e = e_low - 1e-9 * a_;  // below the lowest site, whatever the rounding of its elevation
}

FccLattice::Site FccLattice::site(const std::array<std::uint64_t, 3>& ijk, int basis) const {
  const Vec3 x = origin_ + a_ * (Vec3(static_cast<double>(ijk[0]), static_cast<double>(ijk[1]), static_cast<double>(ijk[2])) + kBasis[basis]);
  return {-x.dot(down_), ((ijk[0] * n_[1] + ijk[1]) * n_[2] + ijk[2]) * 4 + static_cast<std::uint64_t>(basis), x};
}

// The next batch: the batch_ lowest sites after the last one taken, among those of the slab of
// elevations above it (the slab doubled until it holds some, up to the top of the box). Each
// column of sites along the axis m_ is searched only where its elevations meet the slab.
void FccLattice::refill() {
  const auto M = static_cast<std::size_t>(m_), P = static_cast<std::size_t>(p_), Q = static_cast<std::size_t>(q_);
  std::priority_queue<Site> kept;  // the lowest batch_ so far (the highest on top)
  for (;;) {
    const double from = last_.e, to = from + slab_;
    const double step = -a_ * down_[m_];  // the change of elevation per cell along m
    for (std::uint64_t ip = 0; ip < n_[P]; ++ip)
      for (std::uint64_t iq = 0; iq < n_[Q]; ++iq)
        for (int b = 0; b < 4; ++b) {
          std::array<std::uint64_t, 3> ijk{};
          ijk[P] = ip, ijk[Q] = iq, ijk[M] = 0;
          const double e0 = site(ijk, b).e;
          double lo = (from - e0) / step, hi = (to - e0) / step;
          if (lo > hi) std::swap(lo, hi);
          const double first = std::max(0.0, std::floor(lo) - 1), last = std::min(static_cast<double>(n_[M]) - 1, std::ceil(hi) + 1);
          for (double k = first; k <= last; ++k) {
            ijk[M] = static_cast<std::uint64_t>(k);
            const Site s = site(ijk, b);
            if (!(s.e >= from && s.e < to) || (started_ && !(last_ < s)) || !(s.x.array() <= hi_.array()).all()) continue;
            if (kept.size() < batch_) kept.push(s);
            else if (s < kept.top()) kept.pop(), kept.push(s);
          }
        }
    if (!kept.empty() || to > e_top_) break;
    slab_ *= 2;  // nothing in this slab: a wider one
  }
  if (kept.size() < batch_ / 2) slab_ *= 2;
  ready_.clear();
  for (; !kept.empty(); kept.pop()) ready_.push_back(kept.top());  // highest first
  done_ = ready_.empty();
}

bool FccLattice::next(Vec3& x) {
  if (ready_.empty() && !done_) refill();
  if (ready_.empty()) return false;
  last_ = ready_.back();
  ready_.pop_back();
  started_ = true;
  x = last_.x;
  return true;
}

}  // namespace bagdem
