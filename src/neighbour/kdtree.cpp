// k-d tree broad phase: nanoflann (Blanco & Rai, 2014) radius search around each particle with the
// largest possible cut-off r_i + r_max + skin, then the exact per-pair cut-off r_i + r_j + skin.
#include <nanoflann.hpp>

#include <algorithm>

#include "bagdem/neighbour/broad_phase.hpp"

namespace bagdem {
namespace {

// nanoflann's dataset adaptor over the position array.
struct PointCloud {
  const std::vector<Vec3>* x = nullptr;
  std::size_t kdtree_get_point_count() const { return x->size(); }
  double kdtree_get_pt(std::size_t i, std::size_t d) const { return (*x)[i][static_cast<int>(d)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const { return false; }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointCloud>,
                                                 PointCloud, 3, std::uint32_t>;

class KdTree final : public BroadPhase {
 public:
  void find(const std::vector<Vec3>& x, const std::vector<double>& r, double skin,
            CandidatePairs& out) override {
    const std::size_t n = x.size();
    cloud_.x = &x;
    Tree tree(3, cloud_, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    tree.buildIndex();
    const double r_max = n ? *std::max_element(r.begin(), r.end()) : 0.0;
    build_candidates(n, out, scratch_, [&](std::size_t i, std::vector<std::uint32_t>& buf) {
      thread_local std::vector<std::pair<std::uint32_t, double>> hits;
      hits.clear();
      // The search radius is padded a little; the exact cut-off is then decided with the same
      // arithmetic as the other broad phases (nanoflann's distance rounds differently, so pairs at
      // exactly the cut-off would otherwise disagree).
      const double reach = (r[i] + r_max + skin) * (1 + 1e-9);
      nanoflann::SearchParams params;
      params.sorted = false;
      tree.radiusSearch(x[i].data(), reach * reach, hits, params);
      for (const auto& hit : hits) {
        const std::uint32_t j = hit.first;
        if (j <= i) continue;
        const double cut = r[i] + r[j] + skin;
        if ((x[i] - x[j]).squaredNorm() < cut * cut) buf.push_back(j);
      }
    });
  }

 private:
  CandidateScratch scratch_;
  PointCloud cloud_;
};

}  // namespace

std::unique_ptr<BroadPhase> make_kdtree() { return std::make_unique<KdTree>(); }

}  // namespace bagdem
