// Internal to src/structure: <Eigen/Dense> without GCC 12's false -W(maybe-)uninitialized
// warnings from its AVX-512 intrinsics (_mm512_extractf64x4_pd on an _mm512_undefined_pd operand,
// inlined into Eigen's kernels under -march=native; a known GCC 12 false positive). The warnings
// are issued after inlining, at locations in the intrinsics header, so they are switched off for
// the rest of the including file (which includes this first).
#pragma once
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ == 12
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include <Eigen/Dense>
