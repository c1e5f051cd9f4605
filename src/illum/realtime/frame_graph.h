// The frame graph: what the real-time techniques declare and the renderer runs.
//
// * Resources have a name, a size (absolute, or the frame's size divided by an integer;
//   images may be 3-D volumes and carry mip levels and layers), a format and a usage; the usage is
//   the union of what the passes' declared accesses need (plus `extra_usage`, e.g. transfer-source
//   for readback). A resource may keep a second copy of itself (`history`: adaptation, trails,
//   temporal blending): "NAME" is the copy its writer wrote last and "NAME.previous" the one
//   written before. The copies swap when the first pass writing NAME runs in a frame, not by frame
//   parity, so a writer scheduled every N frames leaves its readers the newest copy in between. A
//   writer reads its own last result through NAME.previous (NAME is the copy it is about to
//   overwrite). Descriptor sets follow with one set per copy, picked by PassContext::copy().
//   External resources are owned by a technique; the graph only tracks their synchronization state.
// * Passes run in phase order (shadows, geometry, screen space, lighting, post, display),
//   in declaration order within a phase; several passes may write one resource (the
//   G-buffer pass writes the HDR target, the lighting adds to it) and their order is that
//   order. compile() checks that every read has an earlier writer.
// * Barriers and layout transitions are derived from the accesses: before each pass (and at
//   each PassContext::use() inside one) the graph compares the resource's state with what
//   the access needs; a layout change, a write after any access, or a read by stages the
//   last write was not yet made visible to gets one barrier. Read after read gets none.
// * Schedules: every frame; every N frames with a phase; round-robin (k of n items a frame,
//   e.g. cube faces); on change. Each also names the changes (lights, geometry, camera,
//   the owning technique's parameters) that make all its items due at the next frame.
//   Every pass runs in full on the first frame after it is added.
// * Timing: each pass runs inside a GPU timer scope named by its `timer` label (passes in
//   a row with one label share one scope); a pass may open nested scopes (per light).
//   CPU passes are timed on the CPU and reported as "cpu:NAME".
// * Work: each scope also records what bounds it (illum-bench raster): a raster pass notes
//   its fills (PassContext::fill, or counted with occlusion queries in a counting frame:
//   SceneDrawer::render_counted) and triangles; a pass without attachments is compute
//   work, and the graph notes the bytes of the images and buffers it declares (each read
//   once and written once).
//
// Nothing here needs a GPU: with VK_NULL_HANDLE as the command buffer and no bound images
// the graph runs its schedules and derives barriers as data (tests/realtime/frame_graph_test).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "illum/gpu/gpu_timer.h"

namespace illum::gpu {
class GpuImage;
class Buffer;
}  // namespace illum::gpu

namespace illum::realtime {

// What a pass does with a resource; bits combine within one access (the depth buffer tested
// read-only while a shader samples it).
enum Use : uint32_t {
  kSampled = 1u << 0,          // texture fetches
  kStorageRead = 1u << 1,      // storage image / buffer loads
  kStorageWrite = 1u << 2,     // storage image / buffer stores
  kColorAttachment = 1u << 3,  // rendered to (loaded, blended or cleared)
  kDepthAttachment = 1u << 4,  // depth (and stencil) tested and written
  kDepthReadOnly = 1u << 5,    // depth tested, not written; the stencil written
  kTransferSrc = 1u << 6,
  kTransferDst = 1u << 7,
  kVertexInput = 1u << 8,   // vertex buffer
  kIndirectArgs = 1u << 9,  // indirect draw / dispatch arguments
};
using Uses = uint32_t;
bool writes(Uses uses);

inline constexpr VkPipelineStageFlags2 kFragmentShader = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
inline constexpr VkPipelineStageFlags2 kComputeShader = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
inline constexpr VkPipelineStageFlags2 kVertexShader = VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT;

inline constexpr uint32_t kAllSubresources = ~0u;

struct Access {
  std::string resource;
  Uses uses = 0;
  // The shader stages of sampled and storage uses.
  VkPipelineStageFlags2 shaders = kFragmentShader | kComputeShader;
  // Images: the mip levels and layers touched (a 3-D image has one layer); all by default.
  // Each subresource keeps its own state, so a pass may sample level m − 1 while it writes
  // level m (a pyramid) and the graph puts one barrier on each level.
  uint32_t base_mip = 0, mip_count = kAllSubresources;
  uint32_t base_layer = 0, layer_count = kAllSubresources;
  // A read the pass makes only where some technique declares the resource (tone mapping
  // adds bloom when bloom is on): compile() drops it otherwise, and the pass learns which
  // through PassContext::reads / FrameGraph::reads instead of probing names.
  bool optional = false;

