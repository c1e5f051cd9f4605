// Per-pass GPU time from timestamp queries: begin(cmd, name) writes a timestamp, end() the
// matching one; resolve() reads them back (after the frame's fence) as milliseconds. Scopes
// nest (a pass's per-light steps inside the pass): each PassTime says how deep it sits, so
// totals add up depth 0 only. reserve() grows the query pool before a frame that needs
// more scopes than it holds.
//
// A scope also carries the work it did, so its time can be judged against the device's
// bounds (illum-bench raster): raster fills (a target configuration, what each fragment
// does, and how many times the target's area), triangles, and for compute work the bytes
// of what it declares. In a counting frame (set_counting), draws between begin_count() and
// end_count() are counted by a precise occlusion query and become fills of the scope
// (fragments that passed a pass's tests, the rejected rest, stencil volumes' samples).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

#include "illum/gpu/buffer.h"
#include "illum/gpu/context.h"

namespace illum::gpu {

// The attachments a raster scope fills and how: what a trivial full-screen pass must write
// to be its bound (illum-bench raster draws exactly this, at this size).
struct RasterFill {
  // What each fragment does. kWrite: depth tested, passes, written; kTest: tested, passes,
  // not written; kReject: tested and rejected (overdraw behind what is drawn); kStencil: the
  // stencil written, depth untested; kStencilTest: the stencil tested only; kStencilZFail:
  // depth tested and failing, the stencil written on the failure (z-fail shadow volumes).
  enum class Depth { kNone, kWrite, kTest, kStencil, kStencilTest, kReject, kStencilZFail };
  uint32_t width = 0, height = 0;
  std::vector<VkFormat> colors;  // written (added with blending when `blend`)
  VkFormat depth_format = VK_FORMAT_UNDEFINED;
  Depth depth = Depth::kNone;
  bool blend = false;
  // Bit i: colour i starts undefined instead of cleared (a target the pass writes wherever
  // anything later reads it). Clearing a 1080p target costs 0.15–0.26 ms on the H200.
  uint32_t uncleared = 0;

  bool operator==(const RasterFill& other) const = default;
  // "1920x1080 rgba16f+d32s8 test blend": the configuration as one line.
  std::string key() const;
};

struct PassTime {
  std::string name;
  double ms = 0.0;
  int depth = 0;  // 0: a pass; 1: a step inside the enclosing depth-0 scope; ...
  // The work recorded inside this scope itself (nested scopes carry their own): raster
  // fills, one entry per rendering (a count of full-target equivalents: 1 for a view drawn
  // over its whole target, the scissored fraction, or the counted overdraw), and bytes of
  // compute work.
  std::vector<std::pair<RasterFill, double>> fills;
  double bytes = 0.0;
  double triangles = 0.0;  // triangles submitted (scene draws: every view's)
  // Of those, the ones that reached rasterization (out of clipping; counting frames on a
  // device with pipeline statistics; −1: not counted).
  double rasterized = -1.0;
  // Counted with them: the vertex shader invocations of those draws (what vertex reuse saves:
  // 3 a triangle without any, fewer where triangles share cached vertices).
  double vertices = -1.0;
  // Counting frames on a device that counts quads (Context::quad_counting): the 2×2 quads
  // its renderings shaded with at least one passing sample, and the passing samples the
  // same count saw (equal to the occlusion query's: the check that it replayed the pass);
  // −1: not counted.
  double quads = -1.0;
  double quad_samples = -1.0;
  // Clusters drawn (scene passes; with occlusion culling counted on the GPU, as are the
  // triangles then); −1: not noted.
  double clusters = -1.0;
};

class GpuTimer {
 public:
  GpuTimer(Context& context, uint32_t max_scopes = 64);
  ~GpuTimer();
  GpuTimer(const GpuTimer&) = delete;
  GpuTimer& operator=(const GpuTimer&) = delete;

  bool supported() const { return pool_ != VK_NULL_HANDLE; }
  uint32_t capacity() const { return max_scopes_; }
  // Makes room for `scopes` scopes a frame; call outside command recording (it may recreate
  // the query pool, which no pending work may use).
  void reserve(uint32_t scopes);
  void reset(VkCommandBuffer cmd);  // start of a frame
  uint32_t begin(VkCommandBuffer cmd, const std::string& name);
  void end(VkCommandBuffer cmd, uint32_t scope);
  std::vector<PassTime> resolve() const;  // call after the frame has completed

