#include "illum/core/interrupt.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <cstring>

namespace illum {
namespace {
std::atomic<bool> g_interrupted{false};
std::atomic<int> g_signal{0};

// Staging paths, readable from the signal handler: a slot is free (0), being filled (1) or
// holds a path (2). Only async-signal-safe calls touch them there.
constexpr size_t kMaxPathBytes = 4096;
char g_paths[kMaxStagingPaths][kMaxPathBytes];
std::atomic<int> g_state[kMaxStagingPaths];

// Removes the entries directly inside folder `fd` (getdents64 and unlinkat are plain system
// calls, safe in a handler; opendir is not).
void remove_folder_contents(int fd) {
  alignas(8) char buffer[4096];
  for (;;) {
    const long n = syscall(SYS_getdents64, fd, buffer, sizeof(buffer));
    if (n <= 0) return;
    for (long at = 0; at < n;) {
      struct Entry {
        uint64_t ino;
        int64_t off;
        unsigned short reclen;
        unsigned char type;
        char name[1];
      };
      const auto* e = reinterpret_cast<const Entry*>(buffer + at);
      if (std::strcmp(e->name, ".") != 0 && std::strcmp(e->name, "..") != 0)
        unlinkat(fd, e->name, 0);
      at += e->reclen;
    }
  }
}

void remove_staging_paths() {
  for (int i = 0; i < kMaxStagingPaths; ++i) {
    if (g_state[i].load() != 2) continue;
    const char* path = g_paths[i];
    if (unlink(path) == 0) continue;
    const int fd = open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) continue;
    remove_folder_contents(fd);
    close(fd);
    rmdir(path);
  }
}

extern "C" void on_signal(int signal) {
  if (g_interrupted.exchange(true)) {
    remove_staging_paths();
    _exit(130);
  }
  g_signal.store(signal);
  if (signal != SIGINT) return;  // SIGTERM, SIGHUP: main says it once, on the way out
  const char msg[] = "\nillum: interrupted, stopping (Ctrl-C again to quit at once)\n";
  [[maybe_unused]] auto n = write(STDERR_FILENO, msg, sizeof(msg) - 1);
}
}  // namespace

void install_interrupt_handler() {
  for (int s : {SIGINT, SIGTERM, SIGHUP}) std::signal(s, on_signal);
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

StagingPath::StagingPath(const std::string& path) {
  if (path.size() >= kMaxPathBytes) return;
  for (int i = 0; i < kMaxStagingPaths; ++i) {
    int free = 0;
    if (!g_state[i].compare_exchange_strong(free, 1)) continue;
    std::memcpy(g_paths[i], path.c_str(), path.size() + 1);
    g_state[i].store(2);
    slot_ = i;
    return;
  }
}

StagingPath::~StagingPath() {
  if (slot_ >= 0) g_state[slot_].store(0);
}

}  // namespace illum
