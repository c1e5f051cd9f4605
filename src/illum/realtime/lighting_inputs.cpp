#include "illum/realtime/lighting_inputs.h"

#include <algorithm>

#include "illum/core/error.h"
#include "illum/gpu/buffer.h"
#include "illum/gpu/descriptors.h"
#include "illum/realtime/frame_globals.h"

namespace illum::realtime {

namespace {

constexpr auto kUbo = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
constexpr auto kSsbo = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
constexpr auto kTexture = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
// Zeroed, for the neutral uniform and storage blocks: the largest input block (PRT, 64 SH
// coefficients) fits.
constexpr size_t kZeroBytes = 4096;

// The state block (shaders/lighting_inputs.glsl `inputs_state`): one flag per input.
struct InputsState {
  glm::ivec4 active[kMaxLightingInputs / 4];
};

std::vector<LightingInputDecl> make_registry() {
  std::vector<LightingInputDecl> r;
  LightingInputDecl probes;
  probes.name = "probes";
  probes.terms = kTermIndirect;
  probes.index = kProbesInput;
  probes.base = kProbesInputBase;
  probes.bindings = {{kUbo}, {kSsbo}, {kSsbo}, {kSsbo}};
  probes.summary =
      "the probe volume per pixel or one ambient cube per instance, on probed dynamic draws";
  r.push_back(probes);
  LightingInputDecl prt;
  prt.name = "prt";
  prt.terms = kTermIndirect | kTermVisibility;
  prt.index = kPrtInput;
  prt.base = kPrtInputBase;
  prt.bindings = {{kUbo}, {kSsbo}, {kSsbo}};
  prt.summary = "PRT transfer relit by the sun (its visibility is in the transfer)";
  r.push_back(prt);
  LightingInputDecl lightmap;
  lightmap.name = "lightmap";
  lightmap.terms = kTermIndirect;
  lightmap.index = kLightmapInput;
  lightmap.base = kLightmapInputBase;
  lightmap.bindings = {{kUbo}, {kTexture, VK_IMAGE_VIEW_TYPE_2D_ARRAY}};
  lightmap.summary = "light-map at uv1 (plain, RNM, SH-L1, dominant)";
  r.push_back(lightmap);
  LightingInputDecl ssao;
  ssao.name = "ssao";
  ssao.terms = kTermOcclusion;
  ssao.index = kSsaoInput;
  ssao.base = kSsaoInputBase;
  ssao.bindings = {{kTexture, VK_IMAGE_VIEW_TYPE_2D}};
  ssao.screen_space = true;
  ssao.summary = "screen-space occlusion image (R, 1 = open) at the output resolution";
  r.push_back(ssao);
  LightingInputDecl light_volume;
  light_volume.name = "light_volume";
  light_volume.terms = kTermIndirect;
  light_volume.index = kLightVolumeInput;
  light_volume.base = kLightVolumeInputBase;
  light_volume.bindings = {
      {kUbo}, {kTexture, VK_IMAGE_VIEW_TYPE_3D}, {kTexture, VK_IMAGE_VIEW_TYPE_3D}};
  light_volume.summary =
      "linear irradiance volume over the scene (techniques/light_volume.cpp: a teaching example)";
  r.push_back(light_volume);
  LightingInputDecl lpv;
  lpv.name = "lpv";
  lpv.terms = kTermIndirect;
  lpv.index = kLpvInput;
  lpv.base = kLpvInputBase;
  lpv.bindings = {{kUbo}, {kTexture, VK_IMAGE_VIEW_TYPE_3D}};
  lpv.summary = "light propagation volume: one bounce from the reflective shadow maps";
  r.push_back(lpv);
  LightingInputDecl vpl;
  vpl.name = "vpl";
  vpl.terms = kTermIndirect;
  vpl.index = kVplInput;
  vpl.base = kVplInputBase;
  vpl.bindings = {{kTexture, VK_IMAGE_VIEW_TYPE_2D}};
  vpl.screen_space = true;
  vpl.summary = "virtual point lights' irradiance per pixel (one bounce from the RSMs)";
  r.push_back(vpl);
  return r;
}

// The input's bindings with neutral descriptors: zeroed blocks, 1×1 dummy images.
void write_neutral(gpu::DescriptorWriter& w, VkDescriptorSet set, const LightingInputDecl& in,
                   const FrameGlobals& g, VkBuffer zeros) {
  for (size_t k = 0; k < in.bindings.size(); ++k) {
    const InputBinding& b = in.bindings[k];
    const uint32_t binding = static_cast<uint32_t>(in.base) + static_cast<uint32_t>(k);
    if (b.type == kTexture) {
      const gpu::GpuImage& dummy = b.view == VK_IMAGE_VIEW_TYPE_2D_ARRAY     ? g.dummy_array()
                                   : b.view == VK_IMAGE_VIEW_TYPE_CUBE_ARRAY ? g.dummy_cube()
                                   : b.view == VK_IMAGE_VIEW_TYPE_3D         ? g.dummy_3d()
                                                                             : g.dummy_2d();
      w.image(set, binding, kTexture, dummy.view(), g.clamp_linear().handle(),
              VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    } else {
      w.buffer(set, binding, b.type, zeros);
    }
  }
}

}  // namespace

const std::vector<LightingInputDecl>& lighting_input_registry() {
  static const std::vector<LightingInputDecl> registry = make_registry();
  return registry;
}

const LightingInputDecl* find_lighting_input(const std::string& name) {
  for (const LightingInputDecl& d : lighting_input_registry())
    if (d.name == name) return &d;
  return nullptr;
}

std::vector<gpu::DescriptorBinding> lighting_inputs_layout() {
  std::vector<gpu::DescriptorBinding> out = {{static_cast<uint32_t>(kInputsStateBinding), kUbo}};
  for (const LightingInputDecl& d : lighting_input_registry())
    for (size_t k = 0; k < d.bindings.size(); ++k)
      out.push_back({static_cast<uint32_t>(d.base) + static_cast<uint32_t>(k), d.bindings[k].type});
  return out;
}

void write_neutral_lighting_inputs(gpu::DescriptorWriter& w, VkDescriptorSet set,
                                   const FrameGlobals& globals, VkBuffer zeros) {
  w.buffer(set, static_cast<uint32_t>(kInputsStateBinding), kUbo, zeros);
  for (const LightingInputDecl& d : lighting_input_registry())
    write_neutral(w, set, d, globals, zeros);
}

gpu::Buffer make_lighting_inputs_zeros(gpu::Context& context) {
  gpu::Buffer zeros(context, kZeroBytes,
                    VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                    gpu::MemoryUsage::kUpload);
  const std::vector<uint8_t> bytes(kZeroBytes, 0);
  zeros.write(bytes.data(), bytes.size());
  return zeros;
}

struct LightingInputs::Impl {
  gpu::Context& context;
  const FrameGlobals& globals;
  gpu::DescriptorAllocator descriptors;
  gpu::Buffer zeros, state;
  VkDescriptorSet set = VK_NULL_HANDLE;
  // Per registered input: whether contributed, and the contribution's reads.
  std::vector<bool> active;
  std::vector<std::vector<std::string>> reads;

