// What a command does differently as one rank of an MPI job (distributed/README.md): its
// default thread count, and whether it writes the output (rank 0 only).
#pragma once

#include <string>

#include <fmt/format.h>

#include "illum/core/error.h"
#include "illum/core/interrupt.h"
#include "illum/core/work_split.h"

namespace illum::cli {

// --threads when given, else under mpirun the node's cores over its ranks, else 0 (all).
inline int threads_for_this_rank(int threads_option) {
  if (threads_option > 0) return threads_option;
  const WorkSplit* split = work_split();
  return split ? split->threads_per_rank() : 0;
}

// Rank 0 of a job, or a process without one: the one that writes the output and reports.
inline bool writes_output() {
  const WorkSplit* split = work_split();
  return !split || split->is_root();
}

// What cannot be split across ranks without the result depending on their number is
// refused on more than one: an Error (exit 2) saying `what` and `why`.
inline void refuse_with_several_ranks(bool refused, const std::string& what,
                                      const std::string& why) {
  if (refused && work_split_ranks() > 1)
    throw Error(fmt::format("{} cannot run on {} MPI ranks ({}); run it with mpirun -np 1", what,
                            work_split_ranks(), why));
}

// Just before writing: a Ctrl-C (or mpirun's SIGTERM) that came during the last steps still
// leaves no output.
inline void stop_if_interrupted() {
  if (interrupt_requested()) throw Interrupted{};
}

}  // namespace illum::cli
