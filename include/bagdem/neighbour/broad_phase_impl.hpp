// Template part of broad_phase.hpp: parallel, deterministic assembly of candidate pairs.
#pragma once
#include <omp.h>

#include <algorithm>

namespace bagdem {

template <class Collect>
void build_candidates(std::size_t n, CandidatePairs& out, CandidateScratch& scratch, Collect&& collect) {
  out.begin.assign(n + 1, 0);
  // Per-thread output and scratch live in the broad phase between rebuilds, so a rebuild reuses
  // their memory.
  auto& chunk = scratch.chunk;
  chunk.resize(static_cast<std::size_t>(omp_get_max_threads()));
  scratch.buf.resize(chunk.size());
#pragma omp parallel if (n > 2000)
  {
    auto& mine = chunk[static_cast<std::size_t>(omp_get_thread_num())];
    mine.clear();
    auto& buf = scratch.buf[static_cast<std::size_t>(omp_get_thread_num())];
    // Static schedule: each thread owns one contiguous block of i, so blocks concatenate in order.
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      buf.clear();
      collect(i, buf);
      std::sort(buf.begin(), buf.end());
      out.begin[i + 1] = static_cast<std::uint32_t>(buf.size());
      mine.insert(mine.end(), buf.begin(), buf.end());
    }
  }
  for (std::size_t i = 0; i < n; ++i) out.begin[i + 1] += out.begin[i];
  out.partner.clear();
  out.partner.reserve(out.begin[n]);
  for (auto& c : chunk) out.partner.insert(out.partner.end(), c.begin(), c.end());
}

}  // namespace bagdem
