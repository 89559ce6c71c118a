// Harmonic translation x(t) = X sin(w t + phase) along a unit direction, w = 2 pi f.
#include <cmath>
#include <numbers>
#include <sstream>

#include "bagdem/motion/motion.hpp"

namespace bagdem {
namespace {
class HarmonicMotion final : public Motion {
 public:
  HarmonicMotion(double X, double f, const Vec3& dir, double phase)
      : X_(X), w_(2 * std::numbers::pi * f), dir_(dir), phase_(phase) {}
  CavityState at(double t) const override {
    const double a = w_ * t + phase_;
    return {X_ * std::sin(a) * dir_, X_ * w_ * std::cos(a) * dir_};
  }
  double max_speed() const override { return X_ * w_; }
  double frequency() const override { return w_ / (2 * std::numbers::pi); }
  std::string describe() const override {
    std::ostringstream s;
    s << "harmonic X sin(wt + phase): X = " << X_ << " m, f = " << w_ / (2 * std::numbers::pi)
      << " Hz, direction (" << dir_.x() << ", " << dir_.y() << ", " << dir_.z()
      << "), phase = " << phase_ << " rad, Gamma = X w^2/g = " << X_ * w_ * w_ / 9.81;
    return s.str();
  }

 private:
  double X_, w_;
  Vec3 dir_;
  double phase_;
};
}  // namespace

std::unique_ptr<Motion> make_harmonic_motion(double X, double f, const Vec3& dir, double phase) {
  return std::make_unique<HarmonicMotion>(X, f, dir.normalized(), phase);
}
}  // namespace bagdem
