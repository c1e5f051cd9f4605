// Splitting a job's independent work items across processes (ranks) without knowing how the
// processes talk: the distributed layer (src/illum/distributed, MPI) installs a WorkSplit
// for the whole run, and the loops that can be split (render tiles, light-map texels) ask
// for it here. With none installed, or one rank, they run exactly as before, in one process.
//
// The contract that keeps results independent of the rank count: an item's record depends
// only on the item (per-pixel / per-texel seeding), never on who computed it, and the root
// receives every record and alone builds the result. Other ranks receive nothing back.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <type_traits>
#include <vector>

#include "illum/core/parallel.h"

namespace illum {

class WorkSplit {
 public:
  virtual ~WorkSplit() = default;
  virtual int ranks() const = 0;
  virtual int rank() const = 0;
  bool is_root() const { return rank() == 0; }
  // Worker threads a rank uses when the user did not say (--threads 0).
  virtual int threads_per_rank() const = 0;

  // Fills `out` with the records of items [begin, end), `record_bytes` each, using the
  // rank's threads.
  using UnitWork = std::function<void(int64_t begin, int64_t end, std::byte* out)>;
  // Receives the records of items [begin, end) on the root.
  using UnitKeep = std::function<void(int64_t begin, int64_t end, const std::byte* records)>;

  // Collective: every rank calls it, in the same order, with the same `count` and
  // `record_bytes`. Items [0, count) are handed out in units of consecutive items on demand
  // (faster ranks get more); a unit holds up to `grain` items per worker thread of the rank
  // asking. On the root, `keep` sees every item exactly once (units in any order, one call
  // at a time) before run returns. Throws Interrupted on Ctrl-C / termination.
  virtual void run(int64_t count, size_t record_bytes, int grain, const UnitWork& work,
                   const UnitKeep& keep) = 0;
};

// The split installed for this process, or nullptr (single process).
WorkSplit* work_split();
// Ranks of the installed split; 1 without one.
int work_split_ranks();

// Installs `split` for its lifetime (the CLI's main does this under mpirun).
class ScopedWorkSplit {
 public:
  explicit ScopedWorkSplit(WorkSplit* split);
  ~ScopedWorkSplit();
  ScopedWorkSplit(const ScopedWorkSplit&) = delete;
  ScopedWorkSplit& operator=(const ScopedWorkSplit&) = delete;

 private:
  WorkSplit* previous_;
};

// Computes record = compute(i) for every i in [0, count) and calls store(i, record): in one
// process, both in parallel (grain items per task); across ranks (a split with more than one
// rank installed), compute on whichever rank gets the item and store on the root only, one
// call at a time. `Record` travels as bytes, so it must be trivially copyable.
template <typename Record, typename Compute, typename Store>
void split_items(int64_t count, int grain, Compute&& compute, Store&& store) {
  static_assert(std::is_trivially_copyable_v<Record>);
  WorkSplit* split = work_split();
  if (!split || split->ranks() == 1) {
    parallel_for(
        count,
        [&](int64_t begin, int64_t end) {
          for (int64_t i = begin; i < end; ++i) store(i, compute(i));
        },
        grain);
    return;
  }
  split->run(
      count, sizeof(Record), grain,
      [&](int64_t begin, int64_t end, std::byte* out) {
        parallel_for(
            end - begin,
            [&](int64_t b, int64_t e) {
              for (int64_t k = b; k < e; ++k) {
                const Record record = compute(begin + k);
                std::memcpy(out + static_cast<size_t>(k) * sizeof(Record), &record, sizeof(Record));
              }
            },
            1);
      },
      [&](int64_t begin, int64_t end, const std::byte* records) {
        for (int64_t i = begin; i < end; ++i) {
          Record record;
          std::memcpy(&record, records + static_cast<size_t>(i - begin) * sizeof(Record),
                      sizeof(Record));
          store(i, record);
        }
      });
}

}  // namespace illum
