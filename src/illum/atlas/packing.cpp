// Packing charts into the atlas: cells per chart, skyline bottom-left bins, free rectangles
// of sparse charts as extra bins, and the search for the finest texel size that packs
// (README.md "How it is built", steps 8–10).
#include <algorithm>
#include <cmath>
#include <limits>

#include "illum/atlas/charts.h"
#include "illum/core/error.h"

namespace illum::atlas::detail {

namespace {

// A chart's vertices sit at least this far (in texels) inside its reserved cells, so float
// rounding of uv1 never moves a vertex into a neighbouring texel.
constexpr double kCellMargin = 1.0 / 256.0;
// The texel-size search stops when the finest size that fits is bracketed this tightly.
constexpr double kSearchRelPrecision = 1e-3;
// Charts of at least this many cells filling less than this fraction of their rectangle
// lend its free space to smaller charts.
constexpr double kHostFill = 0.85;
constexpr int kMinHostCells = 1024;
// A host's free space is searched on at most about this many blocks of cells, and
// handed out as at most this many rectangles (the largest first).
constexpr double kMaxHostBlocks = 1 << 16;
constexpr int kMaxHolesPerHost = 12;

// Skyline bottom-left packer: rectangles sorted by decreasing height; each goes where its
// top ends lowest (then leftmost). The skyline is a list of segments covering [0, width).
class SkylinePacker {
 public:
  SkylinePacker(int width, int height) : width_(width), height_(height) {
    segments_.push_back({0, 0, width});
  }

  // Places a w×h rectangle; returns false when it fits nowhere.
  bool place(int w, int h, ivec2& where) {
    if (w > width_ || h > height_) return false;
    int best_top = std::numeric_limits<int>::max(), best_i = -1, best_y = 0;
    // Sliding window [i, j) of segments under the rectangle, with a monotone queue of their
    // heights, so each candidate costs O(1) amortized.
    window_.clear();
    size_t front = 0, j = 0;
    for (size_t i = 0; i < segments_.size(); ++i) {
      const int x = segments_[i].x;
      if (x + w > width_) break;
      while (front < window_.size() && window_[front] < i) ++front;
      while (j < segments_.size() && (j == i || segments_[j - 1].x + segments_[j - 1].w < x + w)) {
        while (window_.size() > front && segments_[window_.back()].y <= segments_[j].y)
          window_.pop_back();
        window_.push_back(j);
        ++j;
      }
      while (front < window_.size() && window_[front] < i) ++front;
      const int y = segments_[window_[front]].y;
      if (y + h <= height_ && y + h < best_top) {
        best_top = y + h;
        best_i = int(i);
        best_y = y;
      }
    }
    if (best_i < 0) return false;
    where = ivec2(segments_[best_i].x, best_y);
    insert(size_t(best_i), w, best_y + h);
    return true;
  }

 private:
  struct Segment {
    int x, y, w;
  };

  void insert(size_t i, int w, int top) {
    const int x0 = segments_[i].x, x1 = x0 + w;
    size_t end = i;  // first segment not fully covered
    while (end < segments_.size() && segments_[end].x + segments_[end].w <= x1) ++end;
    if (end < segments_.size() && segments_[end].x < x1) {
      segments_[end].w -= x1 - segments_[end].x;
      segments_[end].x = x1;
    }
    segments_.erase(segments_.begin() + i, segments_.begin() + end);
    segments_.insert(segments_.begin() + i, Segment{x0, top, w});
    if (i + 1 < segments_.size() && segments_[i + 1].y == top) {
      segments_[i].w += segments_[i + 1].w;
      segments_.erase(segments_.begin() + i + 1);
    }
    if (i > 0 && segments_[i - 1].y == top) {
      segments_[i - 1].w += segments_[i].w;
      segments_.erase(segments_.begin() + i);
    }
  }