  Impl(gpu::Context& c, const FrameGlobals& g) : context(c), globals(g), descriptors(c) {}
};

LightingInputs::LightingInputs(gpu::Context& context, const FrameGlobals& globals)
    : impl_(std::make_unique<Impl>(context, globals)) {
  Impl& m = *impl_;
  m.zeros = make_lighting_inputs_zeros(context);
  m.state = gpu::Buffer(context, sizeof(InputsState), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                        gpu::MemoryUsage::kUpload);
  m.set = m.descriptors.allocate(globals.layout(kInputsSet));
  bind({});
}

LightingInputs::~LightingInputs() = default;

void LightingInputs::set_reads(const std::vector<LightingContribution>& contributions) {
  Impl& m = *impl_;
  const auto& registry = lighting_input_registry();
  std::vector<bool> active(registry.size(), false);
  std::vector<std::vector<std::string>> reads(registry.size());
  for (const LightingContribution& c : contributions) {
    const LightingInputDecl* d = find_lighting_input(c.input);
    if (!d) throw Error("lighting input '" + c.input + "' is not registered (lighting_inputs.cpp)");
    const size_t i = static_cast<size_t>(d - registry.data());
    if (active[i]) throw Error("lighting input '" + c.input + "' has two contributions");
    active[i] = true;
    reads[i] = c.reads;
  }
  m.active = std::move(active);
  m.reads = std::move(reads);
}

void LightingInputs::bind(const std::vector<LightingContribution>& contributions) {
  set_reads(contributions);
  Impl& m = *impl_;
  const auto& registry = lighting_input_registry();
  InputsState state{};
  gpu::DescriptorWriter w;
  w.buffer(m.set, static_cast<uint32_t>(kInputsStateBinding), kUbo, m.state.handle());
  for (size_t i = 0; i < registry.size(); ++i) {
    const LightingInputDecl& d = registry[i];
    const auto c = std::find_if(contributions.begin(), contributions.end(),
                                [&](const LightingContribution& x) { return x.input == d.name; });
    if (c == contributions.end()) {
      write_neutral(w, m.set, d, m.globals, m.zeros.handle());
      continue;
    }
    c->write(w, m.set, static_cast<uint32_t>(d.base));
    state.active[d.index / 4][d.index % 4] = 1;
  }
  w.commit(m.context.device());
  m.state.write(&state, sizeof(state));
}

VkDescriptorSet LightingInputs::set() const {
  return impl_->set;
}

bool LightingInputs::active(const std::string& input) const {
  const auto& registry = lighting_input_registry();
  for (size_t i = 0; i < registry.size(); ++i)
    if (registry[i].name == input) return i < impl_->active.size() && impl_->active[i];
  return false;
}

bool LightingInputs::any_screen_space() const {
  const auto& registry = lighting_input_registry();
  for (size_t i = 0; i < registry.size(); ++i)
    if (registry[i].screen_space && i < impl_->active.size() && impl_->active[i]) return true;
  return false;
}

std::vector<Access> LightingInputs::reads(VkPipelineStageFlags2 shaders, InputReads which) const {
  const auto& registry = lighting_input_registry();
  std::vector<Access> out;
  for (size_t i = 0; i < registry.size() && i < impl_->reads.size(); ++i) {
    if (which == InputReads::kSurface && registry[i].screen_space) continue;
    if (which == InputReads::kScreenSpace && !registry[i].screen_space) continue;
    for (const std::string& r : impl_->reads[i]) out.push_back({r, kSampled, shaders});
  }
  return out;
}

}  // namespace illum::realtime
