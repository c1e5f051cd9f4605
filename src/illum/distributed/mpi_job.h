// The MPI side of a distributed run: one MpiJob per process started by `mpirun`, installed
// as the process's WorkSplit (core/work_split.h) so render tiles and light-map texels are
// handed out across ranks. Rank 0 serves work units on request from its main thread (the
// only thread that calls MPI: MPI_THREAD_FUNNELED), works on units itself on a second
// thread, and receives every record; it alone writes output. See README.md for the
// protocol and the failure behaviour.
#pragma once

#include <cstdint>

#include "illum/core/work_split.h"

namespace illum::distributed {

// True when an MPI launcher started this process (Open MPI's mpirun/mpiexec, or a PMIx
// launcher such as srun --mpi=pmix). Without one the program never calls MPI_Init: a
// singleton MPI_Init costs about 0.4 s in a container (README.md) and can print warnings.
bool launched_by_mpi_launcher();

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

  // Ends every rank of the job with `exit_code` (MPI_Abort). For a rank's error or
  // interrupt: the other ranks may be waiting on this one and would never finish.
  [[noreturn]] void abort(int exit_code);

 private:
  void serve(int64_t count, size_t record_bytes, int64_t want, int tag, const UnitWork& work,
             const UnitKeep& keep);
  void ask(int64_t count, size_t record_bytes, int64_t want, int tag, const UnitWork& work);

  int rank_ = 0, ranks_ = 1, ranks_on_node_ = 1, threads_per_rank_ = 1;
  int phase_ = 0;             // run() calls so far: each phase has its own message tags
  int test_abort_rank_ = -1;  // ILLUM_TEST_ABORT_RANK (README.md): test-only
};

}  // namespace illum::distributed
