// The MPI side of a distributed run: one MpiJob per process started by `mpirun`, installed
// as the process's WorkSplit (core/work_split.h) so render tiles and light-map texels are
// handed out across ranks. Rank 0 serves work units on request from its main thread (the
// only thread that calls MPI: MPI_THREAD_FUNNELED), works on units itself on a second
// thread, and receives every record; it alone writes output. See README.md for the
// protocol and the failure behaviour.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "illum/core/error.h"
#include "illum/core/work_split.h"

namespace illum::distributed {

// True when an MPI launcher started this process (Open MPI's mpirun/mpiexec, or a PMIx
// launcher such as srun --mpi=pmix). Without one the program never calls MPI_Init: a
// singleton MPI_Init costs about 0.4 s in a container (README.md) and can print warnings.
bool launched_by_mpi_launcher();

class Heartbeat;

// Thrown by run() on every rank when another rank failed before the loop: the job ends with
// that rank's exit code and line (MpiJob::finish prints it on rank 0).
class JobFailed : public Error {
 public:
  using Error::Error;
};

// How long a rank may stay silent before the job is ended (ILLUM_RANK_TIMEOUT, seconds).
inline constexpr double kDefaultRankTimeout = 30.0;

class MpiJob final : public WorkSplit {
 public:
  // MPI_Init_thread; throws Error when MPI cannot start or lacks MPI_THREAD_FUNNELED.
  MpiJob(int* argc, char*** argv);
  ~MpiJob() override;  // MPI_Finalize (not after abort, which does not return)
  MpiJob(const MpiJob&) = delete;
  MpiJob& operator=(const MpiJob&) = delete;

  int ranks() const override { return ranks_; }
  int rank() const override { return rank_; }
  // The node's cores (std::thread::hardware_concurrency) over the ranks sharing the node
  // (MPI_COMM_TYPE_SHARED), at least 1.
  int threads_per_rank() const override { return threads_per_rank_; }
  int ranks_on_node() const { return ranks_on_node_; }

  void run(int64_t count, size_t record_bytes, int grain, const UnitWork& work,
           const UnitKeep& keep) override;

  // Throws Error (one line) for a bad ILLUM_RANK_TIMEOUT; called inside the CLI's error
  // handling, so the refusal ends the job like any other (finish).
  void check_settings() const;
  double rank_timeout() const { return rank_timeout_; }

  // How every rank ends the job, called by each once with its exit code and its one stderr
  // line ("" when none). Returns the exit code for main to return, after the ranks agreed on
  // it (collective: the first failing rank's code and line, which rank 0 alone prints and
  // returns; the others return 0, see agreed_end) —
  // unless agreeing is impossible: a rank that failed inside a split loop (the others wait
  // for it there) prints its line and calls MPI_Abort; a silent peer (heartbeat) or mpirun's
  // SIGTERM ends the process without MPI_Finalize.
  int finish(int code, std::string line);

  // Ends every rank of the job with `exit_code` (MPI_Abort). For a rank's error or
  // interrupt: the other ranks may be waiting on this one and would never finish.
  [[noreturn]] void abort(int exit_code);

 private:
  struct Outcome {
    int code = 0, rank = -1;
    std::string line;
  };
  // Collective over every rank: each gives its code (0: fine) and line; all learn the first
  // failing rank's. Matches the agreement at the start of run() as well as finish()'s.
  Outcome agree(int code, const std::string& line);
  // After an agreement: rank 0 prints the line and returns the code; the other ranks return
  // 0. mpirun ends the job at the first non-zero exit it sees, possibly before it forwarded
  // rank 0's line from its pipe; a process's own exit waits for its output to be forwarded,
  // so rank 0 alone exits with the code (and mpirun with it).
  int agreed_end(const Outcome& outcome) const;

  void serve(int64_t count, size_t record_bytes, int64_t want, int tag, const UnitWork& work,
             const UnitKeep& keep);
  void ask(int64_t count, size_t record_bytes, int64_t want, int tag, const UnitWork& work);

  int rank_ = 0, ranks_ = 1, ranks_on_node_ = 1, threads_per_rank_ = 1;
  int phase_ = 0;             // run() calls so far: each phase has its own message tags
  int test_abort_rank_ = -1;  // ILLUM_TEST_ABORT_RANK (README.md): test-only
  double rank_timeout_ = kDefaultRankTimeout;
  std::string settings_error_;
  bool in_loop_ = false;  // an exception left run() mid-protocol: the ranks cannot agree
  Outcome agreed_;        // a failure the ranks already agreed on (run() threw JobFailed)
  std::unique_ptr<Heartbeat> heartbeat_;
};

}  // namespace illum::distributed
