// Loops over items on the OpenMP threads, or as a plain loop when the items are few or there is one
// thread. An OpenMP parallel region costs about a microsecond even when its if() clause is false
// (libgomp still starts a team of one), as much as a whole step of a few tens of balls; so a region
// is entered only when it runs on several threads.
#pragma once
#include <omp.h>

#include <cstddef>

namespace bagdem {

// Parallel loops below this many items run on one thread (fork/join costs more than the work).
inline constexpr std::size_t kParallelMin = 512;

// Below this many balls the step's ball stages (drift, pairs, walls) run on one thread: below it the
// fork, join and imbalance of the parallel region cost more than the second thread saves (on the
// PD-box bed two threads are slower than one at 1000 balls and faster at 4000; the measurements are
// in docs/performance.md).
inline constexpr std::size_t kParallelBalls = 2048;

// Whether a loop over n items runs on several threads.
inline bool threaded(std::size_t n) { return n > kParallelMin && omp_get_max_threads() > 1; }

// body(i) for i in [0, n); every i writes only its own slots.
template <class Body>
void parallel_for(std::size_t n, const Body& body) {
  if (!threaded(n)) {
    for (std::size_t i = 0; i < n; ++i) body(i);
    return;
  }
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) body(i);
}

// The same, folding body(i)'s results with fold (max, min, and: the same for any order and team).
template <class T, class Body, class Fold>
T parallel_fold(std::size_t n, T init, const Body& body, const Fold& fold) {
  if (!threaded(n)) {
    for (std::size_t i = 0; i < n; ++i) init = fold(init, body(i));
    return init;
  }
  T all = init;
#pragma omp parallel
  {
    T mine = init;
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) mine = fold(mine, body(i));
#pragma omp critical(bagdem_parallel_fold)
    all = fold(all, mine);
  }
  return all;
}

}  // namespace bagdem
