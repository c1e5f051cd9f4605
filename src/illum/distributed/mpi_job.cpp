#include "illum/distributed/mpi_job.h"

#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <fmt/ranges.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include "illum/core/error.h"
#include "illum/core/interrupt.h"
#include "illum/core/log.h"
#include "illum/distributed/heartbeat.h"

namespace illum::distributed {

namespace {

// Three tags per phase (request, grant, result), cycling below MPI's guaranteed 32767.
constexpr int kTagsPerPhase = 3;
constexpr int kTagCycle = 30000;
// A unit's records travel as one message, whose size MPI counts in int.
constexpr int64_t kMaxUnitBytes = int64_t{1} << 30;
constexpr int64_t kHeaderBytes = 2 * sizeof(int64_t);  // begin, end

void check(int code, const char* call) {
  if (code != MPI_SUCCESS) {
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(code, text, &length);
    throw Error(fmt::format("MPI: {} failed: {}", call, std::string(text, size_t(length))));
  }
}

}  // namespace

bool launched_by_mpi_launcher() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr;
}

MpiJob::MpiJob(int* argc, char*** argv) {
  // MPI_THREAD_MULTIPLE for the heartbeat's thread; the work protocol itself needs only
  // FUNNELED (rank 0's main thread alone calls MPI for it).
  int provided = MPI_THREAD_SINGLE;
  check(MPI_Init_thread(argc, argv, MPI_THREAD_MULTIPLE, &provided), "MPI_Init_thread");
  if (provided < MPI_THREAD_FUNNELED) {
    MPI_Finalize();
    throw Error("MPI: the library does not support MPI_THREAD_FUNNELED");
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks_);
  MPI_Comm node = MPI_COMM_NULL;
  check(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node),
        "MPI_Comm_split_type");
  MPI_Comm_size(node, &ranks_on_node_);
  MPI_Comm_free(&node);
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads_per_rank_ = std::max(1, cores / std::max(1, ranks_on_node_));
  if (const char* text = std::getenv("ILLUM_TEST_ABORT_RANK")) test_abort_rank_ = std::atoi(text);
  if (const char* text = std::getenv("ILLUM_RANK_TIMEOUT")) {
    char* end = nullptr;
    const double seconds = std::strtod(text, &end);
    if (*text == '\0' || *end != '\0' || !std::isfinite(seconds) || seconds <= 0.0 ||
        seconds > 86400.0)
      settings_error_ =
          fmt::format("ILLUM_RANK_TIMEOUT='{}' must be a number of seconds in (0, 86400]", text);
    else
      rank_timeout_ = seconds;
  }
  // Collective (it duplicates the communicator): every rank decides alike, as `provided` is
  // the library's and the size the job's.
  if (ranks_ > 1 && provided >= MPI_THREAD_MULTIPLE)
    heartbeat_ = std::make_unique<Heartbeat>(MPI_COMM_WORLD, rank_, ranks_, rank_timeout_);
}

MpiJob::~MpiJob() {
  heartbeat_.reset();
  MPI_Finalize();
}

void MpiJob::check_settings() const {
  if (!settings_error_.empty()) throw Error(settings_error_);
}

void MpiJob::abort(int exit_code) {
  MPI_Abort(MPI_COMM_WORLD, exit_code);
  std::_Exit(exit_code);  // MPI_Abort does not return; this keeps [[noreturn]] honest
}

MpiJob::Outcome MpiJob::agree(int code, const std::string& line) {
  std::vector<int> codes(static_cast<size_t>(ranks_), 0);
  check(MPI_Allgather(&code, 1, MPI_INT, codes.data(), 1, MPI_INT, MPI_COMM_WORLD),
        "MPI_Allgather");
  Outcome outcome;
  for (int r = 0; r < ranks_ && outcome.rank < 0; ++r)
    if (codes[static_cast<size_t>(r)] != 0) outcome = {codes[static_cast<size_t>(r)], r, ""};
  if (outcome.rank < 0) return outcome;
  int length = outcome.rank == rank_ ? static_cast<int>(std::min<size_t>(line.size(), 4096)) : 0;
  check(MPI_Bcast(&length, 1, MPI_INT, outcome.rank, MPI_COMM_WORLD), "MPI_Bcast");
  outcome.line =
      outcome.rank == rank_ ? line.substr(0, size_t(length)) : std::string(size_t(length), ' ');
  check(MPI_Bcast(outcome.line.data(), length, MPI_CHAR, outcome.rank, MPI_COMM_WORLD),
        "MPI_Bcast");
  return outcome;
}

