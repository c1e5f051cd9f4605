#include "illum/core/parallel.h"

#include <tbb/info.h>

namespace illum {

void parallel_for_tiles(int width, int height, int tile_size,
                        const std::function<void(const Tile&)>& fn) {
  const int tiles_x = (width + tile_size - 1) / tile_size;
  const int tiles_y = (height + tile_size - 1) / tile_size;
  tbb::parallel_for(
      tbb::blocked_range<int>(0, tiles_x * tiles_y, 1), [&](const tbb::blocked_range<int>& r) {
        for (int i = r.begin(); i != r.end(); ++i) {
          const int tx = i % tiles_x, ty = i / tiles_x;
          Tile t{tx * tile_size, ty * tile_size, std::min(width, (tx + 1) * tile_size),
                 std::min(height, (ty + 1) * tile_size), i};
          fn(t);
        }
      });
}

ThreadLimit::ThreadLimit(int threads) {
  if (threads > 0)
    control_ = new tbb::global_control(tbb::global_control::max_allowed_parallelism,
                                       static_cast<size_t>(threads));
}
ThreadLimit::~ThreadLimit() {
  delete control_;
}
int ThreadLimit::hardware_threads() {
  return tbb::info::default_concurrency();
}

}  // namespace illum
