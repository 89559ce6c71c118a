// Hints to the memory system: no effect on any result.
#pragma once
#include <cstddef>

#include "bagdem/vec3.hpp"  // BAGDEM_INLINE

namespace bagdem {

// Asks for the cache lines of the first `bytes` bytes at p (default: all of *p), for writing, ahead
// of their use: for data that a loop reaches in an order the hardware prefetchers do not follow (a
// sparse subset of an array). A hint: no effect on any result.
template <class T>
BAGDEM_INLINE void prefetch_object(const T* p, std::size_t bytes = sizeof(T)) {
  const char* c = reinterpret_cast<const char*>(p);
  __builtin_prefetch(c, 1);
  __builtin_prefetch(c + bytes - 1, 1);  // they may straddle two lines
}

}  // namespace bagdem
