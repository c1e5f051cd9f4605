// Every rank of a job tells every other that it is alive, on a communicator of its own and
// from a thread of its own, so a rank that stops (SIGSTOP, a hung node, a lost link) is
// noticed whatever the others are doing: computing, waiting for work, or blocked in a
// collective. A peer silent for longer than the timeout ends the job (README.md "Failure").
#pragma once

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <mpi.h>

namespace illum::distributed {

class Heartbeat {
 public:
  // Starts the thread. `world` is duplicated (collective: every rank constructs one).
  Heartbeat(MPI_Comm world, int rank, int ranks, double timeout_s);
  ~Heartbeat();  // stops the thread; never blocks on a peer
  Heartbeat(const Heartbeat&) = delete;
  Heartbeat& operator=(const Heartbeat&) = delete;

  // Set once peers were found silent: the one line that says so (empty before).
  bool lost() const { return lost_.load(); }
  std::string lost_message() const;
  // Whether this rank is the one that prints the line: the lowest rank not found silent.
  bool reports() const { return reports_.load(); }
  // Whether this process itself was stopped for longer than the timeout (SIGSTOP, then
  // SIGCONT from mpirun as it ends the job): the others have reported it already.
  bool stalled_self() const;
  // Prints the line (once per process, and only on the rank that reports) and ends the
  // process with kLostExitCode, without MPI_Finalize, which would wait for the silent peers.
  [[noreturn]] void end_job();

  static constexpr int kLostExitCode = 1;

 private:
  void loop();

  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0, ranks_ = 1;
  std::chrono::duration<double> timeout_, period_;
  std::vector<std::chrono::steady_clock::time_point> heard_;
  std::atomic<bool> stop_{false}, lost_{false}, reports_{false}, printed_{false}, stalled_{false};
  std::atomic<std::chrono::steady_clock::rep> last_turn_;  // steady_clock ticks
  mutable std::mutex message_mutex_;
  std::string message_;
  std::thread thread_;
};

}  // namespace illum::distributed