int MpiJob::finish(int code, std::string line) {
  auto print = [](const std::string& text) {
    if (!text.empty()) std::fprintf(stderr, "%s\n", text.c_str());
  };
  // A silent peer: no collective can complete, so no MPI_Finalize either.
  if (heartbeat_ && heartbeat_->lost()) heartbeat_->end_job();
  // This rank was the stopped one, and mpirun is ending the job that the others ended:
  // they said why.
  if (code != 0 && heartbeat_ && heartbeat_->stalled_self()) std::_Exit(code);
  // Another rank's line says which rank it comes from; rank 0's reads as without mpirun.
  if (rank_ != 0 && line.rfind("illum: ", 0) == 0)
    line.replace(0, 7, fmt::format("illum: rank {}: ", rank_));
  if (code != 0 && line.empty())
    line = code == 130 ? fmt::format("illum: rank {}: interrupted; nothing was written", rank_)
                       : fmt::format("illum: rank {}: failed with exit code {}", rank_, code);
  // mpirun's SIGTERM: the launcher is already ending every rank, and MPI_Finalize would
  // wait for ranks that are gone. Only rank 0 has a line for it.
  if (code != 0 && interrupt_signal() == SIGTERM) {
    if (rank_ == 0) print(line);
    std::_Exit(code);
  }
  if (agreed_.code != 0) return agreed_end(agreed_);
  // Failed inside a split loop: the other ranks wait in it for this one and cannot come to
  // an agreement, so the job is aborted (mpirun exits with `code`; -q keeps its banner out).
  if (code != 0 && in_loop_) {
    print(line);
    abort(code);
  }
  return agreed_end(agree(code, line));
}

int MpiJob::agreed_end(const Outcome& outcome) const {
  if (rank_ != 0) return 0;
  if (!outcome.line.empty()) std::fprintf(stderr, "%s\n", outcome.line.c_str());
  return outcome.code;
}

void MpiJob::run(int64_t count, size_t record_bytes, int grain, const UnitWork& work,
                 const UnitKeep& keep) {
  // Every rank confirms it reached the loop, so a refusal on any rank before it (bad input
  // one rank sees, a file another cannot read) ends every rank through finish(), with one
  // line, instead of leaving the others waiting here.
  const Outcome before = agree(0, "");
  if (before.code != 0) {
    agreed_ = before;
    throw JobFailed(before.line);
  }
  const int tag = (phase_ * kTagsPerPhase) % kTagCycle;
  ++phase_;
  // A unit: `grain` items for each of this rank's threads, as big as one message may be.
  const int64_t threads = std::max(1, tbb::this_task_arena::max_concurrency());
  const int64_t fit = std::max<int64_t>(
      1, (kMaxUnitBytes - kHeaderBytes) / static_cast<int64_t>(std::max<size_t>(1, record_bytes)));
  const int64_t want = std::clamp<int64_t>(threads * std::max(1, grain), 1, fit);
  // mpirun binds each rank to one core when it starts two or fewer (to a socket above):
  // threads asked for beyond the cores a rank may use would only take turns on them.
  const size_t asked =
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  if (rank_ == 0 && phase_ == 1 && asked > static_cast<size_t>(threads))
    log::warn(
        "distributed: a rank may use {} core(s) (mpirun binds ranks to cores), fewer than its {} "
        "threads; start mpirun with --bind-to none (or --map-by slot:PE={}) to use them",
        threads, asked, asked);
  in_loop_ = true;
  if (rank_ == 0)
    serve(count, record_bytes, want, tag, work, keep);
  else
    ask(count, record_bytes, want, tag, work);
  in_loop_ = false;
}

