// SIGINT and SIGTERM during a run or a study (interrupt.hpp).
#include "bagdem/interrupt.hpp"

namespace bagdem {

namespace {

volatile std::sig_atomic_t g_signal = 0;

extern "C" void record_signal(int sig) { g_signal = sig; }

}  // namespace

InterruptGuard::InterruptGuard() {
  g_signal = 0;
  struct sigaction a {};
  a.sa_handler = record_signal;
  sigemptyset(&a.sa_mask);
  a.sa_flags = SA_RESTART | SA_RESETHAND;  // writes go on; a second signal ends the process at once
  sigaction(SIGINT, &a, &old_int_);
  sigaction(SIGTERM, &a, &old_term_);
}

InterruptGuard::~InterruptGuard() {
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
}

int pending_interrupt() { return g_signal; }

const char* signal_name(int sig) { return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal"; }

}  // namespace bagdem
