// Internal to src/run: SIGINT and SIGTERM while a run or a sweep steps. The handler only records
// the signal (async-signal-safe); the loop polls it between steps, writes a checkpoint, marks
// results.h5.part "interrupted", closes its files and returns, and `bagdem run` exits with
// 128 + the signal (130 for SIGINT, 143 for SIGTERM). A second signal ends the process at once.
#pragma once
#include <csignal>

namespace bagdem {

// Installs the handlers for its lifetime (the previous ones are restored) and clears any signal
// recorded before.
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
