// Parallel loops on TBB. Image work is split into square tiles so neighbouring pixels stay
// in cache and per-tile samplers stay deterministic regardless of scheduling.
#pragma once

#include <cstdint>
#include <functional>

#include <tbb/blocked_range.h>
#include <tbb/blocked_range2d.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

namespace illum {

struct Tile {
  int x0, y0, x1, y1;  // half-open pixel rectangle [x0, x1) x [y0, y1)
  int index;           // stable tile number (row-major), usable as a seed stream
};

// Calls fn(tile) for every tile of a width×height image, in parallel. The order of calls
// is not defined; results that depend only on the tile are deterministic.
void parallel_for_tiles(int width, int height, int tile_size,
                        const std::function<void(const Tile&)>& fn);

// Calls fn(begin, end) over chunks of [0, count) in parallel.
template <typename Fn>
void parallel_for(int64_t count, Fn&& fn, int64_t grain = 1024) {
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, count, grain),
                    [&](const tbb::blocked_range<int64_t>& r) { fn(r.begin(), r.end()); });
}

// Limits TBB to `threads` worker threads while alive (0 = all cores).
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;
  static int hardware_threads();

 private:
  tbb::global_control* control_ = nullptr;
};

}  // namespace illum
