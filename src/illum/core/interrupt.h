// Stopping on a signal: the first SIGINT (Ctrl-C), SIGTERM or SIGHUP sets a flag that
// long-running loops poll so they stop cleanly (no output is written); a second one ends
// the process at once, after removing the temporary files and staging folders registered
// below, so even a hurried stop leaves no hidden partial output behind.
#pragma once

#include <string>

namespace illum {

// SIGINT, SIGTERM and SIGHUP. SIGTERM is also how `mpirun` passes a Ctrl-C on to its ranks
// (then SIGKILL after a grace period), so a rank stops like an interrupted process instead
// of dying mid-write.
void install_interrupt_handler();
bool interrupt_requested();
// The signal that requested the interrupt (SIGINT, SIGTERM, SIGHUP), 0 for
// request_interrupt().
int interrupt_signal();
void request_interrupt();  // for tests and programmatic cancellation
void clear_interrupt();

// Thrown by a job that stopped because of an interrupt; the CLI exits 130 on it.
struct Interrupted {};

// A file or folder being written under a temporary name: while registered, a second signal
// removes it (a folder with the files directly inside it) before the process ends. Holds up
// to kMaxStagingPaths at once (more are not tracked); paths up to 4095 bytes.
inline constexpr int kMaxStagingPaths = 32;
class StagingPath {
 public:
  explicit StagingPath(const std::string& path);
  ~StagingPath();
  StagingPath(const StagingPath&) = delete;
  StagingPath& operator=(const StagingPath&) = delete;

 private:
  int slot_ = -1;
};

}  // namespace illum