  Access mips(uint32_t base, uint32_t count = 1) const;
  Access if_produced() const;
  Access layers(uint32_t base, uint32_t count = 1) const;
  bool same_range(const Access& other) const;
};

// Adds `access` to `accesses`, merged into the access of the same resource and range if
// there is one (one pass testing the depth read-only and sampling it).
void merge_access(std::vector<Access>* accesses, const Access& access);

// A resource's synchronization state: its layout (images) and the stages and accesses of
// its uses since the last barrier (the source of the next one).
struct ResourceState {
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkPipelineStageFlags2 stages = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 access = VK_ACCESS_2_NONE;
};

// What one access needs: layout, stages, accesses.
struct UseState {
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;  // buffers: UNDEFINED
  VkPipelineStageFlags2 stages = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 access = VK_ACCESS_2_NONE;
  bool write = false;
};
// Throws InternalError for uses no single layout serves (sampled and storage at once).
UseState use_state(Uses uses, VkPipelineStageFlags2 shaders, bool image, bool depth_format);

struct Barrier {
  std::string resource;  // the physical name ("taa", "taa.previous" resolve to copies)
  // The subresources it covers (buffers: 0, 1, 0, 1).
  uint32_t base_mip = 0, mip_count = 1, base_layer = 0, layer_count = 1;
  VkImageLayout old_layout = VK_IMAGE_LAYOUT_UNDEFINED, new_layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkPipelineStageFlags2 src_stages = VK_PIPELINE_STAGE_2_NONE,
                        dst_stages = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 src_access = VK_ACCESS_2_NONE, dst_access = VK_ACCESS_2_NONE;
};
// The barrier a resource in `*state` needs before `next`, updating `*state`: one for a
// layout change, for a write, after a write, and for a read by stages or accesses the last
// barrier did not cover; none for a read after reads it covered (the reads then add to the
// state, so a later write waits for all of them).
std::optional<Barrier> barrier_for(ResourceState* state, const UseState& next, bool image);

enum class Phase : int { kShadows, kGeometry, kScreenSpace, kLighting, kPost, kDisplay };

// What changed since the last frame; schedules name the changes that invalidate them.
enum Change : uint32_t {
  kLightsChanged = 1u << 0,      // positions, colours, ranges (Renderer::update_lights)
  kGeometryChanged = 1u << 1,    // an object or instance moved or changed
  kCameraChanged = 1u << 2,      // the view or projection
  kParametersChanged = 1u << 3,  // a per-frame parameter of the pass's own technique
};
using Changes = uint32_t;

struct Schedule {
  enum class Kind { kEveryFrame, kEveryN, kRoundRobin, kOnChange };
  Kind kind = Kind::kEveryFrame;
  int period = 1;  // kEveryN: frames where (frame + phase) % period == 0
  int phase = 0;
  int items = 1;  // kRoundRobin: `per_frame` of `items` each frame, in turn
  int per_frame = 1;
  Changes invalidated_by = 0;  // changes after which every item runs at the next frame

  static Schedule every_frame() { return {}; }
  static Schedule every_n(int period, int phase = 0, Changes changes = 0);
  static Schedule round_robin(int items, int per_frame, Changes changes = 0);
  static Schedule on_change(Changes changes, int items = 1);
};

struct ResourceDesc {
  enum class Kind { kImage, kBuffer };
  std::string name;
  Kind kind = Kind::kImage;
  // Images: absolute size, or with frame_divisor > 0 the frame's size divided by it
  // (integer division, at least 1).
  uint32_t width = 1, height = 1;
  uint32_t frame_divisor = 0;
  uint32_t depth = 1;  // > 1: a 3-D image (one layer), sampled trilinearly as sampler3D
  uint32_t mips = 1;   // 0: the full chain of the size the image gets
  VkFormat format = VK_FORMAT_UNDEFINED;
  uint32_t layers = 1;
  bool cube = false, cube_array = false, array = false;
  // Buffers: size in bytes.
  uint64_t bytes = 0;
  uint32_t extra_usage = 0;  // VkImageUsageFlags / VkBufferUsageFlags beyond the accesses'
  bool history = false;      // also keep the previous frame's copy, "NAME.previous"
  bool external = false;     // owned by a technique: only its state is tracked
  // Derived by compile(): the union of the accesses' usage and extra_usage.
  uint32_t usage = 0;

