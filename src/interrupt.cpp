// SIGINT and SIGTERM during a run or a study (interrupt.hpp).
#include "bagdem/interrupt.hpp"

namespace bagdem {

namespace {

volatile std::sig_atomic_t g_signal = 0;
int g_depth = 0;  // guards alive: the outermost installs and restores
// A signal the process was started ignoring (a job that a non-interactive shell starts with `&` ignores
// SIGINT) stays ignored: the guard neither catches it nor gives it the default action.
bool g_ignored_int = false, g_ignored_term = false;

// Records the signal, and gives both signals back their default action (or their SIG_IGN): a second
// one, of either kind, ends the process at once.
extern "C" void record_signal(int sig) {
  if (g_signal == 0) g_signal = sig;
  struct sigaction d {};
  sigemptyset(&d.sa_mask);
  d.sa_handler = g_ignored_int ? SIG_IGN : SIG_DFL;
  sigaction(SIGINT, &d, nullptr);
  d.sa_handler = g_ignored_term ? SIG_IGN : SIG_DFL;
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
  sigaction(SIGINT, nullptr, &old_int_);
  sigaction(SIGTERM, nullptr, &old_term_);
  g_ignored_int = old_int_.sa_handler == SIG_IGN;
  g_ignored_term = old_term_.sa_handler == SIG_IGN;
  if (!g_ignored_int) sigaction(SIGINT, &a, nullptr);
  if (!g_ignored_term) sigaction(SIGTERM, &a, nullptr);
}

InterruptGuard::~InterruptGuard() {
  if (--g_depth > 0) return;
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
}

int pending_interrupt() { return g_signal; }

const char* signal_name(int sig) { return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal"; }

}  // namespace bagdem
