#include "illum/core/work_split.h"

namespace illum {
namespace {
WorkSplit* g_split = nullptr;
}  // namespace

WorkSplit* work_split() {
  return g_split;
}
int work_split_ranks() {
  return g_split ? g_split->ranks() : 1;
}

ScopedWorkSplit::ScopedWorkSplit(WorkSplit* split) : previous_(g_split) {
  g_split = split;
}
ScopedWorkSplit::~ScopedWorkSplit() {
  g_split = previous_;
}

}  // namespace illum