  bool same_shape(const ResourceDesc& other) const;  // everything but the name
};
bool is_depth_format(VkFormat format);

class FrameGraph;
struct PassDesc;

// Handed to a pass while it records.
class PassContext {
 public:
  VkCommandBuffer cmd() const { return cmd_; }
  uint64_t frame() const { return frame_; }
  const std::string& label() const;  // the pass's timer scope label
  // Round-robin and on-change passes: the items due this frame (all, for other schedules).
  const std::vector<int>& items() const { return items_; }
  // A further access inside the pass (a dispatch reading what the previous one wrote, the
  // next light's rendering scope): the barrier is derived as at the pass's start.
  void use(const std::string& resource, Uses uses,
           VkPipelineStageFlags2 shaders = kFragmentShader | kComputeShader);
  // The same for part of an image (Access::mips, Access::layers).
  void use(const Access& access);
  // A nested GPU timer scope, closed when the returned object goes out of scope.
  class Scope {
   public:
    Scope(gpu::GpuTimer* timer, VkCommandBuffer cmd, const std::string& name);
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    gpu::GpuTimer* timer_;
    VkCommandBuffer cmd_;
    uint32_t scope_ = 0;
  };
  Scope scope(const std::string& name) { return Scope(timer_, cmd_, name); }
  // A scope beside the pass's rather than inside it — compute work a raster pass records in
  // its middle (occlusion culling between its two halves) — so the pass's time and bound
  // leave it out: ends the pass's scope, opens `name` at the same depth, and on destruction
  // reopens the pass's scope under its label (the renderer sums scopes of one name). Each
  // costs two scopes: count them in PassDesc::nested_scopes.
  class Aside {
   public:
    Aside(PassContext& pass, const std::string& name);
    ~Aside();
    Aside(const Aside&) = delete;
    Aside& operator=(const Aside&) = delete;

   private:
    PassContext& pass_;
    uint32_t scope_ = 0;
  };
  Aside aside(const std::string& name) { return Aside(*this, name); }
  // The raster work of the innermost open scope: `count` fills of the whole of `fill`'s
  // targets (a full-screen trivial pass into them is the bound of each).
  void fill(const gpu::RasterFill& fill, double count = 1.0);
  // Counting frames (Renderer::measure_work): the samples of the draws recorded between the
  // two calls, inside a rendering scope, become fills of `per_sample` (their overdraw).
  // With `minus` (an earlier query of this frame) its samples are subtracted.
  bool counting() const;
  uint32_t begin_count();
  void end_count(uint32_t query, const gpu::RasterFill& per_sample, int minus = -1);
  // Whether fragments that pass a draw's tests may be counted apart (not on a software
  // device: lavapipe crashes on occlusion queries around depth-tested draws in frames that
  // also build shadow volumes on the GPU).
  bool counts_tested() const;
  // Triangles the innermost open scope submitted (its geometry bound), and its clusters.
  void triangles(double count);
  void clusters(double count);
  // Bytes of compute work the innermost open scope reads and writes (its memory bound).
  void bytes(double count);
  // Triangles and clusters counted on the GPU (gpu::GpuTimer::note_drawn).
  void drawn(VkBuffer counter, VkDeviceSize offset);
  // Counting frames: of the draws recorded between the two calls, the triangles that reach
  // rasterization (gpu::PassTime::rasterized; nothing where the device cannot count them).
  uint32_t begin_rasterized();
  void end_rasterized(uint32_t query);
  // Counting frames on a device that counts quads (gpu::GpuTimer::begin_quads): outside any
  // rendering scope, around the draws that add to `counter`.
  bool counts_quads() const;
  void begin_quads(VkBuffer counter);
  void end_quads(VkBuffer counter);
  // Whether the pass reads `resource` (an optional read whose resource is declared).
  bool reads(const std::string& resource) const;
  // Whether "NAME.previous" holds a frame (false until the writer has run twice).
  bool has_history(const std::string& resource) const;
  // What "NAME" or "NAME.previous" resolves to at this point of the frame: the copy index
  // (0 without history; a technique with one descriptor set per copy picks by it) and the
  // GPU object bound to that copy (null where none is bound).
  int copy(const std::string& name) const;
  gpu::GpuImage* image(const std::string& name) const;
  gpu::Buffer* buffer(const std::string& name) const;

 private:
  friend class FrameGraph;
  FrameGraph* graph_ = nullptr;
  const PassDesc* pass_ = nullptr;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  uint64_t frame_ = 0;
  gpu::GpuTimer* timer_ = nullptr;
  uint32_t* open_scope_ = nullptr;  // the graph's open scope: Aside reopens it
  std::vector<int> items_;
};

struct PassDesc {
  std::string name;
  std::string technique;  // the owner: its parameter changes invalidate the pass
  Phase phase = Phase::kGeometry;
  // Every access of the pass, in the order it makes them: before the pass the graph applies
  // the first access of each resource, the pass applies later ones with PassContext::use().
  std::vector<Access> accesses;
  Schedule schedule;
  std::string timer;      // timer scope label; empty: the pass name
  int nested_scopes = 0;  // upper bound of the scopes the pass opens inside its own
  bool cpu = false;       // CPU work: no barriers, timed on the CPU as "cpu:NAME"
  std::function<void(PassContext&)> record;
};

class FrameGraph {
 public:
  void add_resource(ResourceDesc desc);
  void add_pass(PassDesc pass);
  // A resource the frame must produce (the display image): compile() throws Error naming
  // `hint` when no pass writes it.
  void require(const std::string& resource, const std::string& hint);
  // Orders the passes, drops the optional reads of undeclared resources and derives each
  // resource's usage. Throws InternalError when a pass reads a resource nothing writes
  // before it (or declares an unknown one).
  void compile();
  // After compile(): whether pass `pass` accesses `resource` (false for a dropped optional
  // read or an unknown pass).
  bool reads(const std::string& pass, const std::string& resource) const;

