#include "illum/realtime/frame_graph.h"

#include <algorithm>
#include <map>

#include "illum/core/error.h"

namespace illum::realtime {

void FrameGraph::add_pass(PassDesc pass) {
  ILLUM_CHECK(!has_pass(pass.name), "duplicate pass '{}'", pass.name);
  ILLUM_CHECK(pass.period >= 1, "pass '{}' period must be ≥ 1", pass.name);
  passes_.push_back({std::move(pass), true});
  compiled_ = false;
}

bool FrameGraph::has_pass(const std::string& name) const {
  for (const Node& n : passes_)
    if (n.desc.name == name) return true;
  return false;
}

void FrameGraph::compile() {
  // Kahn's algorithm over "writer before reader" edges; a resource written by several
  // passes (read-modify-write, e.g. lighting accumulation) orders them by declaration.
  const size_t n = passes_.size();
  std::map<std::string, std::vector<size_t>> writers;
  for (size_t i = 0; i < n; ++i)
    for (const std::string& r : passes_[i].desc.outputs) writers[r].push_back(i);
  std::vector<std::set<size_t>> deps(n);
  for (size_t i = 0; i < n; ++i) {
    for (const std::string& r : passes_[i].desc.inputs) {
      auto it = writers.find(r);
      if (it == writers.end()) {
        ILLUM_CHECK(imported_.count(r), "pass '{}' reads '{}', which nothing produces",
                    passes_[i].desc.name, r);
        continue;
      }
      const auto& outs = passes_[i].desc.outputs;
      const bool rmw = std::find(outs.begin(), outs.end(), r) != outs.end();
      for (size_t w : it->second)  // a read-modify-write pass follows only earlier writers
        if (w != i && (!rmw || w < i)) deps[i].insert(w);
    }
    for (const std::string& r : passes_[i].desc.outputs)
      for (size_t w : writers[r])
        if (w < i) deps[i].insert(w);  // keep writes to one resource in declaration order
  }
  sorted_.clear();
  std::vector<bool> done(n, false);
  while (sorted_.size() < n) {
    bool progress = false;
    for (size_t i = 0; i < n; ++i) {
      if (done[i]) continue;
      bool ready = true;
      for (size_t d : deps[i]) ready = ready && done[d];
      if (!ready) continue;
      done[i] = true;
      sorted_.push_back(i);
      progress = true;
      break;  // restart so the order stays as close to declaration order as possible
    }
    ILLUM_CHECK(progress, "frame graph has a cycle");
  }
  order_.clear();
  for (size_t i : sorted_) order_.push_back(passes_[i].desc.name);
  compiled_ = true;
}

void FrameGraph::invalidate(const std::string& pass) {
  for (Node& n : passes_)
    if (n.desc.name == pass) n.dirty = true;
}

void FrameGraph::invalidate_all() {
  for (Node& n : passes_) n.dirty = true;
}

std::vector<std::string> FrameGraph::execute(VkCommandBuffer cmd, uint64_t frame,
                                             gpu::GpuTimer* timer) {
  if (!compiled_) compile();
  std::vector<std::string> ran;
  for (size_t i : sorted_) {
    Node& node = passes_[i];
    bool due = node.dirty;
    switch (node.desc.schedule) {
      case UpdateSchedule::kEveryFrame:
        due = true;
        break;
      case UpdateSchedule::kEveryN:
        due = due || frame % static_cast<uint64_t>(node.desc.period) == 0;
        break;
      case UpdateSchedule::kOnChange:
        break;
    }
    if (!due) continue;
    const bool timed = timer && !node.desc.self_timed;
    const uint32_t scope = timed ? timer->begin(cmd, node.desc.name) : 0;
    if (node.desc.record) node.desc.record(cmd);
    if (timed) timer->end(cmd, scope);
    node.dirty = false;
    ran.push_back(node.desc.name);
  }
  return ran;
}

}  // namespace illum::realtime