  int width_, height_;
  std::vector<Segment> segments_;
  std::vector<size_t> window_;
};

}  // namespace

// Texel cells a chart of `size` metres reserves at texel size `s`: every texel its triangles
// can touch once it is centred in them, with kCellMargin to spare on each side.
ivec2 cells_of(const dvec2& size, double s) {
  const dvec2 t = size / s + 2.0 * kCellMargin;
  return ivec2(int(std::ceil(t.x)), int(std::ceil(t.y)));
}

// Where a chart sits in its cells: centred, so the margin is at least kCellMargin per side.
dvec2 offset_in_cells(const Chart& chart, const ivec2& cells, double s) {
  return 0.5 * (dvec2(cells) - chart.size / s);
}

namespace {

// Free space inside a host chart's cells, as disjoint rectangles (x, y, width, height, in
// cells) that lie more than `padding` cells from every texel the chart touches. The chart's
// conservative coverage (every texel a triangle meets, boundaries included) is marked on a
// grid of blocks of k×k cells (k = 1 up to kMaxHostBlocks cells; coarser blocks only lose
// some free space), grown by ceil(padding / k) blocks; then the largest free rectangles are
// taken one by one (a slanted edge leaves a staircase that row-by-row cutting would slice
// into useless one-row strips).
std::vector<glm::ivec4> free_rectangles(const Chart& chart, const ivec2& cells, double s,
                                        int padding) {
  const int k = std::max(1, int(std::ceil(std::sqrt(double(cells.x) * cells.y / kMaxHostBlocks))));
  const int w = (cells.x + k - 1) / k, h = (cells.y + k - 1) / k;
  std::vector<uint8_t> used(size_t(w) * h, 0);
  const dvec2 offset = offset_in_cells(chart, cells, s);
  for (size_t i = 0; i < chart.triangles.size(); ++i) {
    dvec2 p[3];
    for (int j = 0; j < 3; ++j) p[j] = offset + chart.corners[3 * i + j] / s;
    const double y_lo = std::min(p[0].y, std::min(p[1].y, p[2].y));
    const double y_hi = std::max(p[0].y, std::max(p[1].y, p[2].y));
    // Row by row of cells: the triangle's x-range within the band [y, y + 1] comes from its
    // vertices inside the band and its edges' crossings of the band's two lines.
    for (int y = std::max(0, int(std::floor(y_lo)));
         y <= std::min(cells.y - 1, int(std::floor(y_hi))); ++y) {
      double x_lo = kInf, x_hi = -kInf;
      for (int j = 0; j < 3; ++j) {
        const dvec2 a = p[j], b = p[(j + 1) % 3];
        if (a.y >= y && a.y <= y + 1) {
          x_lo = std::min(x_lo, a.x);
          x_hi = std::max(x_hi, a.x);
        }
        for (const double line : {double(y), double(y + 1)})
          if ((a.y - line) * (b.y - line) < 0.0) {
            const double x = a.x + (b.x - a.x) * (line - a.y) / (b.y - a.y);
            x_lo = std::min(x_lo, x);
            x_hi = std::max(x_hi, x);
          }
      }
      if (x_lo > x_hi) continue;
      const int x0 = std::max(0, int(std::floor(x_lo))) / k;
      const int x1 = std::min(cells.x - 1, int(std::floor(x_hi))) / k;
      std::fill(used.begin() + size_t(y / k) * w + x0, used.begin() + size_t(y / k) * w + x1 + 1,
                uint8_t(1));
    }
  }
  // Grow by r blocks (Chebyshev): running counts along rows, then along columns.
  const int r = (padding + k - 1) / k;
  std::vector<uint8_t> grown(used.size(), 0);
  for (int y = 0; y < h; ++y) {
    const uint8_t* row = &used[size_t(y) * w];
    int count = 0;
    for (int x = 0; x < std::min(w, r); ++x) count += row[x];
    for (int x = 0; x < w; ++x) {
      if (x + r < w) count += row[x + r];
      if (x - r - 1 >= 0) count -= row[x - r - 1];
      grown[size_t(y) * w + x] = count > 0;
    }
  }
  for (int x = 0; x < w; ++x) {
    int count = 0;
    for (int y = 0; y < std::min(h, r); ++y) count += grown[size_t(y) * w + x];
    for (int y = 0; y < h; ++y) {
      if (y + r < h) count += grown[size_t(y + r) * w + x];
      if (y - r - 1 >= 0) count -= grown[size_t(y - r - 1) * w + x];
      used[size_t(y) * w + x] = count > 0;
    }
  }
  // The largest free rectangle (histogram of free runs down each column, a stack per row),
  // taken and marked, up to kMaxHolesPerHost times while one can hold a one-cell chart.
  std::vector<glm::ivec4> rects;
  std::vector<int> run(w), stack;
  for (int hole = 0; hole < kMaxHolesPerHost; ++hole) {
    std::fill(run.begin(), run.end(), 0);
    int64_t best_area = 0;
    glm::ivec4 best(0);  // in blocks: x, y, width, height
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) run[x] = used[size_t(y) * w + x] ? 0 : run[x] + 1;
      stack.clear();
      for (int x = 0; x <= w; ++x) {
        const int height = x < w ? run[x] : 0;
        while (!stack.empty() && run[stack.back()] >= height) {
          const int top = run[stack.back()];
          stack.pop_back();
          const int left = stack.empty() ? 0 : stack.back() + 1;
          const int64_t area = int64_t(top) * (x - left);
          if (area > best_area) {
            best_area = area;
            best = {left, y - top + 1, x - left, top};
          }
        }
        stack.push_back(x);
      }
    }
    if (best_area == 0) break;
    // In cells, clipped to the chart's cells (the last block may reach past them).
    const int cx = best.x * k, cy = best.y * k;
    const int cw = std::min((best.x + best.z) * k, cells.x) - cx;
    const int ch = std::min((best.y + best.w) * k, cells.y) - cy;
    if (cw <= padding || ch <= padding) break;
    rects.push_back({cx, cy, cw, ch});
    for (int y = best.y; y < best.y + best.w; ++y)
      std::fill(used.begin() + size_t(y) * w + best.x,
                used.begin() + size_t(y) * w + best.x + best.z, uint8_t(1));
  }
  return rects;
}

}  // namespace