  // Changes since the last frame: the passes invalidated by them run in full next frame.
  // kParametersChanged concerns the passes of `technique` only.
  void notify(Changes changes, const std::string& technique = "");
  // All passes of `technique`, or every pass, run in full at the next frame.
  void invalidate_technique(const std::string& technique);
  void invalidate_all();
  // After a resource was re-created (contents lost): the passes that write it run in full.
  void invalidate_writers(const std::string& resource);

  // The physical copies of a resource (2 with history), to bind GPU objects to.
  int copies(const std::string& resource) const;
  void bind_image(const std::string& resource, int copy, gpu::GpuImage* image);
  void bind_buffer(const std::string& resource, int copy, gpu::Buffer* buffer);
  // The copy "NAME" (or "NAME.previous") names now (see history above).
  int copy_index(const std::string& name) const;

  // Records the passes due at `frame` with their barriers and timer scopes; returns the
  // names of the passes that ran. `timer` may be null (no timing); `cmd` may be
  // VK_NULL_HANDLE (nothing recorded: schedules and barriers as data).
  std::vector<std::string> execute(VkCommandBuffer cmd, uint64_t frame, gpu::GpuTimer* timer);
  // Timer scopes one frame can open (passes and their nested scopes).
  uint32_t timer_scopes() const;
  // CPU passes' milliseconds in the last execute(), as "cpu:NAME".
  const std::vector<gpu::PassTime>& cpu_times() const { return cpu_times_; }
  // The barriers the last execute() derived, in order.
  const std::vector<Barrier>& barriers() const { return barriers_; }

  const std::vector<std::string>& order() const { return order_; }
  bool has_pass(const std::string& name) const;
  bool has_resource(const std::string& name) const;
  const ResourceDesc& resource(const std::string& name) const;
  const std::vector<ResourceDesc>& resources() const { return resources_; }
  const PassDesc& pass(const std::string& name) const;

  // Carries over from the graph this one replaces: the schedule state (dirty items,
  // round-robin cursor) of passes whose technique `kept` says was kept, and the state and
  // history of resources of the same name and shape.
  void inherit(const FrameGraph& previous, const std::function<bool(const std::string&)>& kept);

 private:
  friend class PassContext;
  struct Copy {
    std::vector<ResourceState> states;  // per subresource (mip * layers + layer)
    gpu::GpuImage* image = nullptr;
    gpu::Buffer* buffer = nullptr;
    int64_t written_frame = -1;
  };
  struct Node {
    PassDesc desc;
    std::vector<bool> dirty;  // per item
    int cursor = 0;           // round-robin: next item
  };
  struct Logical {
    size_t resource;  // index into resources_
    bool previous;    // "NAME.previous"
  };
  // Which copy of a history resource is "NAME", and the frame it last swapped in.
  struct Versions {
    int current = 0;
    int64_t swapped_frame = -1;
  };
  std::optional<Logical> find(const std::string& name) const;
  Copy& copy_of(const std::string& name);
  const Copy& copy_of(const std::string& name) const;
  // Before a pass runs: the history resources it writes swap, once a frame.
  void swap_written_history(const PassDesc& pass, uint64_t frame);
  // Bytes of the resources `pass` declares: each read once, each written once.
  double bytes_of(const PassDesc& pass);
  void apply(const Access& access, uint64_t frame, VkCommandBuffer cmd);
  // Mip levels and layers of `resource`'s copy as bound (as declared without a GPU image).
  uint32_t levels_of(const ResourceDesc& resource, const Copy& copy) const;
  uint32_t layers_of(const ResourceDesc& resource) const;
  std::vector<int> due_items(Node& node, uint64_t frame);

  std::vector<ResourceDesc> resources_;
  std::vector<std::vector<Copy>> copies_;
  std::vector<Versions> versions_;  // per resource
  std::vector<Node> passes_;
  std::vector<std::pair<std::string, std::string>> required_;
  std::vector<size_t> sorted_;
  std::vector<std::string> order_;
  bool compiled_ = false;
  std::vector<Barrier> barriers_;
  std::vector<gpu::PassTime> cpu_times_;
  uint64_t current_frame_ = 0;
};

}  // namespace illum::realtime
