// Loops the stepper's stages share: compile-time switches, the threads' spans and ranges, waiting.
#pragma once
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>
#include <thread>

#include "bagdem/float_rounding.hpp"
#include "bagdem/memory_hints.hpp"
#include "stepper.hpp"
#include "bagdem/vec3.hpp"

namespace bagdem {

// Calls fn.template operator()<b0, b1, ...>() with runtime flags turned into template arguments,
// so each configuration of the kernel is compiled without branches on the flags.
template <bool... Done, class Fn>
void with_flags(Fn&& fn) {
  fn.template operator()<Done...>();
}
template <bool... Done, class Fn, class... Rest>
void with_flags(Fn&& fn, bool first, Rest... rest) {
  if (first) with_flags<Done..., true>(fn, rest...);
  else with_flags<Done..., false>(fn, rest...);
}

// body(i, acc) for i in [begin, end): one function with everything it calls inlined (GCC otherwise
// leaves Eigen's small operators out of line inside large loop bodies). body arrives by value, so
// its captures are this function's own and stay in registers.
template <class Body, class Acc>
[[gnu::flatten]] void run_items(Body body, std::size_t begin, std::size_t end, Acc& acc) {
  for (std::size_t i = begin; i < end; ++i) body(i, acc);
}

// One turn of a spin wait: tells the core it is waiting (x86 `pause`), so it yields resources and
// leaves the loop without a memory-order flush when the value comes.
inline void pause_cpu() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

// Spins until ready(), or false as soon as give_up(). After 4096 turns each turn yields the core
// (more threads than cores: the thread waited for may need it).
template <class Ready, class GiveUp>
bool spin_until(const Ready& ready, const GiveUp& give_up) {
  for (int spins = 0; !ready(); ++spins) {
    if (give_up()) return false;
    if (spins < 4096) {
      pause_cpu();
    } else {
      std::this_thread::yield();
    }
  }
  return true;
}

// The loops of the step over particles or pairs: span(begin, end, acc) over [0, n), on one thread
// or in chunks of Chunk items. With T threads, thread t starts on the t-th contiguous share of the
// chunks, so the balls and pairs a thread handles in one stage are mostly those it handled in the
// last (they stay in its core's cache), then it helps the others with what they have left
// (near-wall balls and touching pairs cost more, and they are not spread evenly over the index
// range). Each thread folds its own acc; merge(acc, mine) combines them. Every item writes only
// its own slots, and the folds (max, min, and, or) do not depend on the order, so results are the
// same for any thread count.
template <std::size_t Chunk = 256, class Acc, class Span, class Merge>
void for_spans(std::size_t n, bool parallel, Acc& acc, const Span& span, Merge merge) {
  if (!parallel) {
    span(0, n, acc);
    return;
  }
  const std::size_t chunks = (n + Chunk - 1) / Chunk;
  const auto shares = static_cast<std::size_t>(omp_get_max_threads());
  struct alignas(64) Share {
    std::atomic<std::size_t> next;
    std::size_t end;
  };
  // No allocation in the step up to 16 threads.
  Share local[16];
  std::unique_ptr<Share[]> more(shares > 16 ? new Share[shares] : nullptr);
  Share* share = shares > 16 ? more.get() : local;
  for (std::size_t t = 0; t < shares; ++t) {
    share[t].next.store(t * chunks / shares, std::memory_order_relaxed);
    share[t].end = (t + 1) * chunks / shares;
  }
#pragma omp parallel
  {
    Acc mine = acc;
    const auto me = static_cast<std::size_t>(omp_get_thread_num());
    for (std::size_t k = 0; k < shares; ++k) {
      Share& sh = share[(me + k) % shares];
      for (std::size_t c; (c = sh.next.fetch_add(1, std::memory_order_relaxed)) < sh.end;)
        span(c * Chunk, std::min(n, (c + 1) * Chunk), mine);
    }
#pragma omp critical(bagdem_for_items)
    merge(acc, mine);
  }
}
// The same with body(i, acc) for each item.
template <std::size_t Chunk = 256, class Acc, class Body, class Merge>
void for_items(std::size_t n, bool parallel, Acc& acc, const Body& body, Merge merge) {
  for_spans<Chunk>(
      n, parallel, acc, [&body](std::size_t b, std::size_t e, Acc& a) { run_items(body, b, e, a); }, merge);
}

// The same over the particles [0, n) cut into spans by `balance` (one per thread, SpanBalance): each
// thread takes its span, times it, and the balance moves the cuts between steps so that the threads
// finish together. The cuts start where the pair stage's ranges lie (PairState), so a thread's
// particles stay in its core's cache from stage to stage. One span: on one thread. Not cut yet (the
// step after a checkpoint is loaded): for_spans.
template <class Acc, class Span, class Merge>
void for_range_spans(SpanBalance& balance, std::size_t n, Acc& acc, const Span& span, Merge merge) {
  const std::size_t spans = balance.spans();
  if (spans == 0) {
    for_spans(n, threaded(n), acc, span, merge);
    return;
  }
  if (spans == 1 || !threaded(n)) {
    span(0, n, acc);
    return;
  }
#pragma omp parallel
  {
    Acc mine = acc;
    const auto me = static_cast<std::size_t>(omp_get_thread_num()), team = static_cast<std::size_t>(omp_get_num_threads());
    for (std::size_t r = me; r < spans; r += team) {
      const double start = omp_get_wtime();
      span(balance.begin(r), balance.end(r), mine);
      balance.add(r, omp_get_wtime() - start);
    }
#pragma omp critical(bagdem_for_ranges)
    merge(acc, mine);
  }
}
// The same with body(i, acc) for each particle.
template <class Acc, class Body, class Merge>
void for_ranges(SpanBalance& balance, std::size_t n, Acc& acc, const Body& body, Merge merge) {
  for_range_spans(
      balance, n, acc, [&body](std::size_t b, std::size_t e, Acc& a) { run_items(body, b, e, a); }, merge);
}

}  // namespace bagdem
