// The film's bending hinges (bag/membrane.hpp, Bending): a hinge's angle and its gradient, written
// once over a number type T (double, or Lanes of kLanes hinges: contact/lanes.hpp), and the faded
// hinge of a wing near collapse. Used by membrane.cpp only.
#pragma once
#include <array>
#include <cmath>
#include <numbers>

#include "bagdem/contact/lanes.hpp"
#include "bagdem/vec3.hpp"

namespace bagdem::hinge {

// A hinge's angle and its gradient with respect to (x0, x1, xa, xb).
//
// theta: the signed angle between the normals nA = e x (xa - x0) of triangle (x0, x1, xa) and
// nB = (xb - x0) x e of (x1, x0, xb), e = x1 - x0: positive where the surface is convex seen from the
// side its normals point to, 0 when flat. From (sin, cos) by atan2, accurate near 0 and pi alike.
//
// Gradient (Bridson, Marino & Fedkiw, SCA 2003): a wing vertex moving along its triangle's normal by
// d turns that triangle by d / h (h its height over the edge), flattening a convex hinge:
// g_a = -|e| nA / |nA|^2. The edge vertices take the rest, split by where the wings project on the
// edge (s = (x_w - x0) . e / |e|^2), so that the gradient is blind to translations and rotations.
// A collapsed triangle (nA = 0) gives non-finite forces, which the stepper's guards report.
template <class T>
struct HingeEval {
  T theta;
  std::array<V3<T>, 4> grad;
  T nA2, nB2;  // |nA|^2, |nB|^2: (2 A)^2 of the wings
};

// From (sin, cos) x |nA| |nB|: atan2_unit where |theta| <= pi/4 (every hinge of a smooth film),
// else libm's atan2, lane by lane.
template <class T>
BAGDEM_INLINE T hinge_angle(const V3<T>& e, const V3<T>& nA, const V3<T>& nB, T le) {
  const T s = dot(cross(nA, nB), e) / le, c = dot(nA, nB);
  T theta = atan2_unit(s, c);
  if constexpr (std::is_same_v<T, double>) {
    if (!(c > 0 && std::abs(s) <= c)) theta = std::atan2(s, c);
  } else {
    for (int l = 0; l < kLanes; ++l)
      if (!(c[l] > 0 && std::abs(s[l]) <= c[l])) theta[l] = std::atan2(s[l], c[l]);
  }
  return theta;
}

BAGDEM_INLINE double hinge_angle(const Vec3& x0, const Vec3& x1, const Vec3& xa, const Vec3& xb) {
  const Vec3 e = x1 - x0;
  return hinge_angle<double>(e, cross(e, Vec3(xa - x0)), cross(Vec3(xb - x0), e), std::sqrt(dot(e, e)));
}

template <class T>
BAGDEM_INLINE HingeEval<T> hinge_eval(const V3<T>& x0, const V3<T>& x1, const V3<T>& xa, const V3<T>& xb) {
  const V3<T> e = x1 - x0, da = xa - x0, db = xb - x0;
  const V3<T> nA = cross(e, da), nB = cross(db, e);
  const T le2 = dot(e, e), le = sqrt_of(le2);
  const V3<T> ga = (-le / dot(nA, nA)) * nA, gb = (-le / dot(nB, nB)) * nB;
  const T inv_le2 = 1.0 / le2, sa = dot(da, e) * inv_le2, sb = dot(db, e) * inv_le2;
  return {hinge_angle<T>(e, nA, nB, le),
          {-((1.0 - sa) * ga) - (1.0 - sb) * gb, -(sa * ga) - sb * gb, ga, gb},
          dot(nA, nA), dot(nB, nB)};
}

// theta - theta0 in (-pi, pi]: the energy stays continuous if a hinge folds through +-pi.
template <class T>
BAGDEM_INLINE T angle_change(T theta, T theta0) {
  const T d = theta - theta0;
  return select(d > std::numbers::pi, d - 2.0 * std::numbers::pi, select(d <= -std::numbers::pi, d + 2.0 * std::numbers::pi, d));
}

// The fade s(u) = u^2 (3 - 2u) for u < 1, else 1, and its derivative (membrane.hpp, Bending).
struct Fade {
  double s, ds;
};
BAGDEM_INLINE Fade fade_of(double u) { return u < 1.0 ? Fade{u * u * (3.0 - 2.0 * u), 6.0 * u * (1.0 - u)} : Fade{1.0, 0.0}; }

// A hinge with a wing below its fade's start: energy and the forces on (x0, x1, xa, xb),
// f = -grad(k s_A s_B d^2), d = theta - theta0, with grad |nA|^2 = 2 (da x nA) on x1, 2 (nA x e) on
// xa (nA = e x da), grad |nB|^2 = 2 (nB x db) on x1, 2 (e x nB) on xb (nB = db x e), x0 taking
// minus their sum.
struct FadedHinge {
  double energy;
  std::array<Vec3, 4> force;
};
inline FadedHinge faded_hinge(const Vec3& x0, const Vec3& x1, const Vec3& xa, const Vec3& xb, double k, double theta0, double fade_a,
                       double fade_b) {
  const HingeEval<double> he = hinge_eval<double>(x0, x1, xa, xb);
  const Vec3 e = x1 - x0, da = xa - x0, db = xb - x0;
  const Vec3 nA = e.cross(da), nB = db.cross(e);
  const Fade fa = fade_of(he.nA2 / fade_a), fb = fade_of(he.nB2 / fade_b);
  const double d = angle_change<double>(he.theta, theta0);
  // grad u_A and grad u_B on (x0, x1, xa, xb).
  const Vec3 uA1 = (2.0 / fade_a) * da.cross(nA), uAa = (2.0 / fade_a) * nA.cross(e);
  const Vec3 uB1 = (2.0 / fade_b) * nB.cross(db), uBb = (2.0 / fade_b) * e.cross(nB);
  const std::array<Vec3, 4> gA = {-(uA1 + uAa), uA1, uAa, Vec3::Zero()}, gB = {-(uB1 + uBb), uB1, Vec3::Zero(), uBb};
  const double s = fa.s * fb.s;
  FadedHinge out{k * s * d * d, {}};
  for (int i = 0; i < 4; ++i) {
    // theta's gradient grows as 1/A where s falls as A^4; at A = 0 exactly it is not finite (s = 0).
    const Vec3 bend = s > 0 ? Vec3(2.0 * s * d * he.grad[i]) : Vec3::Zero();
    out.force[i] = -k * (bend + d * d * (fb.s * fa.ds * gA[i] + fa.s * fb.ds * gB[i]));
  }
  return out;
}

}  // namespace bagdem::hinge
