// Rounding a double to single precision in a chosen direction.
#pragma once
#include <cmath>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "bagdem/vec3.hpp"  // BAGDEM_INLINE

namespace bagdem {

// The largest float not above v (for v within the floats' range): a bound kept in single
// precision that must not grow by its rounding (PairState::wake). NaN stays NaN.
BAGDEM_INLINE float round_down_to_float(double v) {
#if defined(__AVX512F__)
  return _mm_cvtss_f32(_mm_cvt_roundsd_ss(_mm_setzero_ps(), _mm_set_sd(v), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC));
#else
  const float f = static_cast<float>(v);
  return static_cast<double>(f) > v ? std::nextafter(f, -HUGE_VALF) : f;
#endif
}

}  // namespace bagdem
