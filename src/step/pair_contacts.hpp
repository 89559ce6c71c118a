// The pair contacts component: the candidate pair list with its histories and the threads' share
// of it (PairState), and the stamps the threads meet on. Its stage: pairs (pair_schedule.cpp,
// pair_kernel.hpp); the list is renewed by the neighbours component (neighbours.hpp).
#pragma once
#include <atomic>
#include <cstdint>
#include <vector>

#include "pair_state.hpp"

namespace bagdem {

struct PairContacts : PairState {
  // Per range: the last parallel region of the pair stage in which the cross pairs into the range
  // were computed (a thread waits on the stamps of the ranges above its own).
  struct alignas(64) CrossStamp {
    std::atomic<std::uint64_t> region{0};
  };
  std::vector<CrossStamp> cross_done;
  std::uint64_t regions = 0;  // parallel regions of the pair stage so far
  // Its checkpoint fields (step/checkpoint.cpp): one list for writing and reading, so the two
  // cannot disagree. IO: pod(x) and vec(v).
  template <class IO>
  void checkpoint(IO& io) {
    io.vec(pairs.begin), io.vec(pairs.partner);
    hist.fields(io);
  }
};

}  // namespace bagdem