  // Work of the innermost open scope (ignored outside any scope).
  void note_fill(const RasterFill& fill, double count = 1.0);
  void note_bytes(double bytes);
  void note_triangles(double triangles);
  void note_clusters(double clusters);
  // Draws the CPU cannot count (predicated on GPU-written flags): `counter` holds two uint32 at
  // `offset`, {triangles, clusters} drawn; copied out here (outside any rendering), they add
  // to the innermost open scope's `triangles` and `clusters` after resolve().
  void note_drawn(VkCommandBuffer cmd, VkBuffer counter, VkDeviceSize offset);
  // Counting frames: from the next reset() on, begin_count/end_count record occlusion queries
  // (precise where the device has occlusionQueryPrecise); otherwise they record nothing.
  // `statistics`: also count rasterized triangles (begin_rasterized), where the device can.
  void set_counting(bool on, bool statistics = true);
  bool counting() const { return counting_ && occlusion_ != VK_NULL_HANDLE; }
  // Occlusion queries around depth-tested draws: not on a software device (lavapipe crashes
  // on them in frames that also build stencil shadow volumes on the GPU).
  bool counts_tested() const { return counting() && !context_->is_software(); }
  // Inside a rendering scope: the samples of the draws recorded until end_count() become
  // fills of `per_sample` (count = samples / (width × height)) for the innermost open scope;
  // with `minus` (an earlier query), its samples are subtracted (fragments rasterized minus
  // those that passed: the rejected ones).
  uint32_t begin_count(VkCommandBuffer cmd);
  void end_count(VkCommandBuffer cmd, uint32_t query, const RasterFill& per_sample, int minus = -1);
  // Inside a counting frame on a device with pipeline statistics: the primitives of the draws
  // recorded until end_rasterized() that leave clipping add to the innermost open scope's
  // `rasterized`, their vertex shader invocations to its `vertices` (otherwise both record
  // nothing).
  uint32_t begin_rasterized(VkCommandBuffer cmd);
  void end_rasterized(VkCommandBuffer cmd, uint32_t query);
  // Counting frames on a device that can count quads: outside any rendering, begin_quads()
  // zeroes `counter` (two uint32: quads, samples — shaders/quad_count.frag adds to it) and
  // end_quads() copies it out; after resolve() the counts add to the innermost open scope's
  // `quads` and `quad_samples`.
  bool counts_quads() const { return counting() && context_->quad_counting(); }
  void begin_quads(VkCommandBuffer cmd, VkBuffer counter);
  void end_quads(VkCommandBuffer cmd, VkBuffer counter);

 private:
  void create_pool();

  Context* context_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  uint32_t max_scopes_;
  std::vector<std::string> names_;
  std::vector<int> depths_;
  std::vector<uint32_t> stack_;                                    // open scopes, innermost last
  int open_ = 0;                                                   // scopes begun and not yet ended
  std::vector<std::vector<std::pair<RasterFill, double>>> fills_;  // per scope
  std::vector<double> bytes_;                                      // per scope
  std::vector<double> triangles_;                                  // per scope
  std::vector<double> clusters_;                                   // per scope
  Buffer drawn_readback_;               // {triangles, clusters} per note_drawn()
  std::vector<uint32_t> drawn_scopes_;  // per note_drawn()
  // Counting frames.
  bool counting_ = false;
  bool statistics_on_ = false;
  VkQueryPool occlusion_ = VK_NULL_HANDLE;
  uint32_t occlusion_capacity_ = 0;
  struct Count {
    uint32_t scope;
    RasterFill fill;
    int minus = -1;
  };
  std::vector<Count> counts_;
  VkQueryPool statistics_ = VK_NULL_HANDLE;
  std::vector<uint32_t> rasterized_scopes_;  // per statistics query
  Buffer quad_readback_;                     // {quads, samples} per counted rendering
  std::vector<uint32_t> quad_scopes_;        // per counted rendering
};

}  // namespace illum::gpu
