#include "illum/realtime/frame_graph.h"

#include <algorithm>
#include <chrono>
#include <numeric>

#include "illum/core/error.h"
#include "illum/gpu/buffer.h"
#include "illum/gpu/gpu_image.h"

namespace illum::realtime {

namespace {

// Uses that need contents written before (attachments may load, but a pass that only
// renders to a target may also clear it, so they do not count).
constexpr Uses kReadUses =
    kSampled | kStorageRead | kDepthReadOnly | kTransferSrc | kVertexInput | kIndirectArgs;
constexpr const char* kPrevious = ".previous";

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

uint32_t usage_of(Uses uses, bool image) {
  uint32_t u = 0;
  if (image) {
    if (uses & kSampled) u |= VK_IMAGE_USAGE_SAMPLED_BIT;
    if (uses & (kStorageRead | kStorageWrite)) u |= VK_IMAGE_USAGE_STORAGE_BIT;
    if (uses & kColorAttachment) u |= VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    if (uses & (kDepthAttachment | kDepthReadOnly))
      u |= VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
    if (uses & kTransferSrc) u |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    if (uses & kTransferDst) u |= VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  } else {
    if (uses & (kStorageRead | kStorageWrite)) u |= VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    if (uses & kVertexInput) u |= VK_BUFFER_USAGE_VERTEX_BUFFER_BIT;
    if (uses & kIndirectArgs) u |= VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;
    if (uses & kTransferSrc) u |= VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    if (uses & kTransferDst) u |= VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  }
  return u;
}

}  // namespace

Schedule Schedule::every_n(int period, int phase, Changes changes) {
  Schedule s;
  s.kind = Kind::kEveryN;
  s.period = period;
  s.phase = phase;
  s.invalidated_by = changes;
  return s;
}

Schedule Schedule::round_robin(int items, int per_frame, Changes changes) {
  Schedule s;
  s.kind = Kind::kRoundRobin;
  s.items = items;
  s.per_frame = per_frame;
  s.invalidated_by = changes;
  return s;
}

Schedule Schedule::on_change(Changes changes, int items) {
  Schedule s;
  s.kind = Kind::kOnChange;
  s.items = items;
  s.invalidated_by = changes;
  return s;
}

bool ResourceDesc::same_shape(const ResourceDesc& o) const {
  return kind == o.kind && width == o.width && height == o.height &&
         frame_divisor == o.frame_divisor && depth == o.depth && mips == o.mips &&
         format == o.format && layers == o.layers && cube == o.cube && cube_array == o.cube_array &&
         array == o.array && bytes == o.bytes && history == o.history && external == o.external &&
         usage == o.usage;
}

PassContext::Scope::Scope(gpu::GpuTimer* timer, VkCommandBuffer cmd, const std::string& name)
    : timer_(cmd ? timer : nullptr), cmd_(cmd) {
  if (timer_) scope_ = timer_->begin(cmd_, name);
}

PassContext::Scope::~Scope() {
  if (timer_) timer_->end(cmd_, scope_);
}

void PassContext::use(const std::string& resource, Uses uses, VkPipelineStageFlags2 shaders) {
  use(Access{resource, uses, shaders});
}

void PassContext::use(const Access& access) {
  // Only what the pass declared: the usage flags and the order checks come from there.
  Uses declared = 0;
  for (const Access& a : pass_->accesses)
    if (a.resource == access.resource) declared |= a.uses;
  ILLUM_CHECK((access.uses & ~declared) == 0, "pass '{}' uses '{}' in a way it did not declare",
              pass_->name, access.resource);
  graph_->apply(access, frame_, cmd_);
}

PassContext::Aside::Aside(PassContext& pass, const std::string& name) : pass_(pass) {
  if (!pass_.timer_ || !pass_.open_scope_) return;
  pass_.timer_->end(pass_.cmd_, *pass_.open_scope_);
  scope_ = pass_.timer_->begin(pass_.cmd_, name);
}

PassContext::Aside::~Aside() {
  if (!pass_.timer_ || !pass_.open_scope_) return;
  pass_.timer_->end(pass_.cmd_, scope_);
  *pass_.open_scope_ = pass_.timer_->begin(pass_.cmd_, pass_.pass_->timer);
}

const std::string& PassContext::label() const {
  return pass_->timer;
}

void PassContext::clusters(double count) {
  if (timer_) timer_->note_clusters(count);
}

void PassContext::bytes(double count) {
  if (timer_) timer_->note_bytes(count);
}

void PassContext::drawn(VkBuffer counter, VkDeviceSize offset) {
  if (timer_) timer_->note_drawn(cmd_, counter, offset);
}

void PassContext::fill(const gpu::RasterFill& f, double count) {
  if (timer_) timer_->note_fill(f, count);
}

bool PassContext::counting() const {
  return timer_ && timer_->counting();
}

uint32_t PassContext::begin_count() {
  return counting() ? timer_->begin_count(cmd_) : 0;
}

void PassContext::end_count(uint32_t query, const gpu::RasterFill& per_sample, int minus) {
  if (counting()) timer_->end_count(cmd_, query, per_sample, minus);
}

uint32_t PassContext::begin_rasterized() {
  return counting() ? timer_->begin_rasterized(cmd_) : ~0u;
}

void PassContext::end_rasterized(uint32_t query) {
  if (counting()) timer_->end_rasterized(cmd_, query);
}

bool PassContext::counts_quads() const {
  return counting() && timer_->counts_quads();
}

void PassContext::begin_quads(VkBuffer counter) {
  if (counts_quads()) timer_->begin_quads(cmd_, counter);
}

void PassContext::end_quads(VkBuffer counter) {
  if (counts_quads()) timer_->end_quads(cmd_, counter);
}

bool PassContext::counts_tested() const {
  return counting() && timer_->counts_tested();
}

void PassContext::triangles(double count) {
  if (timer_) timer_->note_triangles(count);
}

bool PassContext::reads(const std::string& resource) const {
  return std::any_of(pass_->accesses.begin(), pass_->accesses.end(),
                     [&](const Access& a) { return a.resource == resource; });
}

bool PassContext::has_history(const std::string& resource) const {
  return graph_->copy_of(resource + kPrevious).written_frame >= 0;
}

int PassContext::copy(const std::string& name) const {
  return graph_->copy_index(name);
}

gpu::GpuImage* PassContext::image(const std::string& name) const {
  return graph_->copy_of(name).image;
}

gpu::Buffer* PassContext::buffer(const std::string& name) const {
  return graph_->copy_of(name).buffer;
}

void FrameGraph::add_resource(ResourceDesc desc) {
  ILLUM_CHECK(!has_resource(desc.name), "duplicate resource '{}'", desc.name);
  ILLUM_CHECK(!ends_with(desc.name, kPrevious), "resource name '{}' ends in {}", desc.name,
              kPrevious);
  ILLUM_CHECK(desc.kind == ResourceDesc::Kind::kBuffer || desc.format != VK_FORMAT_UNDEFINED,
              "image '{}' has no format", desc.name);
  ILLUM_CHECK(desc.depth >= 1 && (desc.depth == 1 || (desc.layers == 1 && !desc.cube)),
              "image '{}': a 3-D image has one layer and is not a cube", desc.name);
  resources_.push_back(std::move(desc));
  copies_.emplace_back(resources_.back().history ? 2 : 1);
  versions_.emplace_back();
  compiled_ = false;
}

void FrameGraph::add_pass(PassDesc pass) {
  ILLUM_CHECK(!has_pass(pass.name), "duplicate pass '{}'", pass.name);
  const Schedule& s = pass.schedule;
  ILLUM_CHECK(s.period >= 1 && s.phase >= 0 && s.items >= 1 && s.per_frame >= 1,
              "pass '{}': bad schedule", pass.name);
  if (pass.timer.empty()) pass.timer = pass.name;
  const size_t items = static_cast<size_t>(s.items);
  passes_.push_back({std::move(pass), std::vector<bool>(items, true), 0});
  compiled_ = false;
}

void FrameGraph::require(const std::string& resource, const std::string& hint) {
  required_.emplace_back(resource, hint);
}

bool FrameGraph::has_pass(const std::string& name) const {
  return std::any_of(passes_.begin(), passes_.end(),
                     [&](const Node& n) { return n.desc.name == name; });
}

bool FrameGraph::reads(const std::string& pass, const std::string& resource) const {
  for (const Node& n : passes_)
    if (n.desc.name == pass)
      return std::any_of(n.desc.accesses.begin(), n.desc.accesses.end(),
                         [&](const Access& a) { return a.resource == resource; });
  return false;
}

bool FrameGraph::has_resource(const std::string& name) const {
  return std::any_of(resources_.begin(), resources_.end(),
                     [&](const ResourceDesc& r) { return r.name == name; });
}

const ResourceDesc& FrameGraph::resource(const std::string& name) const {
  const auto l = find(name);
  ILLUM_CHECK(l.has_value(), "no resource '{}'", name);
  return resources_[l->resource];
}

const PassDesc& FrameGraph::pass(const std::string& name) const {
  for (const Node& n : passes_)
    if (n.desc.name == name) return n.desc;
  throw InternalError(fmt::format("no pass '{}'", name));
}

std::optional<FrameGraph::Logical> FrameGraph::find(const std::string& name) const {
  const bool previous = ends_with(name, kPrevious);
  const std::string base =
      previous ? name.substr(0, name.size() - std::string(kPrevious).size()) : name;
  for (size_t i = 0; i < resources_.size(); ++i)
    if (resources_[i].name == base) {
      if (previous && !resources_[i].history) return std::nullopt;
      return Logical{i, previous};
    }
  return std::nullopt;
}

int FrameGraph::copy_index(const std::string& name) const {
  const auto l = find(name);
  ILLUM_CHECK(l.has_value(), "no resource '{}'", name);
  if (!resources_[l->resource].history) return 0;
  const int current = versions_[l->resource].current;
  return l->previous ? 1 - current : current;
}

FrameGraph::Copy& FrameGraph::copy_of(const std::string& name) {
  const auto l = find(name);
  ILLUM_CHECK(l.has_value(), "no resource '{}'", name);
  return copies_[l->resource][static_cast<size_t>(copy_index(name))];
}

const FrameGraph::Copy& FrameGraph::copy_of(const std::string& name) const {
  return const_cast<FrameGraph*>(this)->copy_of(name);
}

void FrameGraph::swap_written_history(const PassDesc& pass, uint64_t frame) {
  for (const Access& a : pass.accesses) {
    if (!writes(a.uses)) continue;
    const auto l = find(a.resource);
    if (!l || l->previous || !resources_[l->resource].history) continue;
    Versions& v = versions_[l->resource];
    if (v.swapped_frame == static_cast<int64_t>(frame)) continue;
    v.current = 1 - v.current;
    v.swapped_frame = static_cast<int64_t>(frame);
  }
}

int FrameGraph::copies(const std::string& resource) const {
  const auto l = find(resource);
  ILLUM_CHECK(l.has_value() && !l->previous, "no resource '{}'", resource);
  return static_cast<int>(copies_[l->resource].size());
}

void FrameGraph::bind_image(const std::string& resource, int copy, gpu::GpuImage* image) {
  const auto l = find(resource);
  ILLUM_CHECK(l.has_value() && !l->previous, "no resource '{}'", resource);
  Copy& c = copies_[l->resource].at(static_cast<size_t>(copy));
  c.image = image;
  // A re-created image starts with no state; one of the same shape keeps it (inherit()).
  const size_t subresources = static_cast<size_t>(levels_of(resources_[l->resource], c)) *
                              layers_of(resources_[l->resource]);
  if (c.states.size() != subresources) c.states.assign(subresources, ResourceState{});
}

uint32_t FrameGraph::levels_of(const ResourceDesc& r, const Copy& copy) const {
  if (r.kind != ResourceDesc::Kind::kImage) return 1;
  if (copy.image) return copy.image->desc().mips;
  return std::max(r.mips, 1u);
}

uint32_t FrameGraph::layers_of(const ResourceDesc& r) const {
  return r.kind == ResourceDesc::Kind::kImage ? r.layers : 1;
}

void FrameGraph::bind_buffer(const std::string& resource, int copy, gpu::Buffer* buffer) {
  const auto l = find(resource);
  ILLUM_CHECK(l.has_value() && !l->previous, "no resource '{}'", resource);
  copies_[l->resource].at(static_cast<size_t>(copy)).buffer = buffer;
}

void FrameGraph::compile() {
  for (Node& n : passes_)
    std::erase_if(n.desc.accesses,
                  [&](const Access& a) { return a.optional && !find(a.resource).has_value(); });
  sorted_.resize(passes_.size());
  std::iota(sorted_.begin(), sorted_.end(), size_t{0});
  std::stable_sort(sorted_.begin(), sorted_.end(), [&](size_t a, size_t b) {
    return passes_[a].desc.phase < passes_[b].desc.phase;
  });
  for (ResourceDesc& r : resources_) r.usage = r.extra_usage;
  std::vector<bool> written(resources_.size(), false);
  for (size_t i : sorted_) {
    const PassDesc& p = passes_[i].desc;
    // In the pass's own order: a read needs a write before it (an earlier pass, or an
    // earlier access of this pass, as a blur reading what the bright pass wrote).
    for (const Access& a : p.accesses) {
      const auto l = find(a.resource);
      ILLUM_CHECK(l.has_value(), "pass '{}' uses '{}', which is not declared", p.name, a.resource);
      ResourceDesc& r = resources_[l->resource];
      const bool image = r.kind == ResourceDesc::Kind::kImage;
      use_state(a.uses, a.shaders, image, image && is_depth_format(r.format));  // checks
      r.usage |= usage_of(a.uses, image);
      ILLUM_CHECK(!(l->previous && writes(a.uses)), "pass '{}' writes '{}'", p.name, a.resource);
      if ((a.uses & kReadUses) && !l->previous && !r.external && !written[l->resource])
        throw InternalError(fmt::format("pass '{}' reads '{}', which no pass before it writes",
                                        p.name, a.resource));
      if (writes(a.uses)) written[l->resource] = true;
    }
  }
  for (const auto& [resource, hint] : required_) {
    const auto l = find(resource);
    if (!l || !written[l->resource])
      throw Error(fmt::format("nothing in this frame writes '{}': {}", resource, hint));
  }
  order_.clear();
  for (size_t i : sorted_) order_.push_back(passes_[i].desc.name);
  compiled_ = true;
}

void FrameGraph::inherit(const FrameGraph& previous,
                         const std::function<bool(const std::string&)>& kept) {
  for (Node& n : passes_)
    for (const Node& old : previous.passes_)
      if (old.desc.name == n.desc.name && old.desc.technique == n.desc.technique &&
          kept(n.desc.technique) && old.dirty.size() == n.dirty.size()) {
        n.dirty = old.dirty;
        n.cursor = old.cursor;
      }
  for (size_t i = 0; i < resources_.size(); ++i)
    for (size_t j = 0; j < previous.resources_.size(); ++j)
      if (previous.resources_[j].name == resources_[i].name &&
          previous.resources_[j].same_shape(resources_[i])) {
        for (size_t c = 0; c < copies_[i].size(); ++c) {
          copies_[i][c].states = previous.copies_[j][c].states;
          copies_[i][c].written_frame = previous.copies_[j][c].written_frame;
        }
        versions_[i] = previous.versions_[j];
      }
}

void FrameGraph::notify(Changes changes, const std::string& technique) {
  for (Node& n : passes_) {
    Changes hit = n.desc.schedule.invalidated_by & changes;
    if (n.desc.technique != technique) hit &= ~Changes{kParametersChanged};
    if (hit) std::fill(n.dirty.begin(), n.dirty.end(), true);
  }
}

void FrameGraph::invalidate_technique(const std::string& technique) {
  for (Node& n : passes_)
    if (n.desc.technique == technique) std::fill(n.dirty.begin(), n.dirty.end(), true);
}

void FrameGraph::invalidate_all() {
  for (Node& n : passes_) std::fill(n.dirty.begin(), n.dirty.end(), true);
}

void FrameGraph::invalidate_writers(const std::string& resource) {
  for (Node& n : passes_)
    for (const Access& a : n.desc.accesses)
      if (a.resource == resource && writes(a.uses)) std::fill(n.dirty.begin(), n.dirty.end(), true);
}

std::vector<int> FrameGraph::due_items(Node& node, uint64_t frame) {
  const Schedule& s = node.desc.schedule;
  const int n = s.items;
  std::vector<int> due;
  const bool all_dirty =
      std::all_of(node.dirty.begin(), node.dirty.end(), [](bool d) { return d; });
  bool all = all_dirty;
  switch (s.kind) {
    case Schedule::Kind::kEveryFrame:
      all = true;
      break;
    case Schedule::Kind::kEveryN:
      all = all || (frame + static_cast<uint64_t>(s.phase)) % static_cast<uint64_t>(s.period) == 0;
      break;
    case Schedule::Kind::kRoundRobin:
      if (!all) {
        std::vector<bool> pick = node.dirty;
        for (int k = 0; k < std::min(s.per_frame, n); ++k)
          pick[static_cast<size_t>((node.cursor + k) % n)] = true;
        node.cursor = (node.cursor + s.per_frame) % n;
        for (int i = 0; i < n; ++i)
          if (pick[static_cast<size_t>(i)]) due.push_back(i);
      }
      break;
    case Schedule::Kind::kOnChange:
      if (!all)
        for (int i = 0; i < n; ++i)
          if (node.dirty[static_cast<size_t>(i)]) due.push_back(i);
      break;
  }
  if (all) {
    due.resize(static_cast<size_t>(n));
    std::iota(due.begin(), due.end(), 0);
  }
  for (int i : due) node.dirty[static_cast<size_t>(i)] = false;
  return due;
}

namespace {
bool same_sync(const Barrier& a, const Barrier& b) {
  return a.old_layout == b.old_layout && a.new_layout == b.new_layout &&
         a.src_stages == b.src_stages && a.dst_stages == b.dst_stages &&
         a.src_access == b.src_access && a.dst_access == b.dst_access;
}
}  // namespace

void FrameGraph::apply(const Access& access, uint64_t frame, VkCommandBuffer cmd) {
  const auto l = find(access.resource);
  ILLUM_CHECK(l.has_value(), "no resource '{}'", access.resource);
  const ResourceDesc& r = resources_[l->resource];
  const bool image = r.kind == ResourceDesc::Kind::kImage;
  const int index = copy_index(access.resource);
  Copy& copy = copies_[l->resource][static_cast<size_t>(index)];
  const uint32_t levels = levels_of(r, copy), layers = layers_of(r);
  if (copy.states.size() != static_cast<size_t>(levels) * layers)
    copy.states.assign(static_cast<size_t>(levels) * layers, ResourceState{});
  const uint32_t mip0 = access.base_mip, layer0 = access.base_layer;
  const uint32_t mips =
      access.mip_count == kAllSubresources ? levels - std::min(mip0, levels) : access.mip_count;
  const uint32_t layer_count = access.layer_count == kAllSubresources
                                   ? layers - std::min(layer0, layers)
                                   : access.layer_count;
  ILLUM_CHECK(
      mips >= 1 && mip0 + mips <= levels && layer_count >= 1 && layer0 + layer_count <= layers,
      "'{}': mips {}+{} and layers {}+{} of {} and {}", access.resource, mip0, mips, layer0,
      layer_count, levels, layers);
  const UseState next =
      use_state(access.uses, access.shaders, image, image && is_depth_format(r.format));
  // One barrier per subresource that needs one, merged into runs of layers, then of levels,
  // with the same synchronization: a uniform image still takes a single barrier.
  std::vector<Barrier> merged;
  for (uint32_t m = mip0; m < mip0 + mips; ++m)
    for (uint32_t k = layer0; k < layer0 + layer_count; ++k) {
      ResourceState& state = copy.states[static_cast<size_t>(m) * layers + k];
      if (copy.image && copy.image->layout(m, k) != state.layout) {
        // Someone else (an upload, a readback) moved the image: start from its own record.
        state = {copy.image->layout(m, k), copy.image->stage(), copy.image->access()};
      }
      std::optional<Barrier> b = barrier_for(&state, next, image);
      if (!b) continue;
      b->base_mip = m;
      b->base_layer = k;
      Barrier* last = merged.empty() ? nullptr : &merged.back();
      if (last && same_sync(*last, *b) && last->base_mip == m && last->mip_count == 1 &&
          last->base_layer + last->layer_count == k)
        ++last->layer_count;
      else
        merged.push_back(std::move(*b));
    }
  std::vector<Barrier> runs;
  for (Barrier& b : merged) {
    auto above = std::find_if(runs.begin(), runs.end(), [&](const Barrier& o) {
      return same_sync(o, b) && o.base_mip + o.mip_count == b.base_mip &&
             o.base_layer == b.base_layer && o.layer_count == b.layer_count;
    });
    if (above != runs.end())
      ++above->mip_count;
    else
      runs.push_back(std::move(b));
  }
  if (writes(access.uses)) copy.written_frame = static_cast<int64_t>(frame);
  for (Barrier& b : runs) {
    b.resource = r.history ? fmt::format("{}[{}]", r.name, index) : r.name;
    if (cmd != VK_NULL_HANDLE) {
      if (copy.image) {
        const VkImageSubresourceRange range{copy.image->aspect(), b.base_mip, b.mip_count,
                                            b.base_layer, b.layer_count};
        gpu::image_barrier(cmd, copy.image->handle(), range, b.old_layout, b.new_layout,
                           b.src_stages, b.src_access, b.dst_stages, b.dst_access);
        copy.image->assume_state(range, b.new_layout, b.dst_stages, b.dst_access);
      } else {
        ILLUM_CHECK(!image || r.external, "image '{}' has no GPU image bound", r.name);
        if (!image)
          gpu::memory_barrier(cmd, b.src_stages, b.src_access, b.dst_stages, b.dst_access);
      }
    }
    barriers_.push_back(std::move(b));
  }
}

double FrameGraph::bytes_of(const PassDesc& pass) {
  double bytes = 0.0;
  for (const Access& a : pass.accesses) {
    const auto l = find(a.resource);
    if (!l) continue;
    const Copy& c = copy_of(a.resource);
    double size = 0.0;
    if (c.image) {
      const gpu::ImageDesc& d = c.image->desc();
      // Depth + stencil: 4 + 1 bytes a texel as stored at least.
      const double texel = d.format == VK_FORMAT_D32_SFLOAT_S8_UINT  ? 5.0
                           : d.format == VK_FORMAT_D24_UNORM_S8_UINT ? 4.0
                                                                     : gpu::format_bytes(d.format);
      const uint32_t mip0 = std::min(a.base_mip, d.mips - 1);
      const uint32_t mip_end =
          a.mip_count == kAllSubresources ? d.mips : std::min(d.mips, mip0 + a.mip_count);
      const uint32_t layers = a.layer_count == kAllSubresources
                                  ? d.layers - std::min(a.base_layer, d.layers - 1)
                                  : a.layer_count;
      for (uint32_t m = mip0; m < mip_end; ++m)
        size += static_cast<double>(std::max(1u, d.width >> m)) * std::max(1u, d.height >> m) *
                std::max(1u, d.depth >> m) * layers * texel;
    } else if (c.buffer) {
      size = static_cast<double>(c.buffer->size());
    }
    const int directions = ((a.uses & kReadUses) ? 1 : 0) + (writes(a.uses) ? 1 : 0);
    bytes += size * directions;
  }
  return bytes;
}

uint32_t FrameGraph::timer_scopes() const {
  uint32_t n = 0;
  for (const Node& p : passes_)
    if (!p.desc.cpu) n += 1 + static_cast<uint32_t>(std::max(p.desc.nested_scopes, 0));
  return n;
}

std::vector<std::string> FrameGraph::execute(VkCommandBuffer cmd, uint64_t frame,
                                             gpu::GpuTimer* timer) {
  if (!compiled_) compile();
  current_frame_ = frame;
  barriers_.clear();
  cpu_times_.clear();
  std::vector<std::string> ran;
  gpu::GpuTimer* gpu_timer = cmd != VK_NULL_HANDLE ? timer : nullptr;
  std::string open_label;
  uint32_t open_scope = 0;
  auto close = [&] {
    if (!open_label.empty() && gpu_timer) gpu_timer->end(cmd, open_scope);
    open_label.clear();
  };
  for (size_t i : sorted_) {
    Node& node = passes_[i];
    std::vector<int> items = due_items(node, frame);
    if (items.empty()) continue;
    PassContext ctx;
    ctx.graph_ = this;
    ctx.pass_ = &node.desc;
    ctx.cmd_ = cmd;
    ctx.frame_ = frame;
    ctx.timer_ = gpu_timer;
    ctx.open_scope_ = &open_scope;
    ctx.items_ = std::move(items);
    swap_written_history(node.desc, frame);
    if (node.desc.cpu) {
      close();
      const auto t0 = std::chrono::steady_clock::now();
      if (node.desc.record) node.desc.record(ctx);
      const auto t1 = std::chrono::steady_clock::now();
      cpu_times_.push_back({"cpu:" + node.desc.timer,
                            std::chrono::duration<double, std::milli>(t1 - t0).count(), 0});
      ran.push_back(node.desc.name);
      continue;
    }
    if (open_label != node.desc.timer) {
      close();
      open_label = node.desc.timer;
      if (gpu_timer) open_scope = gpu_timer->begin(cmd, open_label);
    }
    // Compute work (no attachments): the bytes of what it declares, for the bounds.
    constexpr Uses kAttachments = kColorAttachment | kDepthAttachment | kDepthReadOnly;
    const bool raster = std::any_of(node.desc.accesses.begin(), node.desc.accesses.end(),
                                    [](const Access& a) { return (a.uses & kAttachments) != 0; });
    if (gpu_timer && !raster) gpu_timer->note_bytes(bytes_of(node.desc));
    // The first declared access of each resource; the pass applies later ones with use().
    std::vector<std::string> done;
    for (const Access& a : node.desc.accesses) {
      if (std::find(done.begin(), done.end(), a.resource) != done.end()) continue;
      done.push_back(a.resource);
      apply(a, frame, cmd);
    }
    if (node.desc.record) node.desc.record(ctx);
    ran.push_back(node.desc.name);
  }
  close();
  return ran;
}

}  // namespace illum::realtime
