// Smooth start of a prescribed motion. The displacement from the start position x0 = x(0) is
// ramped in: x_r(t) = x0 + s(t) (x(t) - x0), v_r(t) = s'(t) (x(t) - x0) + s(t) v(t), with the ramp
// s(t) = (1 - cos(pi t / T_r))/2 on [0, T_r] and s = 1 after (T_r: ramp time, unit: s).
// Why: the cavity rests at x0 during settling and its motion starts at motion time 0; a harmonic
// motion X sin(w t) would start with a velocity jump X w (an impulsive start that kicks the bed and
// excites a transient). s is C1: s(0) = s'(0) = 0 and s(T_r) = 1, s'(T_r) = 0, so the ramped motion
// starts at rest where the cavity settled and joins the inner motion with continuous position and
// velocity (the acceleration still jumps at 0 and T_r, by a finite amount). After T_r the inner
// motion is returned unchanged.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "bagdem/motion/motion.hpp"

namespace bagdem {
namespace {
class RampedMotion final : public Motion {
 public:
  RampedMotion(std::unique_ptr<Motion> inner, double ramp_time)
      : inner_(std::move(inner)), T_(ramp_time), k_(std::numbers::pi / ramp_time), x0_(inner_->at(0).position) {
    // Speed bound: |v_r| <= max|s'| max|x| + max|s| max|v| over the ramp, with max|s'| = pi/(2 T_r)
    // (unit: 1/s) and max|s| = 1. The largest displacement over [0, T_r] (unit: m) is sampled at
    // n + 1 points h = T_r/n apart; between two samples |x| grows by at most v_max h/2 (inner max
    // speed), which is added so that the sampled value is a bound, not an estimate.
    const int n = 512;
    const double h = T_ / n, v_inner = inner_->max_speed();
    double x_max = 0;
    for (int i = 0; i <= n; ++i) x_max = std::max(x_max, (inner_->at(h * i).position - x0_).norm());
    x_max += v_inner * h / 2;
    vmax_ = v_inner + k_ / 2 * x_max;
  }
  CavityState at(double t) const override {
    if (t >= T_) return inner_->at(t);
    if (t <= 0) return {x0_, Vec3::Zero()};
    const double a = k_ * t;                  // phase of the ramp, pi t/T_r (rad)
    const double s = (1 - std::cos(a)) / 2;   // ramp factor (unit: 1)
    const double ds = k_ / 2 * std::sin(a);   // s' (unit: 1/s)
    const CavityState c = inner_->at(t);
    return {x0_ + s * (c.position - x0_), ds * (c.position - x0_) + s * c.velocity};
  }
  double max_speed() const override { return vmax_; }
  double ramp_time() const override { return T_; }
  double frequency() const override { return inner_->frequency(); }
  std::string describe() const override {
    std::ostringstream s;
    s << inner_->describe() << ", ramped in over " << T_ << " s";
    return s.str();
  }

 private:
  std::unique_ptr<Motion> inner_;
  double T_;         // ramp time T_r (unit: s)
  double k_;         // pi / T_r (unit: rad/s)
  Vec3 x0_;          // start position x(0) of the inner motion (unit: m)
  double vmax_ = 0;  // bound on |v_r| (unit: m/s)
};
}  // namespace

std::unique_ptr<Motion> make_ramped_motion(std::unique_ptr<Motion> inner, double ramp_time) {
  if (!inner) throw std::invalid_argument("make_ramped_motion: no inner motion");
  if (!(ramp_time > 0) || !std::isfinite(ramp_time))
    throw std::invalid_argument("make_ramped_motion: ramp_time must be finite and > 0 (s)");
  return std::make_unique<RampedMotion>(std::move(inner), ramp_time);
}
}  // namespace bagdem
