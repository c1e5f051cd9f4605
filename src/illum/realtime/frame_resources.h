// The GPU objects behind the frame graph's resources: an image or buffer per declared
// resource (two for history), sized for the frame, with the usage the graph derived.
// realize() keeps what did not change shape between two assemblies of the frame (a
// technique switched on or off elsewhere keeps the shadow maps and their contents) and
// re-creates the rest.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "illum/gpu/buffer.h"
#include "illum/gpu/gpu_image.h"
#include "illum/realtime/frame_graph.h"

namespace illum::realtime {

class FrameResources {
 public:
  explicit FrameResources(gpu::Context& context) : context_(context) {}

  // Creates or keeps one GPU object per copy of every non-external resource of `graph`
  // (frame-relative sizes from width × height), drops the others and binds them to the
  // graph. Returns the names of the resources created (their contents are undefined).
  std::vector<std::string> realize(FrameGraph& graph, uint32_t width, uint32_t height);

  bool has(const std::string& name) const { return entries_.count(name) > 0; }
  bool has_image(const std::string& name) const {
    auto it = entries_.find(name);
    return it != entries_.end() && !it->second.images.empty();
  }
  gpu::GpuImage& image(const std::string& name, int copy = 0);
  gpu::Buffer& buffer(const std::string& name, int copy = 0);

 private:
  struct Entry {
    ResourceDesc desc;
    uint32_t width = 0, height = 0;
    std::vector<gpu::GpuImage> images;
    std::vector<gpu::Buffer> buffers;
  };
  gpu::Context& context_;
  std::map<std::string, Entry> entries_;
};

}  // namespace illum::realtime
