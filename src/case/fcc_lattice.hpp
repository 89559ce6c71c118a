// Private to src/case: the sites of a generated fill with fill = "lattice" (particle_fill.cpp).
//
// FCC sites in the box [lo, hi] with nearest-neighbour distance `spacing`, the first site
// spacing/2 in from `lo`, taken lowest first along `down`: by their elevation -x.down, sites of
// equal elevation in the order of their lattice indices (i along x, j along y, k along z, then the
// four basis sites). The sites are found a batch at a time, each batch only those of a slab of
// elevations, so that memory follows the sites taken, not the box: a box in metres where
// millimetres were meant holds 1e11 sites and more.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "bagdem/vec3.hpp"

namespace bagdem {

class FccLattice {
 public:
  // `wanted`: about how many sites the fill will take (sizes the batches). Throws
  // std::length_error when one layer of the box holds more than kMaxLayerSites sites.
  FccLattice(const Vec3& lo, const Vec3& hi, double spacing, const Vec3& down, std::size_t wanted);

  // The next site, lowest first; false when every site of the box was taken.
  bool next(Vec3& x);

  // Sites in one layer across `down` (the cost of finding a batch) and in the whole box.
  double layer_sites() const { return 4.0 * static_cast<double>(n_[p_]) * static_cast<double>(n_[q_]); }
  double sites() const { return 4.0 * static_cast<double>(n_[0]) * static_cast<double>(n_[1]) * static_cast<double>(n_[2]); }
  static constexpr double kMaxLayerSites = 1e8;

 private:
  struct Site {
    double e;             // elevation -x.down (m)
    std::uint64_t index;  // ((i n_j + j) n_k + k) 4 + basis
    Vec3 x;
    bool operator<(const Site& o) const { return e < o.e || (e == o.e && index < o.index); }
  };
  void refill();
  Site site(const std::array<std::uint64_t, 3>& ijk, int basis) const;

  Vec3 origin_, hi_, down_;
  double a_;                          // the cubic cell's edge (m)
  std::array<std::uint64_t, 3> n_{};  // cells along x, y, z
  int m_ = 2, p_ = 0, q_ = 1;         // m: the axis closest to `down`; p, q: the others
  double e_top_ = 0;                  // the highest elevation of any site (m)
  double slab_ = 0;                   // the batch's slab of elevations (m), doubled when too thin
  std::size_t batch_ = 0;             // sites a batch keeps at most
  std::vector<Site> ready_;           // the batch, highest first (taken from the back)
  bool started_ = false, done_ = false;
  Site last_{};                       // the last site taken
};

}  // namespace bagdem
