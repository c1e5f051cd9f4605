#include "illum/core/interrupt.h"

#include <unistd.h>
#include <atomic>
#include <csignal>
#include <cstdlib>

namespace illum {
namespace {
std::atomic<bool> g_interrupted{false};
std::atomic<int> g_signal{0};

extern "C" void on_sigint(int signal) {
  if (g_interrupted.exchange(true)) _exit(130);
  g_signal.store(signal);
  if (signal == SIGTERM) return;  // the launcher's stop: main says it once, on the way out
  const char msg[] = "\nillum: interrupted, stopping (Ctrl-C again to quit at once)\n";
  [[maybe_unused]] auto n = write(STDERR_FILENO, msg, sizeof(msg) - 1);
}
}  // namespace

void install_interrupt_handler() {
  std::signal(SIGINT, on_sigint);
}
void install_termination_handler() {
  std::signal(SIGTERM, on_sigint);
}
int interrupt_signal() {
  return g_signal.load();
}
bool interrupt_requested() {
  return g_interrupted.load(std::memory_order_relaxed);
}
void request_interrupt() {
  g_interrupted.store(true);
}
void clear_interrupt() {
  g_interrupted.store(false);
  g_signal.store(0);
}

}  // namespace illum
