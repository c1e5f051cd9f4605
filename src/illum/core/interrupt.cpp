#include "illum/core/interrupt.h"

#include <unistd.h>
#include <atomic>
#include <csignal>
#include <cstdlib>

namespace illum {
namespace {
std::atomic<bool> g_interrupted{false};

extern "C" void on_sigint(int) {
  if (g_interrupted.exchange(true)) _exit(130);
  const char msg[] = "\nillum: interrupted, stopping (Ctrl-C again to quit at once)\n";
  [[maybe_unused]] auto n = write(STDERR_FILENO, msg, sizeof(msg) - 1);
}
}  // namespace

void install_interrupt_handler() {
  std::signal(SIGINT, on_sigint);
}
bool interrupt_requested() {
  return g_interrupted.load(std::memory_order_relaxed);
}
void request_interrupt() {
  g_interrupted.store(true);
}
void clear_interrupt() {
  g_interrupted.store(false);
}

}  // namespace illum
