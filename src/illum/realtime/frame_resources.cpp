#include "illum/realtime/frame_resources.h"

#include <algorithm>

#include "illum/core/error.h"

namespace illum::realtime {

std::vector<std::string> FrameResources::realize(FrameGraph& graph, uint32_t width,
                                                 uint32_t height) {
  std::vector<std::string> created;
  std::map<std::string, Entry> next;
  for (const ResourceDesc& d : graph.resources()) {
    if (d.external) continue;
    uint32_t w = d.width, h = d.height;
    if (d.frame_divisor > 0) {
      w = std::max(1u, width / d.frame_divisor);
      h = std::max(1u, height / d.frame_divisor);
    }
    auto old = entries_.find(d.name);
    if (old != entries_.end() && old->second.desc.same_shape(d) && old->second.width == w &&
        old->second.height == h) {
      next.emplace(d.name, std::move(old->second));
    } else {
      Entry e;
      e.desc = d;
      e.width = w;
      e.height = h;
      const int copies = d.history ? 2 : 1;
      for (int c = 0; c < copies; ++c) {
        if (d.kind == ResourceDesc::Kind::kImage) {
          gpu::ImageDesc id;
          id.width = w;
          id.height = h;
          id.layers = d.layers;
          id.depth = d.depth;
          id.mips = d.mips == 0 ? gpu::mip_chain_length(w, h, d.depth) : d.mips;
          id.format = d.format;
          id.usage = d.usage;
          id.cube = d.cube;
          id.cube_array = d.cube_array;
          id.array = d.array;
          e.images.emplace_back(context_, id);
        } else {
          e.buffers.emplace_back(context_, std::max<uint64_t>(d.bytes, 4), d.usage,
                                 gpu::MemoryUsage::kDevice);
        }
      }
      next.emplace(d.name, std::move(e));
      created.push_back(d.name);
    }
  }
  entries_ = std::move(next);
  for (auto& [name, e] : entries_) {
    for (size_t c = 0; c < e.images.size(); ++c)
      graph.bind_image(name, static_cast<int>(c), &e.images[c]);
    for (size_t c = 0; c < e.buffers.size(); ++c)
      graph.bind_buffer(name, static_cast<int>(c), &e.buffers[c]);
  }
  return created;
}

gpu::GpuImage& FrameResources::image(const std::string& name, int copy) {
  auto it = entries_.find(name);
  ILLUM_CHECK(it != entries_.end() && static_cast<size_t>(copy) < it->second.images.size(),
              "no image '{}' in this frame", name);
  return it->second.images[static_cast<size_t>(copy)];
}

gpu::Buffer& FrameResources::buffer(const std::string& name, int copy) {
  auto it = entries_.find(name);
  ILLUM_CHECK(it != entries_.end() && static_cast<size_t>(copy) < it->second.buffers.size(),
              "no buffer '{}' in this frame", name);
  return it->second.buffers[static_cast<size_t>(copy)];
}

}  // namespace illum::realtime
