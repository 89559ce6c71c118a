// SIGINT and SIGTERM during a run or a study (interrupt.hpp).
#include "bagdem/interrupt.hpp"

namespace bagdem {

namespace {

volatile std::sig_atomic_t g_signal = 0;
int g_depth = 0;  // guards alive: the outermost installs and restores

// Records the signal, and gives both signals back their default action: a second one, of either
// kind, ends the process at once.
extern "C" void record_signal(int sig) {
  if (g_signal == 0) g_signal = sig;
  struct sigaction d {};
  d.sa_handler = SIG_DFL;
  sigemptyset(&d.sa_mask);
  sigaction(SIGINT, &d, nullptr);
  sigaction(SIGTERM, &d, nullptr);
}

}  // namespace

InterruptGuard::InterruptGuard() {
  if (g_depth++ > 0) return;  // an outer guard holds them, and any signal it recorded stays
  g_signal = 0;
  struct sigaction a {};
  a.sa_handler = record_signal;
  sigemptyset(&a.sa_mask);  // the other signal waits while the handler runs (it gives both back their default)
  sigaddset(&a.sa_mask, SIGINT);
  sigaddset(&a.sa_mask, SIGTERM);
  a.sa_flags = SA_RESTART;  // writes go on
  sigaction(SIGINT, &a, &old_int_);
  sigaction(SIGTERM, &a, &old_term_);
}

InterruptGuard::~InterruptGuard() {
  if (--g_depth > 0) return;
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
}

int pending_interrupt() { return g_signal; }

const char* signal_name(int sig) { return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal"; }

}  // namespace bagdem
