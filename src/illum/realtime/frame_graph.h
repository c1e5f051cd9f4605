// A small frame graph: passes declare the resources they read and write and when they
// must run (every frame, every N frames, or only after invalidate()). compile() orders the
// passes so every input is produced before it is read (stable: declaration order among
// independent passes) and rejects reads of resources no pass or import produces.
#pragma once

#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "illum/gpu/gpu_timer.h"

namespace illum::realtime {

enum class UpdateSchedule { kEveryFrame, kEveryN, kOnChange };

struct PassDesc {
  std::string name;
  std::vector<std::string> inputs;
  std::vector<std::string> outputs;
  UpdateSchedule schedule = UpdateSchedule::kEveryFrame;
  int period = 1;  // kEveryN: runs on frames where frame % period == 0
  std::function<void(VkCommandBuffer)> record;
  bool self_timed = false;  // the pass opens its own timer scopes (a finer breakdown)
};

class FrameGraph {
 public:
  void import_resource(const std::string& name) { imported_.insert(name); }
  void add_pass(PassDesc pass);
  // Orders the passes; throws InternalError on a missing producer or a cycle.
  void compile();
  // An on-change pass runs at the next execute(); every pass runs on the first frame.
  void invalidate(const std::string& pass);
  void invalidate_all();
  // Records the passes due on `frame`, each inside a timer scope named after it. Returns
  // the names of the passes that ran.
  std::vector<std::string> execute(VkCommandBuffer cmd, uint64_t frame, gpu::GpuTimer* timer);

  const std::vector<std::string>& order() const { return order_; }
  bool has_pass(const std::string& name) const;

 private:
  struct Node {
    PassDesc desc;
    bool dirty = true;
  };
  std::vector<Node> passes_;
  std::vector<size_t> sorted_;
  std::vector<std::string> order_;
  std::set<std::string> imported_;
  bool compiled_ = false;
};

}  // namespace illum::realtime
