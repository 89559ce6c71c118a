// Spatial hashing broad phase. Cells of edge h = 2 r_max + skin (no pair can span more than one
// cell); integer cell coordinates are hashed into a power-of-two table (Teschner et al., "Optimized
// spatial hashing for collision detection of deformable objects", VMV 2003), particles are sorted by
// bucket with a counting sort, and each particle scans the buckets of its 27 neighbour cells. Two
// cells may share a bucket, so the bucket list is de-duplicated before scanning.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "bagdem/neighbour/broad_phase.hpp"

namespace bagdem {
namespace {

class SpatialHash final : public BroadPhase {
 public:
  void find(const std::vector<Vec3>& x, const std::vector<double>& r, double skin,
            CandidatePairs& out) override {
    const std::size_t n = x.size();
    const double r_max = n ? *std::max_element(r.begin(), r.end()) : 0.0;
    const double h = 2 * r_max + skin;
    const double inv_h = 1.0 / h;
    std::size_t table = 64;
    while (table < 2 * n) table *= 2;
    const std::uint64_t mask = table - 1;

    cell_.resize(n);
    bucket_of_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const Cell c{static_cast<std::int64_t>(std::floor(x[i].x() * inv_h)),
                   static_cast<std::int64_t>(std::floor(x[i].y() * inv_h)),
                   static_cast<std::int64_t>(std::floor(x[i].z() * inv_h))};
      cell_[i] = c;
      bucket_of_[i] = static_cast<std::uint32_t>(hash(c) & mask);
    }
    // Counting sort of particle indices by bucket (stable: ascending index within a bucket).
    start_.assign(table + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++start_[bucket_of_[i] + 1];
    for (std::size_t b = 0; b < table; ++b) start_[b + 1] += start_[b];
    sorted_.resize(n);
    fill_ = std::vector<std::uint32_t>(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) sorted_[fill_[bucket_of_[i]]++] = static_cast<std::uint32_t>(i);

    build_candidates(n, out, scratch_, [&](std::size_t i, std::vector<std::uint32_t>& buf) {
      std::uint32_t buckets[27];
      int nb = 0;
      const Cell c = cell_[i];
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz)
            buckets[nb++] = static_cast<std::uint32_t>(hash({c.x + dx, c.y + dy, c.z + dz}) & mask);
      std::sort(buckets, buckets + nb);
      nb = static_cast<int>(std::unique(buckets, buckets + nb) - buckets);
      for (int k = 0; k < nb; ++k) {
        for (std::uint32_t s = start_[buckets[k]]; s < start_[buckets[k] + 1]; ++s) {
          const std::uint32_t j = sorted_[s];
          if (j <= i) continue;
          const double cut = r[i] + r[j] + skin;
          if ((x[i] - x[j]).squaredNorm() < cut * cut) buf.push_back(j);
        }
      }
    });
  }

 private:
  CandidateScratch scratch_;
  struct Cell {
    std::int64_t x, y, z;
  };
  static std::uint64_t hash(const Cell& c) {
    return (static_cast<std::uint64_t>(c.x) * 73856093ULL) ^
           (static_cast<std::uint64_t>(c.y) * 19349663ULL) ^
           (static_cast<std::uint64_t>(c.z) * 83492791ULL);
  }
  std::vector<Cell> cell_;
  std::vector<std::uint32_t> bucket_of_, start_, fill_, sorted_;
};

}  // namespace

std::unique_ptr<BroadPhase> make_spatial_hash() { return std::make_unique<SpatialHash>(); }

}  // namespace bagdem
