// SIGINT and SIGTERM while a run steps or a study runs its points. The handler only records the
// signal (async-signal-safe) and the loop polls it: a run between steps (it writes a checkpoint,
// marks results.h5.part "interrupted", closes its files and returns), a study between its points'
// polls (study/pool.cpp: it keeps the points done, stops the running ones and throws Interrupted);
// during a study's planning and its merged tables a signal waits until they are written whole
// (study/study.hpp, holding_interrupts). Either exits with 128 + the signal (130 for SIGINT, 143
// for SIGTERM). A second signal ends the process at once.
#pragma once
#include <csignal>

namespace bagdem {

// Installs the handlers for its lifetime (the previous ones are restored) and clears any signal
// recorded before; a signal the process ignores (SIG_IGN, as a script's background job ignores
// SIGINT) stays ignored; inside another guard (a study's, around the pool's) it does nothing, so that
// a signal the outer one recorded is not lost.
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

 private:
  struct sigaction old_int_{}, old_term_{};
};

// The signal received since the guard was installed (SIGINT or SIGTERM), or 0.
int pending_interrupt();

// "SIGINT", "SIGTERM" or "signal N".
const char* signal_name(int sig);

}  // namespace bagdem