// Worker: ask for a unit, compute it, send its records, until the root says there is none.
void MpiJob::ask(int64_t /*count*/, size_t record_bytes, int64_t want, int tag,
                 const UnitWork& work) {
  // Test-only (README.md): this rank dies before its first request, so the root can never
  // finish the phase and the launcher must end the job.
  if (test_abort_rank_ == rank_) std::abort();
  std::vector<std::byte> message;
  for (;;) {
    check(MPI_Send(&want, 1, MPI_INT64_T, 0, tag, MPI_COMM_WORLD), "MPI_Send");
    int64_t unit[2] = {0, 0};
    check(MPI_Recv(unit, 2, MPI_INT64_T, 0, tag + 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
          "MPI_Recv");
    if (unit[0] >= unit[1]) return;
    const int64_t items = unit[1] - unit[0];
    message.resize(static_cast<size_t>(kHeaderBytes + items * int64_t(record_bytes)));
    std::memcpy(message.data(), unit, kHeaderBytes);
    work(unit[0], unit[1], message.data() + kHeaderBytes);
    if (interrupt_requested()) throw Interrupted{};
    check(MPI_Send(message.data(), static_cast<int>(message.size()), MPI_BYTE, 0, tag + 2,
                   MPI_COMM_WORLD),
          "MPI_Send");
  }
}

// Root: hand out units on request (guided: a unit is at most 1/(2·ranks) of what is left,
// so the last units are small and no rank is left with a long tail), work on units on a
// second thread, and keep every record.
void MpiJob::serve(int64_t count, size_t record_bytes, int64_t want, int tag, const UnitWork& work,
                   const UnitKeep& keep) {
  std::mutex dispense_mutex, keep_mutex;
  int64_t next = 0;
  bool stop = false;
  auto dispense = [&](int64_t asked) {
    std::lock_guard<std::mutex> lock(dispense_mutex);
    const int64_t left = stop ? 0 : count - next;
    const int64_t n = std::min(left, std::clamp<int64_t>(left / (2 * int64_t(ranks_)), 1, asked));
    const int64_t begin = next;
    next += n;
    return std::pair<int64_t, int64_t>{begin, begin + n};
  };
  std::atomic<int64_t> kept{0};
  std::vector<int64_t> items_of_rank(static_cast<size_t>(ranks_), 0);  // for the log
  std::exception_ptr local_error;
  std::atomic<bool> local_done{false};
  std::thread local([&] {
    try {
      std::vector<std::byte> records;
      for (;;) {
        const auto [begin, end] = dispense(want);
        if (begin >= end) break;
        records.resize(static_cast<size_t>((end - begin) * int64_t(record_bytes)));
        work(begin, end, records.data());
        if (interrupt_requested()) break;
        {
          std::lock_guard<std::mutex> lock(keep_mutex);
          keep(begin, end, records.data());
        }
        kept += end - begin;
        items_of_rank[0] += end - begin;  // this thread's alone
      }
    } catch (...) {
      local_error = std::current_exception();
    }
    local_done = true;
  });
  // Whatever ends the loop below, the local thread must be stopped and joined first.
  auto stop_local = [&] {
    {
      std::lock_guard<std::mutex> lock(dispense_mutex);
      stop = true;
    }
    local.join();
  };

  try {
    int waiting = ranks_ - 1;  // workers not yet told that there is no more work
    std::vector<std::byte> message;
    while (waiting > 0 || kept.load() < count) {
      if (interrupt_requested()) throw Interrupted{};
      if (local_done && local_error) break;
      int flag = 0;
      MPI_Status status;
      check(MPI_Iprobe(MPI_ANY_SOURCE, tag, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe");
      if (flag) {
        int64_t asked = 0;
        check(MPI_Recv(&asked, 1, MPI_INT64_T, status.MPI_SOURCE, tag, MPI_COMM_WORLD,
                       MPI_STATUS_IGNORE),
              "MPI_Recv");
        const auto [begin, end] = dispense(std::max<int64_t>(1, asked));
        const int64_t unit[2] = {begin, end};
        check(MPI_Send(unit, 2, MPI_INT64_T, status.MPI_SOURCE, tag + 1, MPI_COMM_WORLD),
              "MPI_Send");
        if (begin >= end) --waiting;
        continue;
      }
      check(MPI_Iprobe(MPI_ANY_SOURCE, tag + 2, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe");
      if (flag) {
        int bytes = 0;
        MPI_Get_count(&status, MPI_BYTE, &bytes);
        message.resize(static_cast<size_t>(bytes));
        check(MPI_Recv(message.data(), bytes, MPI_BYTE, status.MPI_SOURCE, tag + 2, MPI_COMM_WORLD,
                       MPI_STATUS_IGNORE),
              "MPI_Recv");
        int64_t unit[2];
        std::memcpy(unit, message.data(), kHeaderBytes);
        if (bytes != kHeaderBytes + (unit[1] - unit[0]) * int64_t(record_bytes))
          throw InternalError(fmt::format("MPI: rank {} sent {} bytes for items [{}, {})",
                                          status.MPI_SOURCE, bytes, unit[0], unit[1]));
        {
          std::lock_guard<std::mutex> lock(keep_mutex);
          keep(unit[0], unit[1], message.data() + kHeaderBytes);
        }
        kept += unit[1] - unit[0];
        items_of_rank[static_cast<size_t>(status.MPI_SOURCE)] += unit[1] - unit[0];
        continue;
      }
      // Nothing to answer: sleep briefly rather than spin, so the root's own worker threads
      // keep the core (a unit takes milliseconds; the answer is late by at most this).
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
  } catch (...) {
    stop_local();
    throw;
  }
  stop_local();
  if (local_error) std::rethrow_exception(local_error);
  if (interrupt_requested()) throw Interrupted{};
  // Threads rank 0 could run: its arena (what the binding left it) under --threads's limit.
  const size_t threads = std::min<size_t>(
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism),
      static_cast<size_t>(tbb::this_task_arena::max_concurrency()));
  log::info("distributed: {} items over {} ranks ({}), {} threads on rank 0", count, ranks_,
            fmt::join(items_of_rank, " / "), threads);
}

}  // namespace illum::distributed
