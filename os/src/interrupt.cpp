#include <granstack/os/interrupt.hpp>

#include <atomic>
#include <csignal>
#include <unistd.h>

namespace granstack::os {

namespace {
std::atomic<int> g_signal{0};

extern "C" void on_stop_signal(int s) {
  int expected = 0;
  if (!g_signal.compare_exchange_strong(expected, s)) {
    // The second request: stop now, with the conventional status.
    ::signal(s, SIG_DFL);
    ::raise(s);
  }
}
}  // namespace

void install_interrupt_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  for (const int s : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(s, &sa, nullptr);
}

int interrupt_signal() { return g_signal.load(); }

}  // namespace granstack::os
