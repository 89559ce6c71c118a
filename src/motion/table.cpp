// Tabulated cavity motion: cubic Hermite interpolation of (t, x, y, z) rows with central-difference
// slopes (one-sided at the ends), so position is C1 and velocity continuous inside the table and
// exactly the derivative of the interpolated position. Outside the table the cavity rests at the
// first or last position, so the velocity jumps there unless the table starts and ends at rest.
#include <algorithm>
#include <sstream>

#include "bagdem/motion/motion.hpp"

namespace bagdem {
namespace {
class TableMotion final : public Motion {
 public:
  TableMotion(std::vector<double> t, std::vector<Vec3> x, std::string source)
      : t_(std::move(t)), x_(std::move(x)), source_(std::move(source)) {
    const size_t n = t_.size();
    m_.resize(n);
    for (size_t k = 0; k < n; ++k) {
      const size_t a = k == 0 ? 0 : k - 1, b = k + 1 == n ? n - 1 : k + 1;
      m_[k] = (x_[b] - x_[a]) / (t_[b] - t_[a]);
    }
    for (size_t k = 0; k + 1 < n; ++k) {  // sample each interval to bound the speed
      for (int s = 0; s <= 8; ++s) {
        vmax_ = std::max(vmax_, at(t_[k] + (t_[k + 1] - t_[k]) * s / 8.0).velocity.norm());
      }
    }
  }
  CavityState at(double t) const override {
    if (t <= t_.front()) return {x_.front(), Vec3::Zero()};
    if (t >= t_.back()) return {x_.back(), Vec3::Zero()};
    const size_t k = static_cast<size_t>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin()) - 1;
    const double h = t_[k + 1] - t_[k], s = (t - t_[k]) / h;
    const double s2 = s * s, s3 = s2 * s;
    // Hermite basis and derivatives (d/dt = d/ds / h).
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
                 h11 = s3 - s2;
    const double d00 = 6 * s2 - 6 * s, d10 = 3 * s2 - 4 * s + 1, d01 = -6 * s2 + 6 * s,
                 d11 = 3 * s2 - 2 * s;
    CavityState c;
    c.position = h00 * x_[k] + h10 * h * m_[k] + h01 * x_[k + 1] + h11 * h * m_[k + 1];
    c.velocity = (d00 * x_[k] + d01 * x_[k + 1]) / h + d10 * m_[k] + d11 * m_[k + 1];
    return c;
  }
  double max_speed() const override { return vmax_; }
  std::string describe() const override {
    std::ostringstream s;
    s << "table from " << source_ << ": " << t_.size() << " rows over " << t_.back() - t_.front()
      << " s (cubic Hermite), max speed " << vmax_ << " m/s";
    return s.str();
  }

 private:
  std::vector<double> t_;
  std::vector<Vec3> x_, m_;
  std::string source_;
  double vmax_ = 0;
};
}  // namespace

std::unique_ptr<Motion> make_table_motion(std::vector<double> t, std::vector<Vec3> x,
                                          std::string source) {
  return std::make_unique<TableMotion>(std::move(t), std::move(x), std::move(source));
}
}  // namespace bagdem
