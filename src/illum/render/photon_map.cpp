#include "illum/render/photon_map.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include <tbb/parallel_invoke.h>

#include "illum/core/error.h"

namespace illum {

namespace {

// Build item: position and the photon's original index, 16 bytes so nth_element moves
// little data; the photons are permuted once at the end.
struct Item {
  vec3 p;
  uint32_t index;
};

// Size of the left subtree of a left-balanced (complete) binary tree with n nodes: all
// levels but the last are full and the last fills from the left.
size_t left_subtree_size(size_t n) {
  if (n <= 1) return 0;
  const int h = std::bit_width(n) - 1;       // 2^h ≤ n < 2^(h+1): h full levels above the last
  const size_t full = (size_t{1} << h) - 1;  // nodes in the full levels
  const size_t last = n - full;              // nodes on the last level
  const size_t half_last = size_t{1} << (h - 1);  // last-level capacity of the left subtree
  return (full - 1) / 2 + std::min(last, half_last);
}

struct Builder {
  std::vector<Item>& items;
  std::vector<uint32_t>& order;  // order[node] = original photon index
  std::vector<uint8_t>& axis;

  void build(size_t begin, size_t end, size_t node) {
    const size_t n = end - begin;
    if (n == 0) return;
    if (n == 1) {
      order[node] = items[begin].index;
      axis[node] = 0;
      return;
    }
    Bounds3 b;
    for (size_t i = begin; i < end; ++i) b.extend(items[i].p);
    const vec3 e = b.extent();
    const int ax = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
    const size_t median = begin + left_subtree_size(n);
    std::nth_element(items.begin() + static_cast<ptrdiff_t>(begin),
                     items.begin() + static_cast<ptrdiff_t>(median),
                     items.begin() + static_cast<ptrdiff_t>(end),
                     [ax](const Item& a, const Item& c) { return a.p[ax] < c.p[ax]; });
    order[node] = items[median].index;
    axis[node] = static_cast<uint8_t>(ax);
    // Subtrees are independent; split the top of the tree across threads.
    if (n > 65536) {
      tbb::parallel_invoke([&] { build(begin, median, 2 * node + 1); },
                           [&] { build(median + 1, end, 2 * node + 2); });
    } else {
      build(begin, median, 2 * node + 1);
      build(median + 1, end, 2 * node + 2);
    }
  }
};

}  // namespace

PhotonMap::PhotonMap(std::vector<Photon> photons) {
  const size_t n = photons.size();
  ILLUM_CHECK(n < 0xffffffffu, "photon map too large ({} photons)", n);
  std::vector<Item> items(n);
  for (size_t i = 0; i < n; ++i) {
    items[i] = {photons[i].position, static_cast<uint32_t>(i)};
    bounds_.extend(photons[i].position);
  }
  std::vector<uint32_t> order(n);
  axis_.assign(n, 0);
  Builder{items, order, axis_}.build(0, n, 0);
  photons_.resize(n);
  positions_.resize(n);
  for (size_t i = 0; i < n; ++i) {
    photons_[i] = photons[order[i]];
    positions_[i] = photons_[i].position;
  }
}

float PhotonMap::knn(const vec3& p, int k, float max_distance,
                     std::vector<PhotonNeighbor>* out) const {
  out->clear();
  const uint32_t n = static_cast<uint32_t>(positions_.size());
  if (n == 0 || k <= 0) return 0.0f;
  const size_t kk = static_cast<size_t>(k);
  float r2 = max_distance * max_distance;
  const auto farther = [](const PhotonNeighbor& a, const PhotonNeighbor& b) {
    return a.distance2 < b.distance2;
  };
  struct Entry {
    uint32_t node;
    float bound2;  // squared distance from p to the node's half-space
  };
  Entry stack[64];
  int top = 0;
  stack[top++] = {0, 0.0f};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.bound2 > r2) continue;
    const uint32_t node = e.node;
    const vec3& q = positions_[node];
    const vec3 d = p - q;
    const float d2 = glm::dot(d, d);
    if (d2 <= r2) {
      if (out->size() < kk) {
        out->push_back({node, d2});
        std::push_heap(out->begin(), out->end(), farther);
        if (out->size() == kk) r2 = out->front().distance2;
      } else {
        std::pop_heap(out->begin(), out->end(), farther);
        out->back() = {node, d2};
        std::push_heap(out->begin(), out->end(), farther);
        r2 = out->front().distance2;
      }
    }
    const uint32_t left = 2 * node + 1;
    if (left >= n) continue;
    const int axis = axis_[node];
    const float delta = p[axis] - q[axis];
    const uint32_t near = delta <= 0.0f ? left : left + 1;
    const uint32_t far = delta <= 0.0f ? left + 1 : left;
    // Far first on the stack so the near side is searched first and shrinks r2.
    if (far < n) stack[top++] = {far, std::max(e.bound2, delta * delta)};
    if (near < n) stack[top++] = {near, e.bound2};
  }
  std::sort_heap(out->begin(), out->end(), farther);
  return out->empty() ? 0.0f : out->back().distance2;
}

void PhotonMap::radius_search(const vec3& p, float radius, std::vector<PhotonNeighbor>* out) const {
  out->clear();
  for_each_in_radius(p, radius, [out](uint32_t i, float d2) { out->push_back({i, d2}); });
}

PhotonFilter parse_photon_filter(const std::string& name) {
  if (name == "none") return PhotonFilter::kNone;
  if (name == "cone") return PhotonFilter::kCone;
  if (name == "gaussian") return PhotonFilter::kGaussian;
  throw Error(fmt::format("photon filter '{}' is unknown (expected none, cone or gaussian)", name));
}

float filter_weight(const FilterSettings& filter, float d2, float r2) {
  switch (filter.type) {
    case PhotonFilter::kNone:
      return 1.0f;
    case PhotonFilter::kCone:
      return std::max(0.0f, 1.0f - std::sqrt(d2 / r2) / filter.cone_k);
    case PhotonFilter::kGaussian: {
      const float b = filter.gauss_beta;
      return filter.gauss_alpha *
             (1.0f - (1.0f - std::exp(-b * d2 / (2.0f * r2))) / (1.0f - std::exp(-b)));
    }
  }
  return 1.0f;
}

float filter_normalization(const FilterSettings& filter) {
  switch (filter.type) {
    case PhotonFilter::kNone:
      return 1.0f;
    case PhotonFilter::kCone:
      return 1.0f - 2.0f / (3.0f * filter.cone_k);
    case PhotonFilter::kGaussian: {
      // With x = d²/r², dA/(πr²) = dx on [0,1]: ∫(1 − e^{−βx/2})dx = 1 − (2/β)(1 − e^{−β/2}).
      // Jensen's α = 0.918, β = 1.953 as printed give 0.531 here, not 1, so we divide by
      // the integral instead of trusting α to normalize (keeps the estimate unbiased for a
      // constant density; the kernel's shape is Jensen's).
      const float b = filter.gauss_beta;
      const float tail = 1.0f - (2.0f / b) * (1.0f - std::exp(-0.5f * b));
      return filter.gauss_alpha * (1.0f - tail / (1.0f - std::exp(-b)));
    }
  }
  return 1.0f;
}

}  // namespace illum