// Packs every chart at texel size `s`: origins[c] is the first texel of chart c's cells.
// Each item reserves its cells plus `padding` texels on its high sides, in a bin that starts
// and ends `padding` texels inside the atlas border, so cells are ≥ padding apart everywhere.
// Big sparse charts (floor plans) host smaller ones: the free rectangles of their padded
// footprint become bins of their own (an item there also keeps `padding` free on its high
// sides, so items of two disjoint free rectangles stay apart), tried before the skyline.
bool pack_charts(const std::vector<Chart>& charts, double s, int resolution, int padding,
                 std::vector<ivec2>* origins) {
  const int bin = resolution - 2 * padding;
  struct Item {
    ivec2 size;  // cells + padding
    uint32_t chart;
  };
  std::vector<Item> items(charts.size());
  double area = 0.0;  // a lower bound of the area needed (holes excluded)
  for (size_t c = 0; c < charts.size(); ++c) {
    const double cs = charts[c].texel(s);
    const dvec2 texels = charts[c].size / cs;
    if (texels.x > resolution || texels.y > resolution) return false;
    items[c] = {cells_of(charts[c].size, cs) + padding, uint32_t(c)};
    area += std::min(1.0, charts[c].fill()) * items[c].size.x * items[c].size.y;
  }
  if (area > double(bin + padding) * (bin + padding)) return false;
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    if (a.size.y != b.size.y) return a.size.y > b.size.y;
    if (a.size.x != b.size.x) return a.size.x > b.size.x;
    return a.chart < b.chart;
  });
  SkylinePacker packer(bin + padding, bin + padding);
  struct HoleBin {
    ivec2 origin;
    SkylinePacker packer;
    // The smallest item that did not fit: anything as wide and as tall cannot fit later
    // either (bins only fill up), so it is not tried.
    ivec2 failed{std::numeric_limits<int>::max()};
  };
  std::vector<HoleBin> holes;
  if (origins) origins->assign(charts.size(), ivec2(0));
  for (const Item& item : items) {
    ivec2 where, origin;
    bool placed = false;
    for (HoleBin& hole : holes) {
      if (item.size.x >= hole.failed.x && item.size.y >= hole.failed.y) continue;
      if (hole.packer.place(item.size.x, item.size.y, where)) {
        origin = hole.origin + where;
        placed = true;
        break;
      }
      if (item.size.x <= hole.failed.x && item.size.y <= hole.failed.y) hole.failed = item.size;
    }
    if (!placed) {
      if (!packer.place(item.size.x, item.size.y, where)) return false;
      origin = where + padding;
    }
    if (origins) (*origins)[item.chart] = origin;
    const Chart& chart = charts[item.chart];
    const ivec2 cells = item.size - padding;
    if (chart.fill() < kHostFill && cells.x * cells.y >= kMinHostCells)
      for (const glm::ivec4& r : free_rectangles(chart, cells, chart.texel(s), padding))
        holes.push_back({origin + ivec2(r.x, r.y), SkylinePacker(r.z, r.w)});
  }
  return true;
}

