// O(N^2) reference broad phase: every pair tested. Used by tests to check the others.
#include "bagdem/neighbour/broad_phase.hpp"

namespace bagdem {
namespace {

class BruteForce final : public BroadPhase {
 public:
  void find(const std::vector<Vec3>& x, const std::vector<double>& r, double skin,
            CandidatePairs& out) override {
    build_candidates(x.size(), out, scratch_, [&](std::size_t i, std::vector<std::uint32_t>& buf) {
      for (std::size_t j = i + 1; j < x.size(); ++j) {
        const double cut = r[i] + r[j] + skin;
        if ((x[i] - x[j]).squaredNorm() < cut * cut) buf.push_back(static_cast<std::uint32_t>(j));
      }
    });
  }

 private:
  CandidateScratch scratch_;
};

}  // namespace

std::unique_ptr<BroadPhase> make_brute_force() { return std::make_unique<BruteForce>(); }

}  // namespace bagdem
