// Fixed cavity: at rest at its rest place.
#include "bagdem/motion/motion.hpp"

namespace bagdem {
namespace {
class FixedMotion final : public Motion {
 public:
  CavityState at(double) const override { return {}; }
  double max_speed() const override { return 0; }
  std::string describe() const override { return "fixed"; }
};
}  // namespace

std::unique_ptr<Motion> make_fixed_motion() { return std::make_unique<FixedMotion>(); }
}  // namespace bagdem
