// Lanes: kLanes contacts computed side by side, one per lane of a SIMD register (GCC vector
// extensions; AVX2 lanes of 4 doubles). The contact law (geometry.hpp, hertz.hpp, mindlin.hpp,
// rolling.hpp) is written once over a number type T: double for one contact, Lanes for kLanes of
// them. Every operation rounds as written (-ffp-contract=off), and sqrt and division round
// correctly in both, so a lane gives the same bits as the scalar law on the same contact.
//
// Loading the particles' data into lanes is a transpose: each particle's Vec3 is one row, four
// rows give the x, y and z lanes (gather3); results go back the same way (to_rows). Element-wise
// inserts would round-trip through memory, and a wide load of narrow stores stalls the core.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <type_traits>

#if defined(__AVX__)
#include <immintrin.h>
#endif

#include "bagdem/vec3.hpp"

namespace bagdem {

inline constexpr int kLanes = 4;
typedef double Lanes __attribute__((vector_size(32)));
typedef std::int64_t LanesMask __attribute__((vector_size(32)));

// A 3-vector of lanes: component c of lane l is c[l].
struct Lanes3 {
  Lanes x, y, z;
};

template <class T>
using V3 = std::conditional_t<std::is_same_v<T, double>, Vec3, Lanes3>;

// ---- the operations the law uses, for double and Lanes alike -------------------------------------
template <class T>
BAGDEM_INLINE T splat(double v) {
  if constexpr (std::is_same_v<T, double>) return v;
  else return Lanes{v, v, v, v};
}
template <class T>
BAGDEM_INLINE V3<T> zero3() {
  if constexpr (std::is_same_v<T, double>) return Vec3::Zero();
  else return Lanes3{splat<Lanes>(0), splat<Lanes>(0), splat<Lanes>(0)};
}
BAGDEM_INLINE double sqrt_of(double v) { return std::sqrt(v); }
BAGDEM_INLINE Lanes sqrt_of(Lanes v) {
#if defined(__AVX__)
  return (Lanes)_mm256_sqrt_pd((__m256d)v);
#else
  return Lanes{std::sqrt(v[0]), std::sqrt(v[1]), std::sqrt(v[2]), std::sqrt(v[3])};
#endif
}
// std::min and std::max's rule ((b < a) ? b : a), NaN included, lane by lane.
BAGDEM_INLINE double min_of(double a, double b) { return std::min(a, b); }
BAGDEM_INLINE double max_of(double a, double b) { return std::max(a, b); }
BAGDEM_INLINE Lanes min_of(Lanes a, Lanes b) { return b < a ? b : a; }
BAGDEM_INLINE Lanes max_of(Lanes a, Lanes b) { return a < b ? b : a; }
BAGDEM_INLINE double select(bool m, double a, double b) { return m ? a : b; }
BAGDEM_INLINE Lanes select(LanesMask m, Lanes a, Lanes b) { return m ? a : b; }
// The mask type of T (bool for double), a mask of one value, and a && !b lane by lane.
template <class T>
using LanesMaskT = std::conditional_t<std::is_same_v<T, double>, bool, LanesMask>;
template <class T>
BAGDEM_INLINE LanesMaskT<T> mask_of(bool v) {
  if constexpr (std::is_same_v<T, double>) return v;
  else return LanesMask{-std::int64_t{v}, -std::int64_t{v}, -std::int64_t{v}, -std::int64_t{v}};
}
BAGDEM_INLINE bool and_not(bool a, bool b) { return a && !b; }
BAGDEM_INLINE LanesMask and_not(LanesMask a, LanesMask b) { return a & ~b; }
// As opaque(double) (vec3.hpp). Four doubles fit one register only with AVX: without it (a
// portable build, BAGDEM_NATIVE=OFF) there is no such register and the hint is left out.
BAGDEM_INLINE Lanes opaque(Lanes v) {
#if defined(__GNUC__) && defined(__x86_64__) && defined(__AVX__)
  asm("" : "+x"(v));
#endif
  return v;
}

BAGDEM_INLINE double dot(const Vec3& a, const Vec3& b) { return a.x() * b.x() + a.y() * b.y() + a.z() * b.z(); }
BAGDEM_INLINE Lanes dot(const Lanes3& a, const Lanes3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
BAGDEM_INLINE Lanes3 cross(const Lanes3& a, const Lanes3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
BAGDEM_INLINE Lanes3 operator+(const Lanes3& a, const Lanes3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
BAGDEM_INLINE Lanes3 operator-(const Lanes3& a, const Lanes3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
BAGDEM_INLINE Lanes3 operator-(const Lanes3& a) { return {-a.x, -a.y, -a.z}; }
BAGDEM_INLINE Lanes3 operator*(Lanes s, const Lanes3& a) { return {s * a.x, s * a.y, s * a.z}; }
BAGDEM_INLINE Lanes3 operator*(double s, const Lanes3& a) { return {s * a.x, s * a.y, s * a.z}; }
BAGDEM_INLINE Lanes3 operator/(const Lanes3& a, Lanes s) { return {a.x / s, a.y / s, a.z / s}; }
BAGDEM_INLINE Lanes3& operator+=(Lanes3& a, const Lanes3& b) { return a = a + b; }
BAGDEM_INLINE Lanes3& operator-=(Lanes3& a, const Lanes3& b) { return a = a - b; }
BAGDEM_INLINE Lanes3& operator*=(Lanes3& a, Lanes s) {
  a.x *= s, a.y *= s, a.z *= s;
  return a;
}

// ---- in and out of lanes ------------------------------------------------------------------------
#if defined(__AVX__)
BAGDEM_INLINE void transpose4(__m256d& a, __m256d& b, __m256d& c, __m256d& d) {
  const __m256d t0 = _mm256_unpacklo_pd(a, b), t1 = _mm256_unpackhi_pd(a, b);
  const __m256d t2 = _mm256_unpacklo_pd(c, d), t3 = _mm256_unpackhi_pd(c, d);
  a = _mm256_permute2f128_pd(t0, t2, 0x20);
  b = _mm256_permute2f128_pd(t1, t3, 0x20);
  c = _mm256_permute2f128_pd(t0, t2, 0x31);
  d = _mm256_permute2f128_pd(t1, t3, 0x31);
}
#endif

// The Vec3s at p[l] into lanes (reads exactly their 3 doubles each).
BAGDEM_INLINE Lanes3 gather3(const double* const* p) {
#if defined(__AVX__)
  const __m256i xyz = _mm256_set_epi64x(0, -1, -1, -1);
  __m256d a = _mm256_maskload_pd(p[0], xyz), b = _mm256_maskload_pd(p[1], xyz);
  __m256d c = _mm256_maskload_pd(p[2], xyz), d = _mm256_maskload_pd(p[3], xyz);
  transpose4(a, b, c, d);
  return {(Lanes)a, (Lanes)b, (Lanes)c};
#else
  return {Lanes{p[0][0], p[1][0], p[2][0], p[3][0]}, Lanes{p[0][1], p[1][1], p[2][1], p[3][1]},
          Lanes{p[0][2], p[1][2], p[2][2], p[3][2]}};
#endif
}
// The same for base[at[l]].
BAGDEM_INLINE Lanes3 gather3(const Vec3* base, const std::uint32_t* at) {
  const double* p[kLanes] = {base[at[0]].data(), base[at[1]].data(), base[at[2]].data(), base[at[3]].data()};
  return gather3(p);
}

// Four consecutive doubles at p[l] (a Vec3 and the double after it) into lanes: (x, y, z, w).
BAGDEM_INLINE void gather4(const double* const* p, Lanes3& v, Lanes& w) {
#if defined(__AVX__)
  __m256d a = _mm256_loadu_pd(p[0]), b = _mm256_loadu_pd(p[1]), c = _mm256_loadu_pd(p[2]), d = _mm256_loadu_pd(p[3]);
  transpose4(a, b, c, d);
  v = {(Lanes)a, (Lanes)b, (Lanes)c};
  w = (Lanes)d;
#else
  v = {Lanes{p[0][0], p[1][0], p[2][0], p[3][0]}, Lanes{p[0][1], p[1][1], p[2][1], p[3][1]},
       Lanes{p[0][2], p[1][2], p[2][2], p[3][2]}};
  w = Lanes{p[0][3], p[1][3], p[2][3], p[3][3]};
#endif
}

// Lanes back to rows: row l = (v.x[l], v.y[l], v.z[l], w[l]) stored at to[l] (4 doubles).
BAGDEM_INLINE void to_rows(const Lanes3& v, Lanes w, double* const* to) {
#if defined(__AVX__)
  __m256d a = (__m256d)v.x, b = (__m256d)v.y, c = (__m256d)v.z, d = (__m256d)w;
  transpose4(a, b, c, d);
  _mm256_storeu_pd(to[0], a), _mm256_storeu_pd(to[1], b), _mm256_storeu_pd(to[2], c), _mm256_storeu_pd(to[3], d);
#else
  for (int l = 0; l < kLanes; ++l) to[l][0] = v.x[l], to[l][1] = v.y[l], to[l][2] = v.z[l], to[l][3] = w[l];
#endif
}

BAGDEM_INLINE Vec3 lane(const Lanes3& v, int l) { return {v.x[l], v.y[l], v.z[l]}; }

// atan2(s, c) for c > 0 and |s| <= c (an angle of at most pi/4 either way), inline and over lanes,
// for the film's hinges (bag/membrane.cpp). For |s| > tan(pi/8) c, atan(s/c) = pi/4 +
// atan((|s| - c)/(|s| + c)); on |t| <= tan(pi/8), t p(t^2) with p the 11-term Chebyshev fit of
// atan(sqrt(u))/sqrt(u) on [0, tan^2(pi/8)] (mpmath.chebyfit, fit error 3.5e-17), by Estrin's
// scheme. One division. Within 6e-16 (relative) of libm's atan2 (tests/test_contact_lanes.cpp).
template <class T>
BAGDEM_INLINE T atan2_unit(T s, T c) {
  constexpr double kTanPi8 = 0.41421356237309503;
  constexpr double q[] = {1.0,  -0.3333333333332844, 0.1999999999885511,  -0.14285714180976467, 0.11111106180455946,
                          -0.09090773074808414, 0.07689953496306857, -0.06640233930429408, 0.056883492268090106,
                          -0.04348052215716462, 0.021135373157693246};  // q[i]: the coefficient of u^i
  const LanesMaskT<T> negative = s < 0.0;
  const T a = select(negative, -s, s);
  const LanesMaskT<T> reduce = a > kTanPi8 * c;
  const T t = select(reduce, a - c, a) / select(reduce, a + c, c);
  const T u = t * t, u2 = u * u, u4 = u2 * u2, u8 = u4 * u4;
  const T p01 = q[0] + q[1] * u, p23 = q[2] + q[3] * u, p45 = q[4] + q[5] * u, p67 = q[6] + q[7] * u, p89 = q[8] + q[9] * u;
  const T p03 = p01 + p23 * u2, p47 = p45 + p67 * u2, p8a = p89 + q[10] * u2;
  const T y = select(reduce, splat<T>(0.25 * std::numbers::pi), splat<T>(0.0)) + t * ((p03 + p47 * u4) + p8a * u8);
  return select(negative, -y, y);
}

}  // namespace bagdem
