// The lighting-inputs set (set 4 of the shading layout): the one open slot through which any
// technique adds light or occlusion to the ambient term of every frame pipeline (forward,
// deferred, visibility). Each input is registered once (lighting_input_registry(), the list in
// lighting_inputs.cpp) with its name, the terms it fills, its base binding
// (lighting_inputs_bindings.h, shared with GLSL) and its descriptors; its shader module
// shaders/inputs/<name>.glsl declares those bindings and one input_<name>() that
// gather_lighting_inputs() (shaders/lighting_inputs.glsl) calls. The set's layout is the union
// of the inputs' ranges.
//
// A technique contributes by returning LightingContribution values from
// Technique::lighting_inputs(): it writes its descriptors into the core's set and names the
// frame-graph resources the shading passes then sample (so the graph orders and barriers
// them). An input no active technique contributes gets neutral descriptors (FrameGlobals'
// dummies) and its active flag 0, so its module returns at once.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "illum/gpu/buffer.h"
#include "illum/gpu/descriptors.h"
#include "illum/realtime/frame_graph.h"
#include "illum/realtime/lighting_inputs_bindings.h"

namespace illum::realtime {

class FrameGlobals;

// What an input adds to LightingTerms (shaders/lighting_inputs.glsl), as bits.
enum LightingTerm : uint32_t {
  kTermIndirect = 1u << 0,    // indirect irradiance × albedo (replaces albedo · ambient)
  kTermVisibility = 1u << 1,  // that indirect already holds the surface's visibility (PRT)
  kTermOcclusion = 1u << 2,   // an occlusion factor (1 = open); occlusions combine by minimum
  kTermSpecular = 1u << 3,    // indirect specular radiance
  kTermExtra = 1u << 4,       // any other radiance added to the ambient term
};

// One binding of an input's range: its descriptor type and, for images, the view type its
// neutral image must have.
struct InputBinding {
  VkDescriptorType type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
  VkImageViewType view = VK_IMAGE_VIEW_TYPE_2D;  // images only
};

struct LightingInputDecl {
  std::string name;  // shaders/inputs/<name>.glsl, input_<name>()
  uint32_t terms = 0;
  int index = 0;  // its active flag (lighting_inputs_bindings.h)
  int base = 0;   // its first binding
  std::vector<InputBinding> bindings;
  // Sampled at the pixel from an image this frame's screen-space phase writes (SSAO): the
  // deferred G-buffer pass, which runs before that phase, leaves it to a later pass.
  bool screen_space = false;
  std::string summary;
};

// Every input, in the order gather_lighting_inputs() calls them: an indirect term comes from
// the first active input that gives one for the surface (a probed dynamic object takes the
// probes even where a light-map is bound).
const std::vector<LightingInputDecl>& lighting_input_registry();
const LightingInputDecl* find_lighting_input(const std::string& name);  // null if none
// The set's layout: the union of the inputs' ranges and the state block.
std::vector<gpu::DescriptorBinding> lighting_inputs_layout();
// A zeroed block for neutral uniform and storage bindings (the largest input block fits).
gpu::Buffer make_lighting_inputs_zeros(gpu::Context& context);
// Every binding of `set` neutral, the state block `zeros` (no input active).
void write_neutral_lighting_inputs(gpu::DescriptorWriter& writer, VkDescriptorSet set,
                                   const FrameGlobals& globals, VkBuffer zeros);

// A technique's contribution to one input.
struct LightingContribution {
  std::string input;  // a registered input's name
  // Writes the input's bindings (base .. base + bindings − 1) of `set`; called whenever the
  // frame's resources are (re)bound, after the technique's own bind().
  std::function<void(gpu::DescriptorWriter& writer, VkDescriptorSet set, uint32_t base)> write;
  // Frame-graph resources sampled through those bindings.
  std::vector<std::string> reads;
};

// Which inputs' resources a pass reads.
enum class InputReads { kAll, kSurface, kScreenSpace };

// The core's set 4: the state block, every input's bindings, neutral where no technique
// contributes. Owned by the renderer.
class LightingInputs {
 public:
  LightingInputs(gpu::Context& context, const FrameGlobals& globals);
  ~LightingInputs();
  LightingInputs(const LightingInputs&) = delete;
  LightingInputs& operator=(const LightingInputs&) = delete;

  // Rewrites the set from the active techniques' contributions (each input at most once:
  // a second contribution to one input is an error naming it).
  void bind(const std::vector<LightingContribution>& contributions);
  // The contributions' reads (taken when the frame is assembled, before bind()).
  void set_reads(const std::vector<LightingContribution>& contributions);

  VkDescriptorSet set() const;
  bool active(const std::string& input) const;
  // Whether an active input is screen-space (the deferred pipeline then adds its late pass).
  bool any_screen_space() const;
  std::vector<Access> reads(VkPipelineStageFlags2 shaders, InputReads which) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace illum::realtime
