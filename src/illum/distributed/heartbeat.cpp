#include "illum/distributed/heartbeat.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "illum/core/interrupt.h"

namespace illum::distributed {

namespace {
constexpr int kTag = 1;
// How long the main thread gets to unwind (remove temporaries, print) once the job is lost,
// before the heartbeat thread ends the process itself: the main thread may be blocked in an
// MPI call that waits on the silent peer and never returns.
constexpr std::chrono::milliseconds kGrace{2000};
}  // namespace

Heartbeat::Heartbeat(MPI_Comm world, int rank, int ranks, double timeout_s)
    : rank_(rank),
      ranks_(ranks),
      timeout_(timeout_s),
      // Ten beats per timeout, at most one a second: a late beat or two never counts as silence.
      period_(std::min(1.0, timeout_s / 10.0)),
      heard_(size_t(ranks), std::chrono::steady_clock::now()) {
  MPI_Comm_dup(world, &comm_);
  // A failure on this communicator (a peer gone) must not end the process with Open MPI's
  // banner: the heartbeat's own timeout says what happened.
  MPI_Comm_set_errhandler(comm_, MPI_ERRORS_RETURN);
  last_turn_ = std::chrono::steady_clock::now().time_since_epoch().count();
  thread_ = std::thread([this] { loop(); });
}

Heartbeat::~Heartbeat() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

std::string Heartbeat::lost_message() const {
  std::lock_guard<std::mutex> lock(message_mutex_);
  return message_;
}

void Heartbeat::end_job() {
  if (reports_) {
    if (!printed_.exchange(true)) {
      const std::string line = lost_message();
      std::fprintf(stderr, "%s\n", line.c_str());
      std::fflush(stderr);
    }
    std::_Exit(kLostExitCode);
  }
  // Another rank reports: its exit makes mpirun end this one. Exiting first would let mpirun
  // end the reporter before it printed (it may notice the silence a beat later), so this
  // rank waits, and exits on its own only if nothing ends it.
  std::this_thread::sleep_for(timeout_ + kGrace);
  std::_Exit(kLostExitCode);
}

bool Heartbeat::stalled_self() const {
  const auto now = std::chrono::steady_clock::now().time_since_epoch().count();
  return stalled_ || std::chrono::steady_clock::duration(now - last_turn_.load()) > timeout_ / 2;
}

void Heartbeat::loop() {
  using Clock = std::chrono::steady_clock;
  const char beat = 1;
  auto next = Clock::now();
  Clock::time_point deadline{};  // once peers are lost: when end_job() runs at the latest
  while (!stop_) {
    const auto now = Clock::now();
    // A turn long after the last one (turns come every 10 ms): this process was stopped, not
    // its peers. Half the timeout, because the peers end the job a timeout after this
    // process's last beat, which may have come shortly before it stopped.
    if (now - Clock::time_point(Clock::duration(last_turn_.load())) > timeout_ / 2) stalled_ = true;
    last_turn_ = now.time_since_epoch().count();
    if (now >= next) {
      for (int r = 0; r < ranks_; ++r) {
        if (r == rank_) continue;
        MPI_Request request;
        // Eager and never waited for: a stopped peer must not block this thread.
        if (MPI_Isend(&beat, 1, MPI_CHAR, r, kTag, comm_, &request) == MPI_SUCCESS)
          MPI_Request_free(&request);
      }
      next = now + std::chrono::duration_cast<Clock::duration>(period_);
    }
    // Drained before silence is judged, so a process that was itself stopped hears the
    // beats that waited for it and blames no peer.
    for (;;) {
      int flag = 0;
      MPI_Status status;
      if (MPI_Iprobe(MPI_ANY_SOURCE, kTag, comm_, &flag, &status) != MPI_SUCCESS || !flag) break;
      char got = 0;
      MPI_Recv(&got, 1, MPI_CHAR, status.MPI_SOURCE, kTag, comm_, MPI_STATUS_IGNORE);
      heard_[size_t(status.MPI_SOURCE)] = Clock::now();
    }
    if (lost_) {
      if (Clock::now() >= deadline) end_job();
    } else if (!stalled_) {
      std::vector<int> silent;
      for (int r = 0; r < ranks_; ++r)
        // Against the turn's start: a process stopped during this turn judges after its next
        // turn, which first notices the stop (stalled_) and drains the beats that waited.
        if (r != rank_ && now - heard_[size_t(r)] > timeout_) silent.push_back(r);
      if (!silent.empty()) {
        bool lowest = true;
        for (int r = 0; r < rank_; ++r)
          lowest = lowest && std::find(silent.begin(), silent.end(), r) != silent.end();
        {
          std::lock_guard<std::mutex> lock(message_mutex_);
          message_ = fmt::format(
              "illum: error: rank{} {} sent no sign of life for {:g} s (stopped or hung; "
              "ILLUM_RANK_TIMEOUT sets the limit); the job was ended and nothing was written",
              silent.size() > 1 ? "s" : "", fmt::join(silent, ", "), timeout_.count());
        }
        reports_ = lowest;
        lost_ = true;
        // Loops poll the interrupt flag: the main thread stops its work, unwinds (removing
        // staging files) and ends the job through end_job(). Beats go on meanwhile, so the
        // peers do not take this rank for silent too.
        request_interrupt();
        deadline =
            Clock::now() + std::chrono::duration_cast<Clock::duration>(
                               std::min<std::chrono::duration<double>>(kGrace, timeout_ / 2));
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

}  // namespace illum::distributed