namespace {

// The finest texel size that packs, by bisection on log s between the area bound (nothing
// finer can fit) and the size at which every chart is one cell. Returns 0 if even that fails.
// Charts with their own texel size take the same space at every s: the bounds come from the
// others.
double finest_search(const std::vector<Chart>& charts, int resolution, int padding) {
  double area = 0.0, largest = 0.0;  // the triangles' area: no packing needs less
  for (const Chart& c : charts) {
    if (c.texel_size > 0.0) continue;
    area += c.area;
    largest = std::max(largest, std::max(c.size.x, c.size.y));
  }
  // At this size every chart spans less than half a texel: one cell each.
  const double coarse = largest > 0.0 ? 2.0 * largest : 1.0;
  if (!pack_charts(charts, coarse, resolution, padding, nullptr)) return 0.0;
  const double span = double(resolution - 2 * padding);  // cells lie within it
  double lo = std::max(std::sqrt(area) / span, largest / span);
  if (!(lo > 0.0) || lo >= coarse) return coarse;
  if (pack_charts(charts, lo, resolution, padding, nullptr)) return lo;
  // The answer is usually within tens of percent of the area bound: bracket it in steps of
  // 25% before bisecting (fewer packings than bisecting from `coarse`).
  double hi = lo;
  do {
    hi = std::min(hi * 1.25, coarse);
    if (pack_charts(charts, hi, resolution, padding, nullptr)) break;
    lo = hi;
  } while (hi < coarse);
  while (hi / lo > 1.0 + kSearchRelPrecision) {
    const double mid = std::sqrt(lo * hi);
    (pack_charts(charts, mid, resolution, padding, nullptr) ? hi : lo) = mid;
  }
  return hi;
}

}  // namespace

// finest_search rounded up to a float that packs, so Atlas::texel_size given back as
// AtlasOptions::texel_size reproduces the same atlas. Returns 0 if nothing fits.
float finest_texel_size(const std::vector<Chart>& charts, int resolution, int padding) {
  const double s = finest_search(charts, resolution, padding);
  if (!(s > 0.0)) return 0.0f;
  float f = float(s);
  if (double(f) < s) f = std::nextafter(f, kInf);
  // Packing is not strictly monotone in s; a few float steps up always find a size that fits
  // (s itself packed, and f is within one float step of it).
  for (int step = 0; step < 64; ++step, f = std::nextafter(f, kInf))
    if (pack_charts(charts, double(f), resolution, padding, nullptr)) return f;
  ILLUM_CHECK(false, "no float texel size near {} packs", s);
  return 0.0f;
}

}  // namespace illum::atlas::detail
