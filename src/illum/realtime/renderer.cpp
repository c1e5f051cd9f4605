#include "illum/realtime/renderer.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <initializer_list>
#include <utility>

#include "illum/core/color.h"
#include "illum/core/log.h"
#include "illum/gpu/buffer.h"
#include "illum/gpu/descriptors.h"
#include "illum/gpu/gpu_image.h"
#include "illum/gpu/pipeline.h"
#include "illum/gpu/vk_check.h"
#include "illum/realtime/frame_graph.h"
#include "illum/realtime/gpu_scene.h"
#include "illum/realtime/renderer_input.h"
#include "illum/realtime/stencil_shadows.h"

namespace illum::realtime {

using gpu::GpuImage;

namespace {

// The enum value named `name`, or an Error listing the known names of `what`.
template <typename E>
E enum_from_string(const std::string& name, const char* what,
                   std::initializer_list<std::pair<const char*, E>> values) {
  std::string known;
  for (const auto& [text, value] : values) {
    if (name == text) return value;
    known += (known.empty() ? "" : ", ") + std::string(text);
  }
  throw Error(fmt::format("unknown {} '{}' (known: {})", what, name, known));
}

}  // namespace

ToneMapOp tone_map_op_from_string(const std::string& name) {
  return enum_from_string<ToneMapOp>(name, "tone mapper",
                                     {{"clamp", ToneMapOp::kClamp},
                                      {"reinhard", ToneMapOp::kReinhard},
                                      {"aces", ToneMapOp::kAces},
                                      {"agx", ToneMapOp::kAgx}});
}

ShadowMode shadow_mode_from_string(const std::string& name) {
  return enum_from_string<ShadowMode>(name, "shadow technique",
                                      {{"none", ShadowMode::kNone},
                                       {"map", ShadowMode::kMap},
                                       {"vsm", ShadowMode::kVsm},
                                       {"volume", ShadowMode::kVolume}});
}

Technique technique_from_string(const std::string& name) {
  return enum_from_string<Technique>(
      name, "technique", {{"forward", Technique::kForward}, {"deferred", Technique::kDeferred}});
}

DeferredLighting deferred_lighting_from_string(const std::string& name) {
  return enum_from_string<DeferredLighting>(
      name, "deferred_lighting",
      {{"compute", DeferredLighting::kCompute}, {"volumes", DeferredLighting::kVolumes}});
}

SilhouetteSource silhouette_source_from_string(const std::string& name) {
  return enum_from_string<SilhouetteSource>(
      name, "silhouettes", {{"cpu", SilhouetteSource::kCpu}, {"gpu", SilhouetteSource::kGpu}});
}

RendererOptions RendererOptions::from_params(const Params& p) {
  RendererOptions o;
  o.width = p.get<int>("width", o.width);
  o.height = p.get<int>("height", o.height);
  if (p.has("technique")) o.technique = technique_from_string(p.get<std::string>("technique"));
  if (p.has("shadows")) o.shadows = shadow_mode_from_string(p.get<std::string>("shadows"));
  o.shadow_resolution = p.get<int>("shadow_resolution", o.shadow_resolution);
  o.shadow_update_period = p.get<int>("shadow_update_period", o.shadow_update_period);
  o.pcf_taps = p.get<int>("pcf_taps", o.pcf_taps);
  o.pcf_radius = p.get<float>("pcf_radius", o.pcf_radius);
  o.shadow_bias = p.get<float>("shadow_bias", o.shadow_bias);
  o.vsm_tau = p.get<float>("vsm_tau", o.vsm_tau);
  o.volume_back_faces = p.get<bool>("volume_back_faces", o.volume_back_faces);
  if (p.has("silhouettes"))
    o.silhouettes = silhouette_source_from_string(p.get<std::string>("silhouettes"));
  o.half_lambert = p.get<bool>("half_lambert", o.half_lambert);
  if (p.has("ambient")) o.ambient = p.get<vec3>("ambient");
  if (p.has("tone_mapper"))
    o.tone_mapper = tone_map_op_from_string(p.get<std::string>("tone_mapper"));
  o.auto_exposure = p.get<bool>("auto_exposure", o.auto_exposure);
  o.exposure = p.get<float>("exposure", o.exposure);
  o.key = p.get<float>("key", o.key);
  o.bloom_strength = p.get<float>("bloom_strength", o.bloom_strength);
  o.bloom_threshold = p.get<float>("bloom_threshold", o.bloom_threshold);
  if (p.has("deferred_lighting"))
    o.deferred_lighting = deferred_lighting_from_string(p.get<std::string>("deferred_lighting"));
  // The ranges live in one place, the check the Renderer runs at its entry too.
  try {
    check_renderer_options(o);
  } catch (const Error& e) {
    throw Error(fmt::format("{}: {}", p.origin(), e.what()));
  }
  return o;
}

RendererOptions RendererOptions::from_settings(const RenderSettings& s) {
  RendererOptions o;
  o.width = s.width;
  o.height = s.height;
  o.technique = technique_from_string(s.pipeline);
  o.shadows = shadow_mode_from_string(s.shadows);
  const std::string maps = s.shadows == "vsm" ? "vsm" : "map";
  o.shadow_resolution = s.get<int>(maps + ".resolution");
  o.shadow_update_period =
      s.get<int>((s.shadows == "volume" ? std::string("volume") : maps) + ".update_period");
  o.pcf_taps = s.get<int>("map.pcf_taps");
  o.pcf_radius = s.get<float>("map.pcf_radius");
  o.shadow_bias = s.get<float>("map.bias");
  o.vsm_tau = s.get<float>("vsm.tau");
  o.volume_back_faces = s.get<bool>("volume.back_faces");
  o.silhouettes = silhouette_source_from_string(s.get<std::string>("volume.silhouettes"));
  o.half_lambert = s.get<bool>("lighting.half_lambert");
  o.ambient = s.get<Color>("lighting.ambient");
  o.single_light = s.get<int>("lighting.single_light");
  o.tone_mapper = tone_map_op_from_string(s.get<std::string>("tonemap.operator"));
  o.auto_exposure = s.active("luminance");
  o.exposure = s.get<float>("tonemap.exposure");
  o.key = s.get<float>("tonemap.key");
  o.bloom_strength = s.active("bloom") ? s.get<float>("bloom.strength") : 0.0f;
  o.bloom_threshold = s.get<float>("bloom.threshold");
  o.deferred_lighting = deferred_lighting_from_string(s.get<std::string>("deferred.lighting"));
  return o;
}

namespace {

constexpr VkFormat kHdrFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
constexpr VkFormat kLdrFormat = VK_FORMAT_R8G8B8A8_UNORM;
// Shadow maps hold distance/far and, for VSM only, its square: PCF needs half the bytes.
constexpr VkFormat kShadowFormat = VK_FORMAT_R32G32_SFLOAT;
constexpr VkFormat kShadowPcfFormat = VK_FORMAT_R32_SFLOAT;
constexpr VkFormat kShadowDepthFormat = VK_FORMAT_D32_SFLOAT;
// Compact G-buffer, 20 bytes a pixel plus the HDR target (was 28 + 8 in four fp16 targets).
constexpr VkFormat kGbufferAlbedoFormat = VK_FORMAT_R16G16B16A16_SFLOAT;  // albedo, exponent
constexpr VkFormat kGbufferNormalFormat = VK_FORMAT_R16G16B16A16_SFLOAT;  // 2 octahedral normals
constexpr VkFormat kGbufferSpecularFormat = VK_FORMAT_R8G8B8A8_UNORM;     // ks, material type

gpu::VertexInput mesh_vertex_input(bool position_only) {
  gpu::VertexInput in;
  in.stride = sizeof(Vertex);
  in.attributes.push_back({0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, position)});
  if (position_only) return in;
  in.attributes.push_back({1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, normal)});
  in.attributes.push_back({2, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(Vertex, tangent)});
  in.attributes.push_back({3, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(Vertex, uv0)});
  in.attributes.push_back({4, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(Vertex, uv1)});
  return in;
}

void set_viewport(VkCommandBuffer cmd, uint32_t w, uint32_t h) {
  VkViewport vp{0.0f, 0.0f, static_cast<float>(w), static_cast<float>(h), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, {w, h}};
  vkCmdSetViewport(cmd, 0, 1, &vp);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
}

VkRenderingAttachmentInfo color_attachment(VkImageView view, bool clear,
                                           VkClearColorValue value = {}) {
  VkRenderingAttachmentInfo a{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  a.imageView = view;
  a.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  a.loadOp = clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD;
  a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  a.clearValue.color = value;
  return a;
}

VkRenderingAttachmentInfo depth_attachment(VkImageView view, bool clear) {
  VkRenderingAttachmentInfo a{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  a.imageView = view;
  a.imageLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
  a.loadOp = clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD;
  a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  a.clearValue.depthStencil = {1.0f, 0};
  return a;
}

// Unit icosphere (icosahedron subdivided once, 80 faces) for deferred light volumes.
void icosphere(std::vector<vec3>* positions, std::vector<uint32_t>* indices) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<vec3> p = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (vec3& v : p) v = glm::normalize(v);
  const std::vector<uint32_t> f = {0, 11, 5, 0, 5,  1,  0,  1,  7,  0,  7, 10, 0, 10, 11,
                                   1, 5,  9, 5, 11, 4,  11, 10, 2,  10, 7, 6,  7, 1,  8,
                                   3, 9,  4, 3, 4,  2,  3,  2,  6,  3,  6, 8,  3, 8,  9,
                                   4, 9,  5, 2, 4,  11, 6,  2,  10, 8,  6, 7,  9, 8,  1};
  std::vector<uint32_t> out;
  auto mid = [&](uint32_t a, uint32_t b) {
    p.push_back(glm::normalize(p[a] + p[b]));
    return static_cast<uint32_t>(p.size() - 1);
  };
  for (size_t i = 0; i < f.size(); i += 3) {
    const uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
    const uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
    out.insert(out.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
  }
  *positions = std::move(p);
  *indices = std::move(out);
}

}  // namespace

bool lit_in_real_time(const Light& l) {
  return l.type == LightType::kPoint || l.type == LightType::kSpot ||
         l.type == LightType::kDirectional;
}

std::vector<Light> realtime_lights(const Scene& scene) {
  std::vector<Light> out;
  for (const Light& l : scene.lights) {
    if (l.type != LightType::kArea) {
      out.push_back(l);
      continue;
    }
    const std::string name = l.name.empty() ? "area light" : fmt::format("area light '{}'", l.name);
    if (l.instance < 0 || static_cast<size_t>(l.instance) >= scene.instances.size())
      throw Error(
          fmt::format("{} refers to instance {} of {}", name, l.instance, scene.instances.size()));
    const Instance& inst = scene.instances[static_cast<size_t>(l.instance)];
    const Mesh& m = scene.meshes.at(static_cast<size_t>(inst.mesh));
    if (m.material < 0 || static_cast<size_t>(m.material) >= scene.materials.size())
      throw Error(fmt::format("{}: its mesh has no material to emit with", name));
    const Material& mat = scene.materials[static_cast<size_t>(m.material)];
    float area = 0.0f;
    vec3 centroid(0.0f), normal(0.0f);
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
      const vec3 a = vec3(inst.transform * vec4(m.positions[m.indices[t]], 1.0f));
      const vec3 b = vec3(inst.transform * vec4(m.positions[m.indices[t + 1]], 1.0f));
      const vec3 c = vec3(inst.transform * vec4(m.positions[m.indices[t + 2]], 1.0f));
      const vec3 n = glm::cross(b - a, c - a);
      const float ta = 0.5f * glm::length(n);
      area += ta;
      centroid += ta * (a + b + c) / 3.0f;
      normal += n;
    }
    // A zero-area emitter has no direction to face and no power: bad input, not a light
    // to drop silently (the offline renderers would not see it either).
    if (!(area > 0.0f) || !std::isfinite(area) || !(glm::length(normal) > 0.0f))
      throw Error(fmt::format("{} (instance {}) has zero area", name, l.instance));
    Light spot;
    spot.name = l.name + " (area as Lambertian spot)";
    spot.type = LightType::kSpot;
    spot.direction = glm::normalize(normal);
    // Just in front of the emitter, so its own triangles lie behind the light (outside the
    // cone, and inside the shadow maps' near plane); 1e-3 of the emitter's size keeps the
    // 1/d² error below 0.1% wherever the far-field model holds.
    spot.position = centroid / area + spot.direction * (1e-3f * std::sqrt(area));
    spot.cone_half_angle = radians(89.9f);
    // Seen from a distance, a flat one-sided Lambertian emitter of radiance L and area A has
    // intensity I(θ) = L·A·cos θ about its normal (flux π·L·A).
    spot.intensity = mat.emission * area;
    spot.cosine_falloff = true;
    spot.range = l.range;
    out.push_back(spot);
  }
  return out;
}

namespace {

constexpr VkPipelineStageFlags2 kColorStage = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
constexpr VkAccessFlags2 kColorAccess =
    VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT;
constexpr VkPipelineStageFlags2 kDepthStage =
    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
constexpr VkAccessFlags2 kDepthAccess =
    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT;
constexpr VkPipelineStageFlags2 kSampleStage =
    VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;

}  // namespace

struct Renderer::Impl {
  gpu::Context& context;
  RendererOptions options;
  GpuScene scene;
  std::vector<Light> lights;
  uint32_t width, height;

  // Frame resources.
  GpuImage hdr, ldr, depth, shadow_depth, dummy_cube, dummy_array, dummy_2d, dummy_white;
  GpuImage shadow_cubes;  // cube-map array, one cube per shadowed light
  GpuImage cascades;      // 2D array: cascaded shadow maps of one directional light
  int cascade_light = -1;
  static constexpr int kCascades = 4;
  glm::vec4 cascade_half_widths{0.0f};
  std::vector<int> shadow_lights;  // light index of each cube
  // Narrow spot lights get one 2-D perspective map (the cone's frustum) instead of 6 faces.
  GpuImage spot_maps;            // 2D array, one layer per entry of spot_lights
  std::vector<int> spot_lights;  // light index of each spot map
  int cascade_view_offset = 0;   // first cascade's entry in shadow_views
  gpu::Buffer frame_ubo, lights_buffer, shadow_views, luminance;
  gpu::Sampler linear, nearest, clamp_linear;
  gpu::DescriptorAllocator descriptors;
  gpu::DescriptorSetLayout frame_layout, material_layout, tonemap_layout;
  VkDescriptorSet frame_set = VK_NULL_HANDLE, tonemap_set = VK_NULL_HANDLE;
  std::vector<VkDescriptorSet> material_sets;
  gpu::PipelineLayout scene_pipeline_layout, tonemap_pipeline_layout;
  gpu::Pipeline forward, shadow_cube, luminance_pipe, reduce_pipe, tonemap_pipe;
  gpu::Pipeline depth_prepass;  // forward: depth only, then shading with depth EQUAL
  // Stencil shadows: the lighting pass per light, where the volumes' count is 0 (forward:
  // the scene again, depth LESS_OR_EQUAL; deferred: a full-screen G-buffer pass).
  gpu::Pipeline volume_light, volume_fullscreen;
  // Deferred path.
  GpuImage g_albedo, g_normal, g_specular;  // compact: see shaders/gbuffer.glsl
  gpu::DescriptorSetLayout gbuffer_layout;
  VkDescriptorSet gbuffer_set = VK_NULL_HANDLE;
  gpu::PipelineLayout deferred_pipeline_layout;
  gpu::Pipeline gbuffer_pipe, light_stencil_pipe, light_volume_pipe, light_fullscreen_pipe;
  gpu::Pipeline light_compute_pipe, gbuffer_prepass;
  gpu::Buffer sphere_vertices, sphere_indices;
  uint32_t sphere_index_count = 0;
  std::unique_ptr<StencilShadows> stencil_shadows;
  bool volumes_dirty = true;    // CPU volumes: rebuild before the next frame
  double silhouette_ms = -1.0;  // CPU build time in this frame (−1: not rebuilt)
  std::array<glm::mat4, 4> cascade_matrices{glm::mat4(1.0f), glm::mat4(1.0f), glm::mat4(1.0f),
                                            glm::mat4(1.0f)};
  gpu::Pipeline shadow_dir;
  GpuImage lightmap_image;
  gpu::Buffer ambient_cubes;  // 6 vec4 per probed draw
  gpu::Buffer prt_transfer;   // per vertex SH-L1 transfer
  bool prt = false;
  std::vector<int> draw_cube;  // per draw item: cube index + 1 (0 = none)
  Lightmap lightmap_info;
  // Bloom: half-resolution ping-pong images.
  GpuImage bloom_a, bloom_b;
  gpu::DescriptorSetLayout bloom_layout;
  gpu::PipelineLayout bloom_pipeline_layout;
  VkDescriptorSet bloom_sets[3] = {VK_NULL_HANDLE, VK_NULL_HANDLE, VK_NULL_HANDLE};
  gpu::Pipeline bloom_bright, bloom_blur;
  VkFormat depth_format;
  uint32_t tiles_x = 0, tiles_y = 0;

  FrameGraph graph;
  gpu::GpuTimer timer;
  VkCommandPool pool = VK_NULL_HANDLE;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  uint64_t frame_index = 0;
  mat4 view_proj{1.0f};  // this frame's camera
  std::vector<gpu::PassTime> times;

  Impl(gpu::Context& c, const Scene& s, const RendererOptions& o)
      : context(c),
        options(o),
        scene(c, s),
        lights(realtime_lights(s)),
        width(static_cast<uint32_t>(o.width)),
        height(static_cast<uint32_t>(o.height)),
        descriptors(c),
        timer(c) {
    if (volumes() && !c.depth_clamp())
      throw Error(
          fmt::format("shadows 'volume' need depthClamp, which '{}' lacks", c.device_name()));
    depth_format = gpu::pick_depth_stencil_format(c);
    create_targets();
    create_buffers();
    create_descriptors();
    create_pipelines();
    build_graph();
    VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pi.queueFamilyIndex = c.queue_family();
    ILLUM_VK(vkCreateCommandPool(c.device(), &pi, nullptr, &pool));
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    ILLUM_VK(vkAllocateCommandBuffers(c.device(), &ai, &cmd));
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    ILLUM_VK(vkCreateFence(c.device(), &fi, nullptr, &fence));
  }

  ~Impl() {
    context.wait_idle();
    if (fence) vkDestroyFence(context.device(), fence, nullptr);
    if (pool) vkDestroyCommandPool(context.device(), pool, nullptr);
  }

  void create_targets() {
    gpu::ImageDesc d;
    d.width = width;
    d.height = height;
    d.format = kHdrFormat;
    d.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
              VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    // Storage only for the deferred compute lighting: some GPUs drop colour-target
    // compression on storage-capable images.
    if (options.technique == Technique::kDeferred) d.usage |= VK_IMAGE_USAGE_STORAGE_BIT;
    hdr = GpuImage(context, d);
    d.format = kLdrFormat;
    d.usage =
        VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    ldr = GpuImage(context, d);
    d.format = depth_format;
    d.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
              VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    depth = GpuImage(context, d);

    if (options.technique == Technique::kDeferred) {
      gpu::ImageDesc g = d;
      g.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
      g.format = kGbufferSpecularFormat;
      g_specular = GpuImage(context, g);
      // Albedo in fp16: 8 bits would cost dark channels (0.065 red-wall green) several
      // percent and break agreement with the forward path.
      g.format = kGbufferAlbedoFormat;
      g_albedo = GpuImage(context, g);
      g.format = kGbufferNormalFormat;
      g_normal = GpuImage(context, g);
      std::vector<vec3> sp;
      std::vector<uint32_t> si;
      icosphere(&sp, &si);
      sphere_vertices = gpu::make_device_buffer(context, sp.data(), sp.size() * sizeof(vec3),
                                                VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
      sphere_indices = gpu::make_device_buffer(context, si.data(), si.size() * sizeof(uint32_t),
                                               VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
      sphere_index_count = static_cast<uint32_t>(si.size());
    }
    if (options.bloom_strength > 0.0f) {
      gpu::ImageDesc b;
      b.width = std::max(1u, width / 2);
      b.height = std::max(1u, height / 2);
      b.format = VK_FORMAT_R16G16B16A16_SFLOAT;
      b.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
      bloom_a = GpuImage(context, b);
      bloom_b = GpuImage(context, b);
    }
    // Dummies keep every descriptor valid when a feature is off.
    gpu::ImageDesc small;
    small.format = VK_FORMAT_R32G32_SFLOAT;
    small.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    small.layers = 6;
    small.cube = true;
    small.cube_array = true;
    dummy_cube = GpuImage(context, small);
    small.layers = 1;
    small.cube = false;
    small.cube_array = false;
    dummy_2d = GpuImage(context, small);
    small.array = true;
    dummy_array = GpuImage(context, small);
    small.array = false;
    const Image far_moments(1, 1, 2, 1.0f);
    for (uint32_t l = 0; l < 6; ++l) dummy_cube.upload(far_moments, l);
    dummy_2d.upload(Image(1, 1, 2, 0.0f));
    dummy_array.upload(far_moments);
    small.format = VK_FORMAT_R8G8B8A8_UNORM;
    dummy_white = GpuImage(context, small);
    dummy_white.upload(Image(1, 1, 4, 1.0f));

    if (options.shadows == ShadowMode::kMap || options.shadows == ShadowMode::kVsm) {
      const uint32_t r = static_cast<uint32_t>(options.shadow_resolution);
      for (size_t i = 0; i < lights.size(); ++i) {
        const Light& l = lights[i];
        if (l.type == LightType::kSpot && l.cone_half_angle <= kMaxSpotMapHalfAngle) {
          if (spot_lights.size() < kMaxSpotMaps) spot_lights.push_back(static_cast<int>(i));
        } else if (l.type == LightType::kPoint || l.type == LightType::kSpot) {
          if (shadow_lights.size() < kMaxShadowCubes) shadow_lights.push_back(static_cast<int>(i));
        }
      }
      for (size_t i = 0; i < lights.size() && cascade_light < 0; ++i)
        if (lights[i].type == LightType::kDirectional) cascade_light = static_cast<int>(i);
      if (cascade_light >= 0) {
        gpu::ImageDesc c;
        c.width = c.height = r;
        c.layers = kCascades;
        c.format = shadow_format();
        c.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
        cascades = GpuImage(context, c);
      }
      if (!spot_lights.empty()) {
        gpu::ImageDesc c;
        c.width = c.height = r;
        c.layers = static_cast<uint32_t>(spot_lights.size());
        c.array = true;
        c.format = shadow_format();
        c.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
        spot_maps = GpuImage(context, c);
      }
      if (!shadow_lights.empty() || !spot_lights.empty() || cascade_light >= 0) {
        gpu::ImageDesc sd;
        sd.width = sd.height = r;
        sd.format = kShadowDepthFormat;
        sd.usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
        shadow_depth = GpuImage(context, sd);
      }
      if (!shadow_lights.empty()) {
        gpu::ImageDesc c;
        c.width = c.height = r;
        c.layers = static_cast<uint32_t>(6 * shadow_lights.size());
        c.cube = true;
        c.cube_array = true;
        c.format = shadow_format();
        c.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
        shadow_cubes = GpuImage(context, c);
      }
    }
  }

  bool volumes() const { return options.shadows == ShadowMode::kVolume; }
  // Lights or the caster choice changed: rebuild the volumes (CPU) or extract them (GPU).
  void invalidate_volumes() {
    volumes_dirty = true;
    graph.notify(kParametersChanged, "renderer");
  }

  VkFormat shadow_format() const {
    return options.shadows == ShadowMode::kVsm ? kShadowFormat : kShadowPcfFormat;
  }

  float shadow_far(const Light& l) const {
    if (l.range > 0.0f) return l.range;
    const Bounds3 b = scene.bounds();
    return glm::length(l.position - b.center()) + b.diagonal() + 1e-3f;
  }

  void upload_lights() {
    std::vector<GpuLight> gl;
    std::vector<glm::mat4> views;
    for (size_t i = 0; i < lights.size(); ++i) {
      const Light& l = lights[i];
      GpuLight g{};
      g.position_range = vec4(l.position, l.range);
      g.direction_cos = vec4(glm::normalize(l.direction), l.cos_cutoff());
      int type = 0;
      Color color = l.intensity;
      switch (l.type) {
        case LightType::kPoint:
          type = 0;
          break;
        case LightType::kSpot:
          type = l.cosine_falloff ? 3 : 1;
          break;
        case LightType::kDirectional:
          type = 2;
          color = l.irradiance;
          break;
        default:
          color = Color(0.0f);
          break;  // area/environment: not lit in real time
      }
      g.color_type = vec4(color, static_cast<float>(type));
      g.shadow = glm::ivec4(-1, 0, 0, 0);
      g.shadow_params = vec4(shadow_far(l), 0.0f, 0.0f, 0.0f);
      gl.push_back(g);
    }
    for (size_t s = 0; s < shadow_lights.size(); ++s) {
      const Light& l = lights[static_cast<size_t>(shadow_lights[s])];
      GpuLight& g = gl[static_cast<size_t>(shadow_lights[s])];
      g.shadow = glm::ivec4(static_cast<int>(s), static_cast<int>(views.size()), 6, 0);
      const float far_plane = g.shadow_params.x;
      // No y flip: Vulkan and OpenGL both map NDC y = −1 to the first row in memory, so the
      // OpenGL cube-face conventions (face axes and up vectors) apply unchanged.
      const mat4 proj = glm::perspectiveRH_ZO(radians(90.0f), 1.0f, far_plane * 1e-4f, far_plane);
      const vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
      const vec3 ups[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
      for (int f = 0; f < 6; ++f)
        views.push_back(proj * glm::lookAtRH(l.position, l.position + axes[f], ups[f]));
    }
    for (size_t s = 0; s < spot_lights.size(); ++s) {
      const Light& l = lights[static_cast<size_t>(spot_lights[s])];
      GpuLight& g = gl[static_cast<size_t>(spot_lights[s])];
      g.shadow = glm::ivec4(static_cast<int>(s), static_cast<int>(views.size()), 1, 1);
      const float far_plane = g.shadow_params.x;
      // A few degrees beyond the cone so PCF taps and the normal offset stay on the map.
      const float half_fov = std::min(l.cone_half_angle + radians(4.0f), radians(80.0f));
      const float tan_half = std::tan(half_fov);
      g.shadow_params.y = tan_half;
      const vec3 dir = glm::normalize(l.direction);
      const vec3 up = std::abs(dir.y) > 0.99f ? vec3(1, 0, 0) : vec3(0, 1, 0);
      const mat4 proj = glm::perspectiveRH_ZO(2.0f * half_fov, 1.0f, far_plane * 1e-4f, far_plane);
      views.push_back(proj * glm::lookAtRH(l.position, l.position + dir, up));
    }
    cascade_view_offset = static_cast<int>(views.size());
    if (cascade_light >= 0) {
      GpuLight& g = gl[static_cast<size_t>(cascade_light)];
      g.shadow = glm::ivec4(-1, static_cast<int>(views.size()), kCascades, 0);
      g.shadow_params = cascade_half_widths;
      for (int k = 0; k < kCascades; ++k)
        views.emplace_back(cascade_matrices[static_cast<size_t>(k)]);
    }
    if (gl.empty()) gl.push_back(GpuLight{});
    if (views.empty()) views.emplace_back(1.0f);
    lights_buffer.write(gl.data(), gl.size() * sizeof(GpuLight));
    shadow_views.write(views.data(), views.size() * sizeof(glm::mat4));
  }

  void create_buffers() {
    frame_ubo = gpu::Buffer(context, sizeof(FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                            gpu::MemoryUsage::kUpload);
    const size_t nl = std::max<size_t>(1, lights.size());
    lights_buffer = gpu::Buffer(context, nl * sizeof(GpuLight), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                gpu::MemoryUsage::kUpload);
    shadow_views = gpu::Buffer(
        context, (6 * shadow_lights.size() + spot_lights.size() + kCascades) * sizeof(glm::mat4),
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::kUpload);
    tiles_x = (width + 15) / 16;
    tiles_y = (height + 15) / 16;
    luminance = gpu::Buffer(context, (tiles_x * tiles_y + 1) * sizeof(float),
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                            gpu::MemoryUsage::kDevice);
    upload_lights();
  }

  void create_descriptors() {
    linear = gpu::Sampler(context, VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_REPEAT, true);
    nearest = gpu::Sampler(context, VK_FILTER_NEAREST, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);
    clamp_linear = gpu::Sampler(context, VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);
    using B = gpu::DescriptorBinding;
    frame_layout = gpu::DescriptorSetLayout(
        context,
        {B{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER}, B{1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
         B{2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}, B{3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
         B{4, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
         B{5, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
         B{6, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER}, B{7, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
         B{8, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}, B{9, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER}});
    frame_set = descriptors.allocate(frame_layout);
    material_layout =
        gpu::DescriptorSetLayout(context, {B{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
                                           B{1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
                                           B{2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
                                           B{3, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER}});
    gpu::DescriptorWriter w;
    const auto ro = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    const auto cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    w.buffer(frame_set, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frame_ubo.handle())
        .buffer(frame_set, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, scene.materials().handle())
        .buffer(frame_set, 2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, lights_buffer.handle())
        .buffer(frame_set, 3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, shadow_views.handle());
    // PCF compares single texels; VSM filters the moments.
    const VkSampler shadow_sampler =
        options.shadows == ShadowMode::kVsm ? clamp_linear.handle() : nearest.handle();
    w.image(frame_set, 4, cis, shadow_cubes ? shadow_cubes.view() : dummy_cube.view(),
            shadow_sampler, ro);
    w.image(frame_set, 5, cis, cascades ? cascades.view() : dummy_array.view(), shadow_sampler, ro);
    w.image(frame_set, 6, cis, dummy_array.view(), clamp_linear.handle(), ro);
    w.image(frame_set, 9, cis, spot_maps ? spot_maps.view() : dummy_array.view(), shadow_sampler,
            ro);
    ambient_cubes = gpu::Buffer(context, 6 * sizeof(vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                gpu::MemoryUsage::kUpload);
    w.buffer(frame_set, 7, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, ambient_cubes.handle());
    prt_transfer = gpu::Buffer(context, sizeof(vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                               gpu::MemoryUsage::kUpload);
    w.buffer(frame_set, 8, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, prt_transfer.handle());
    draw_cube.assign(scene.draws().size(), 0);
    const Scene& sc = scene.scene();
    const size_t nmat = std::max<size_t>(1, sc.materials.size());
    auto texture_view = [&](int index) {
      return index >= 0 && static_cast<size_t>(index) < scene.textures().size()
                 ? scene.textures()[static_cast<size_t>(index)].view()
                 : dummy_white.view();
    };
    for (size_t m = 0; m < nmat; ++m) {
      const VkDescriptorSet set = descriptors.allocate(material_layout);
      const Material mat = m < sc.materials.size() ? sc.materials[m] : Material{};
      w.image(set, 0, cis, texture_view(mat.albedo_texture), linear.handle(), ro)
          .image(set, 1, cis, texture_view(mat.normal_texture), linear.handle(), ro)
          .image(set, 2, cis, texture_view(mat.emission_texture), linear.handle(), ro)
          .image(set, 3, cis, dummy_white.view(), linear.handle(), ro);
      material_sets.push_back(set);
    }
    w.commit(context.device());

    if (g_albedo) {
      // Binding 4 (the HDR target as a storage image) is used by the compute lighting only.
      gbuffer_layout = gpu::DescriptorSetLayout(
          context,
          {B{0, cis}, B{1, cis}, B{2, cis}, B{3, cis}, B{4, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}});
      gbuffer_set = descriptors.allocate(gbuffer_layout);
      w.image(gbuffer_set, 0, cis, g_albedo.view(), nearest.handle(), ro)
          .image(gbuffer_set, 1, cis, g_normal.view(), nearest.handle(), ro)
          .image(gbuffer_set, 2, cis, g_specular.view(), nearest.handle(), ro)
          .image(gbuffer_set, 3, cis, depth.view(), nearest.handle(),
                 VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL)
          .image(gbuffer_set, 4, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, hdr.view(), VK_NULL_HANDLE,
                 VK_IMAGE_LAYOUT_GENERAL)
          .commit(context.device());
    }
    tonemap_layout =
        gpu::DescriptorSetLayout(context, {B{0, cis}, B{1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                           B{2, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}, B{3, cis}});
    tonemap_set = descriptors.allocate(tonemap_layout);
    w.image(tonemap_set, 0, cis, hdr.view(), nearest.handle(), ro)
        .buffer(tonemap_set, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, luminance.handle())
        .image(tonemap_set, 2, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, ldr.view(), VK_NULL_HANDLE,
               VK_IMAGE_LAYOUT_GENERAL)
        .image(tonemap_set, 3, cis, bloom_a ? bloom_a.view() : dummy_2d.view(),
               clamp_linear.handle(), ro)
        .commit(context.device());
    if (bloom_a) {
      bloom_layout =
          gpu::DescriptorSetLayout(context, {B{0, cis}, B{1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE}});
      const VkImageView src[3] = {hdr.view(), bloom_a.view(), bloom_b.view()};
      const VkImageView dst[3] = {bloom_a.view(), bloom_b.view(), bloom_a.view()};
      for (int k = 0; k < 3; ++k) {
        bloom_sets[k] = descriptors.allocate(bloom_layout);
        w.image(bloom_sets[k], 0, cis, src[k], clamp_linear.handle(), ro)
            .image(bloom_sets[k], 1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, dst[k], VK_NULL_HANDLE,
                   VK_IMAGE_LAYOUT_GENERAL);
      }
      w.commit(context.device());
    }
  }

  void create_pipelines() {
    scene_pipeline_layout = gpu::PipelineLayout(
        context, {frame_layout.handle(), material_layout.handle()}, sizeof(PushConstants));
    tonemap_pipeline_layout = gpu::PipelineLayout(context, {tonemap_layout.handle()}, 32);
    gpu::GraphicsPipelineDesc fwd;
    fwd.vertex_shader = "forward.vert";
    fwd.fragment_shader = "forward.frag";
    fwd.vertex_input = mesh_vertex_input(false);
    fwd.cull = VK_CULL_MODE_NONE;  // scenes are two-sided, like the offline renderers
    fwd.color_formats = {kHdrFormat};
    fwd.depth_format = depth_format;
    fwd.stencil_format = depth_format;
    // Depth pre-pass: the same vertex shader and inputs (so depths repeat exactly), no
    // fragment shader; the shading pass then runs each pixel's fragment shader once, where
    // Sibenik's nave would otherwise shade every overlapping layer.
    gpu::GraphicsPipelineDesc pre = fwd;
    pre.fragment_shader = "";
    pre.color_write = false;
    depth_prepass = gpu::Pipeline(context, scene_pipeline_layout.handle(), pre);
    fwd.depth_write = false;
    fwd.depth_compare = VK_COMPARE_OP_EQUAL;
    forward = gpu::Pipeline(context, scene_pipeline_layout.handle(), fwd);
    fwd.depth_write = true;
    fwd.depth_compare = VK_COMPARE_OP_LESS;
    if (shadow_cubes || spot_maps) {
      gpu::GraphicsPipelineDesc sh;
      sh.vertex_shader = "shadow_cube.vert";
      sh.fragment_shader = "shadow_cube.frag";
      sh.vertex_input = mesh_vertex_input(true);
      sh.cull = VK_CULL_MODE_NONE;
      sh.color_formats = {shadow_format()};
      sh.depth_format = kShadowDepthFormat;
      shadow_cube = gpu::Pipeline(context, scene_pipeline_layout.handle(), sh);
    }
    if (cascades) {
      gpu::GraphicsPipelineDesc sh;
      sh.vertex_shader = "shadow_cube.vert";
      sh.fragment_shader = "shadow_dir.frag";
      sh.vertex_input = mesh_vertex_input(true);
      sh.cull = VK_CULL_MODE_NONE;
      sh.depth_clamp = context.depth_clamp();  // casters behind the cascade's near plane
      sh.color_formats = {shadow_format()};
      sh.depth_format = kShadowDepthFormat;
      shadow_dir = gpu::Pipeline(context, scene_pipeline_layout.handle(), sh);
    }
    if (g_albedo) {
      deferred_pipeline_layout = gpu::PipelineLayout(
          context, {frame_layout.handle(), material_layout.handle(), gbuffer_layout.handle()},
          sizeof(PushConstants));
      gpu::GraphicsPipelineDesc g = fwd;
      g.fragment_shader = "gbuffer.frag";
      g.color_formats = {kGbufferAlbedoFormat, kGbufferNormalFormat, kGbufferSpecularFormat,
                         kHdrFormat};
      // Depth pre-pass as in the forward path: each pixel then writes its 28 bytes once.
      gpu::GraphicsPipelineDesc g_pre = g;
      g_pre.fragment_shader = "";
      g_pre.color_write = false;
      gbuffer_prepass = gpu::Pipeline(context, deferred_pipeline_layout.handle(), g_pre);
      g.depth_write = false;
      g.depth_compare = VK_COMPARE_OP_EQUAL;
      gbuffer_pipe = gpu::Pipeline(context, deferred_pipeline_layout.handle(), g);
      light_compute_pipe =
          gpu::Pipeline(context, deferred_pipeline_layout.handle(), "deferred_light.comp");
      gpu::GraphicsPipelineDesc l;
      l.vertex_shader = "deferred_light.vert";
      l.fragment_shader = "deferred_light.frag";
      l.vertex_input.stride = sizeof(vec3);
      l.vertex_input.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
      l.color_formats = {kHdrFormat};
      l.depth_format = depth_format;
      l.stencil_format = depth_format;
      l.depth_write = false;
      l.depth_clamp = context.depth_clamp();
      // Stencil trick (S001 §4.1): mark pixels whose surface lies inside the sphere (z-fail
      // count ≠ 0), then shade them once through the back faces.
      gpu::GraphicsPipelineDesc st = l;
      st.fragment_shader = "";
      st.color_write = false;
      use_z_fail_count(&st);
      light_stencil_pipe = gpu::Pipeline(context, deferred_pipeline_layout.handle(), st);
      gpu::GraphicsPipelineDesc lv = l;
      // Both faces, no depth test (works with the camera inside the sphere); a shaded pixel
      // zeroes its stencil so the other face cannot light it twice.
      lv.cull = VK_CULL_MODE_NONE;
      lv.depth_test = false;
      lv.additive_blend = true;
      lv.stencil_test = true;
      lv.stencil_front =
          stencil_op(VK_STENCIL_OP_ZERO, VK_STENCIL_OP_KEEP, VK_COMPARE_OP_NOT_EQUAL);
      lv.stencil_back = lv.stencil_front;
      light_volume_pipe = gpu::Pipeline(context, deferred_pipeline_layout.handle(), lv);
      gpu::GraphicsPipelineDesc fs = l;
      fs.cull = VK_CULL_MODE_NONE;
      fs.depth_test = false;
      fs.additive_blend = true;
      light_fullscreen_pipe = gpu::Pipeline(context, deferred_pipeline_layout.handle(), fs);
      if (volumes()) {
        use_stencil_zero_test(&fs);
        volume_fullscreen = gpu::Pipeline(context, deferred_pipeline_layout.handle(), fs);
      }
    }
    if (volumes()) {
      stencil_shadows = std::make_unique<StencilShadows>(
          context, scene, lights.size(), options.silhouettes, scene_pipeline_layout.handle(),
          kHdrFormat, depth_format);
      if (!g_albedo) {
        gpu::GraphicsPipelineDesc l = fwd;
        l.depth_write = false;
        // Same vertex shader and state as the depth pass, so the depths repeat exactly (the
        // SPIR-V Invariant decoration on gl_Position trips the validator's struct-member rule).
        l.depth_compare = VK_COMPARE_OP_LESS_OR_EQUAL;
        l.additive_blend = true;
        use_stencil_zero_test(&l);
        // The first fragment that adds the light sets the count to 1, so a second,
        // coplanar surface at the same depth (Sibenik has such duplicates) fails the test
        // instead of adding the light again; the stencil is cleared before the next light.
        l.stencil_front =
            stencil_op(VK_STENCIL_OP_INCREMENT_AND_CLAMP, VK_STENCIL_OP_KEEP, VK_COMPARE_OP_EQUAL);
        l.stencil_back = l.stencil_front;
        volume_light = gpu::Pipeline(context, scene_pipeline_layout.handle(), l);
      }
    }
    if (bloom_a) {
      bloom_pipeline_layout = gpu::PipelineLayout(context, {bloom_layout.handle()}, 16);
      bloom_bright = gpu::Pipeline(context, bloom_pipeline_layout.handle(), "bloom_bright.comp");
      bloom_blur = gpu::Pipeline(context, bloom_pipeline_layout.handle(), "bloom_blur.comp");
    }
    luminance_pipe = gpu::Pipeline(context, tonemap_pipeline_layout.handle(), "luminance.comp");
    reduce_pipe = gpu::Pipeline(context, tonemap_pipeline_layout.handle(), "luminance_reduce.comp");
    tonemap_pipe = gpu::Pipeline(context, tonemap_pipeline_layout.handle(), "tonemap.comp");
  }

  void bind_scene(VkCommandBuffer c, VkPipeline pipeline) {
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
    vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_GRAPHICS, scene_pipeline_layout.handle(), 0,
                            1, &frame_set, 0, nullptr);
    VkDeviceSize offset = 0;
    VkBuffer vb = scene.vertices().handle();
    vkCmdBindVertexBuffers(c, 0, 1, &vb, &offset);
    vkCmdBindIndexBuffer(c, scene.indices().handle(), 0, VK_INDEX_TYPE_UINT32);
  }

  // Colour passes pass each draw's ambient-cube slot in push.view_index; shadow passes use
  // it for the shadow view.
  void draw_scene(VkCommandBuffer c, PushConstants push, bool colour_pass) {
    const bool materials = true;
    int bound = -1;
    for (size_t di = 0; di < scene.draws().size(); ++di) {
      const DrawItem& d = scene.draws()[di];
      if (colour_pass) push.view_index = draw_cube[di];
      push.model = d.transform;
      push.material = std::clamp<int>(d.material, 0, static_cast<int>(material_sets.size()) - 1);
      if (materials && push.material != bound) {
        bound = push.material;
        vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_GRAPHICS, scene_pipeline_layout.handle(),
                                1, 1, &material_sets[static_cast<size_t>(bound)], 0, nullptr);
      }
      vkCmdPushConstants(c, scene_pipeline_layout.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push),
                         &push);
      const MeshRange& r = scene.meshes()[d.mesh];
      vkCmdDrawIndexed(c, r.index_count, 1, r.first_index, r.vertex_offset, 0);
    }
  }

  // One view of the scene into one layer of `target` with `pipeline` (shadow_cube: radial
  // distance / far, shadow_dir: orthographic depth; VSM: also its square).
  void record_shadow_view(VkCommandBuffer c, const gpu::Pipeline& pipeline, GpuImage& target,
                          uint32_t layer, int view, int light) {
    const uint32_t r = static_cast<uint32_t>(options.shadow_resolution);
    shadow_depth.transition(c, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, kDepthStage,
                            kDepthAccess);
    VkRenderingAttachmentInfo color =
        color_attachment(target.layer_view(layer), true, {{1.0f, 1.0f, 0.0f, 0.0f}});
    VkRenderingAttachmentInfo depth_att = depth_attachment(shadow_depth.view(), true);
    depth_att.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, {r, r}};
    info.layerCount = 1;
    info.colorAttachmentCount = 1;
    info.pColorAttachments = &color;
    info.pDepthAttachment = &depth_att;
    vkCmdBeginRendering(c, &info);
    set_viewport(c, r, r);
    bind_scene(c, pipeline.handle());
    PushConstants push{};
    push.view_index = view;
    push.light_index = light;
    draw_scene(c, push, false);
    vkCmdEndRendering(c);
  }

  void record_shadow_maps(VkCommandBuffer c) {
    for (GpuImage* target : {&shadow_cubes, &spot_maps}) {
      if (!*target) continue;
      target->transition(c, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, kColorStage, kColorAccess);
    }
    for (size_t s = 0; s < shadow_lights.size(); ++s)
      for (uint32_t f = 0; f < 6; ++f)
        record_shadow_view(c, shadow_cube, shadow_cubes, static_cast<uint32_t>(6 * s + f),
                           static_cast<int>(6 * s + f), shadow_lights[s]);
    for (size_t s = 0; s < spot_lights.size(); ++s)
      record_shadow_view(c, shadow_cube, spot_maps, static_cast<uint32_t>(s),
                         static_cast<int>(6 * shadow_lights.size() + s), spot_lights[s]);
    for (GpuImage* target : {&shadow_cubes, &spot_maps}) {
      if (!*target) continue;
      target->transition(c, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, kSampleStage,
                         VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    }
  }

  void record_cascades(VkCommandBuffer c) {
    cascades.transition(c, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, kColorStage, kColorAccess);
    for (int k = 0; k < kCascades; ++k)
      record_shadow_view(c, shadow_dir, cascades, static_cast<uint32_t>(k), cascade_view_offset + k,
                         cascade_light);
    cascades.transition(c, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, kSampleStage,
                        VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
  }

  // Cascaded shadow maps (S001 §4.2.1): the view frustum split between uniform and
  // logarithmic (λ = 0.5); each split's bounding sphere gets an orthographic light view,
  // snapped to whole texels so the maps do not shimmer as the camera moves.
  glm::vec4 update_cascades(const Camera& camera, float aspect, float near_plane, float far_plane) {
    const Light& l = lights[static_cast<size_t>(cascade_light)];
    const vec3 dir = glm::normalize(l.direction);
    const mat4 inv_view = glm::inverse(camera.view_matrix());
    const float tan_half = std::tan(0.5f * camera.fov_y);
    const float scene_extent = scene.bounds().diagonal();
    glm::vec4 splits(far_plane);
    float prev = near_plane;
    for (int k = 0; k < kCascades; ++k) {
      const float f = static_cast<float>(k + 1) / kCascades;
      const float split = 0.5f * (near_plane + (far_plane - near_plane) * f) +
                          0.5f * near_plane * std::pow(far_plane / near_plane, f);
      splits[k] = split;
      vec3 center(0.0f);
      vec3 corners[8];
      int n = 0;
      for (float z : {prev, split})
        for (int sx : {-1, 1})
          for (int sy : {-1, 1}) {
            corners[n] =
                vec3(inv_view * vec4(sx * z * tan_half * aspect, sy * z * tan_half, -z, 1.0f));
            center += corners[n++];
          }
      center /= 8.0f;
      float radius = 0.0f;
      for (const vec3& c : corners) radius = std::max(radius, glm::length(c - center));
      const vec3 up = std::abs(dir.y) > 0.99f ? vec3(1, 0, 0) : vec3(0, 1, 0);
      mat4 view = glm::lookAtRH(center - dir * scene_extent, center, up);
      // Snap the light-space centre to the texel grid.
      const float texel = 2.0f * radius / static_cast<float>(options.shadow_resolution);
      vec4 origin = view * vec4(center, 1.0f);
      const vec2 snapped = glm::floor(vec2(origin) / texel) * texel;
      view = glm::translate(mat4(1.0f), vec3(snapped - vec2(origin), 0.0f)) * view;
      const mat4 proj =
          glm::orthoRH_ZO(-radius, radius, -radius, radius, 0.0f, scene_extent + radius);
      cascade_matrices[static_cast<size_t>(k)] = proj * view;
      cascade_half_widths[k] = radius;
      prev = split;
    }
    upload_lights();
    return splits;
  }

  void record_forward(VkCommandBuffer c) {
    hdr.transition(c, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, kColorStage, kColorAccess);
    depth.transition(c, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, kDepthStage,
                     kDepthAccess);
    VkRenderingAttachmentInfo color = color_attachment(hdr.view(), true);
    VkRenderingAttachmentInfo depth_att = depth_attachment(depth.layer_view(0), true);
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, {width, height}};
    info.layerCount = 1;
    info.colorAttachmentCount = 1;
    info.pColorAttachments = &color;
    info.pDepthAttachment = &depth_att;
    info.pStencilAttachment = &depth_att;
    vkCmdBeginRendering(c, &info);
    set_viewport(c, width, height);
    PushConstants push{};
    push.pad = volumes() ? 1 : 0;
    bind_scene(c, depth_prepass.handle());
    draw_scene(c, push, true);
    bind_scene(c, forward.handle());
    draw_scene(c, push, true);
    vkCmdEndRendering(c);
  }

  void record_gbuffer(VkCommandBuffer c) {
    for (GpuImage* g : {&g_albedo, &g_normal, &g_specular, &hdr})
      g->transition(c, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, kColorStage, kColorAccess);
    depth.transition(c, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, kDepthStage,
                     kDepthAccess);
    const VkRenderingAttachmentInfo colors[4] = {
        color_attachment(g_albedo.view(), true), color_attachment(g_normal.view(), true),
        color_attachment(g_specular.view(), true), color_attachment(hdr.view(), true)};
    VkRenderingAttachmentInfo depth_att = depth_attachment(depth.layer_view(0), true);
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, {width, height}};
    info.layerCount = 1;
    info.colorAttachmentCount = 4;
    info.pColorAttachments = colors;
    info.pDepthAttachment = &depth_att;
    info.pStencilAttachment = &depth_att;
    vkCmdBeginRendering(c, &info);
    set_viewport(c, width, height);
    bind_scene(c, gbuffer_prepass.handle());
    draw_scene(c, PushConstants{}, true);
    bind_scene(c, gbuffer_pipe.handle());
    draw_scene(c, PushConstants{}, true);
    vkCmdEndRendering(c);
  }

  void bind_gbuffer_sets(VkCommandBuffer c, VkPipelineBindPoint bind_point) {
    const VkDescriptorSet sets[3] = {frame_set, material_sets[0], gbuffer_set};
    vkCmdBindDescriptorSets(c, bind_point, deferred_pipeline_layout.handle(), 0, 3, sets, 0,
                            nullptr);
  }

  // The per-light passes after the depth (and G-buffer) pass — light volumes, shadow
  // volumes: the depth buffer read-only (tested, and sampled by the G-buffer lighting), the
  // stencil free for them, the HDR target added to.
  void prepare_light_rendering(VkCommandBuffer c) {
    for (GpuImage* g : {&g_albedo, &g_normal, &g_specular})
      if (*g)
        g->transition(c, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                      VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    hdr.transition(c, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, kColorStage, kColorAccess);
    depth.transition(c, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL,
                     kDepthStage | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                     kDepthAccess | VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
  }

  // A rendering scope over the HDR target and the read-only depth with the stencil cleared.
  void begin_light_rendering(VkCommandBuffer c) {
    const VkImageLayout ds = VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL;
    VkRenderingAttachmentInfo color = color_attachment(hdr.view(), false);
    VkRenderingAttachmentInfo depth_att = depth_attachment(depth.layer_view(0), false);
    depth_att.imageLayout = ds;
    depth_att.storeOp = VK_ATTACHMENT_STORE_OP_NONE;
    VkRenderingAttachmentInfo stencil_att = depth_attachment(depth.layer_view(0), true);
    stencil_att.imageLayout = ds;
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, {width, height}};
    info.layerCount = 1;
    info.colorAttachmentCount = 1;
    info.pColorAttachments = &color;
    info.pDepthAttachment = &depth_att;
    info.pStencilAttachment = &stencil_att;
    vkCmdBeginRendering(c, &info);
    set_viewport(c, width, height);
  }

  // One dispatch: every pixel loops over the lights and adds to the HDR target in place.
  void record_compute_lighting(VkCommandBuffer c) {
    const VkPipelineStageFlags2 cs = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    for (GpuImage* g : {&g_albedo, &g_normal, &g_specular})
      g->transition(c, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, cs,
                    VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    depth.transition(c, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL, cs,
                     VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    hdr.transition(c, VK_IMAGE_LAYOUT_GENERAL, cs,
                   VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    bind_gbuffer_sets(c, VK_PIPELINE_BIND_POINT_COMPUTE);
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, light_compute_pipe.handle());
    const PushConstants push{};
    vkCmdPushConstants(c, deferred_pipeline_layout.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push),
                       &push);
    vkCmdDispatch(c, (width + 7) / 8, (height + 7) / 8, 1);
  }

  void record_deferred_lighting(VkCommandBuffer c) {
    if (options.deferred_lighting == DeferredLighting::kCompute) {
      record_compute_lighting(c);
      return;
    }
    prepare_light_rendering(c);
    begin_light_rendering(c);
    const VkPipelineLayout layout = deferred_pipeline_layout.handle();
    bind_gbuffer_sets(c, VK_PIPELINE_BIND_POINT_GRAPHICS);
    VkDeviceSize offset = 0;
    VkBuffer vb = sphere_vertices.handle();
    vkCmdBindVertexBuffers(c, 0, 1, &vb, &offset);
    vkCmdBindIndexBuffer(c, sphere_indices.handle(), 0, VK_INDEX_TYPE_UINT32);
    for (size_t i = 0; i < lights.size(); ++i) {
      if (options.single_light >= 0 && static_cast<int>(i) != options.single_light) continue;
      const Light& l = lights[i];
      if (!lit_in_real_time(l)) continue;
      PushConstants push{};
      push.light_index = static_cast<int>(i);
      const bool volume = l.type != LightType::kDirectional && l.range > 0.0f;
      if (volume) {
        VkClearAttachment clear{VK_IMAGE_ASPECT_STENCIL_BIT, 0, {}};
        clear.clearValue.depthStencil = {1.0f, 0};
        VkClearRect rect{{{0, 0}, {width, height}}, 0, 1};
        vkCmdClearAttachments(c, 1, &clear, 1, &rect);
        push.view_index = 0;
        vkCmdPushConstants(c, layout, VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
        vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, light_stencil_pipe.handle());
        vkCmdSetStencilReference(c, VK_STENCIL_FACE_FRONT_AND_BACK, 0);
        vkCmdDrawIndexed(c, sphere_index_count, 1, 0, 0, 0);
        vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, light_volume_pipe.handle());
        vkCmdSetStencilReference(c, VK_STENCIL_FACE_FRONT_AND_BACK, 0);
        vkCmdDrawIndexed(c, sphere_index_count, 1, 0, 0, 0);
      } else {
        push.view_index = 1;
        vkCmdPushConstants(c, layout, VK_SHADER_STAGE_ALL, 0, sizeof(push), &push);
        vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, light_fullscreen_pipe.handle());
        vkCmdDraw(c, 3, 1, 0, 0);
      }
    }
    vkCmdEndRendering(c);
  }

  // Stencil shadows, forward or deferred: per light, the z-fail count of its volumes against
  // the depth buffer, then the light added where the count is 0 — the scene again with depth
  // LESS_OR_EQUAL (forward) or one full-screen pass over the G-buffer (deferred).
  void record_volume_lighting(VkCommandBuffer c) {
    prepare_light_rendering(c);
    for (size_t i = 0; i < lights.size(); ++i) {
      if (options.single_light >= 0 && static_cast<int>(i) != options.single_light) continue;
      if (!lit_in_real_time(lights[i])) continue;
      const uint32_t stencil_scope = timer.begin(c, "stencil_volumes");
      begin_light_rendering(c);
      const VkRect2D scissor = light_scissor(lights[i], scene.bounds(), view_proj, width, height);
      vkCmdSetScissor(c, 0, 1, &scissor);
      stencil_shadows->record_stencil(c, frame_set, i);
      timer.end(c, stencil_scope);
      const uint32_t light_scope = timer.begin(c, "volume_lighting");
      PushConstants push{};
      push.light_index = static_cast<int>(i);
      if (g_albedo) {
        bind_gbuffer_sets(c, VK_PIPELINE_BIND_POINT_GRAPHICS);
        vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_GRAPHICS, volume_fullscreen.handle());
        vkCmdSetStencilReference(c, VK_STENCIL_FACE_FRONT_AND_BACK, 0);
        push.view_index = 1;  // deferred_light.vert: the full-screen triangle
        vkCmdPushConstants(c, deferred_pipeline_layout.handle(), VK_SHADER_STAGE_ALL, 0,
                           sizeof(push), &push);
        vkCmdDraw(c, 3, 1, 0, 0);
      } else {
        bind_scene(c, volume_light.handle());
        vkCmdSetStencilReference(c, VK_STENCIL_FACE_FRONT_AND_BACK, 0);
        push.pad = 2;  // forward.frag: only this light, no shadow-map lookup
        draw_scene(c, push, true);
      }
      vkCmdEndRendering(c);
      timer.end(c, light_scope);
    }
  }

  void record_luminance(VkCommandBuffer c) {
    hdr.transition(c, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                   VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    // The previous frame's tone map read the buffer; the write below must wait for it.
    gpu::memory_barrier(c, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_READ_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_COMPUTE, tonemap_pipeline_layout.handle(), 0,
                            1, &tonemap_set, 0, nullptr);
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, luminance_pipe.handle());
    vkCmdDispatch(c, tiles_x, tiles_y, 1);
    gpu::memory_barrier(c, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, reduce_pipe.handle());
    const uint32_t push[2] = {tiles_x * tiles_y, width * height};
    vkCmdPushConstants(c, tonemap_pipeline_layout.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push),
                       push);
    vkCmdDispatch(c, 1, 1, 1);
    gpu::memory_barrier(
        c, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
  }

  // Bright pass into A (half resolution), Gaussian A → B horizontally, B → A vertically.
  void record_bloom(VkCommandBuffer c) {
    hdr.transition(c, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                   VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    const uint32_t bw = bloom_a.desc().width, bh = bloom_a.desc().height;
    struct {
      float dx, dy, threshold;
      int32_t radius;
    } push{0.0f, 0.0f, options.bloom_threshold, 8};
    GpuImage* dst[3] = {&bloom_a, &bloom_b, &bloom_a};
    GpuImage* src[3] = {&hdr, &bloom_a, &bloom_b};
    for (int k = 0; k < 3; ++k) {
      if (k > 0)
        src[k]->transition(c, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                           VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                           VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
      dst[k]->transition(c, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                         VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
      vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE,
                        k == 0 ? bloom_bright.handle() : bloom_blur.handle());
      vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_COMPUTE, bloom_pipeline_layout.handle(), 0,
                              1, &bloom_sets[k], 0, nullptr);
      push.dx = k == 1 ? 1.0f : 0.0f;
      push.dy = k == 2 ? 1.0f : 0.0f;
      vkCmdPushConstants(c, bloom_pipeline_layout.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push),
                         &push);
      vkCmdDispatch(c, (bw + 15) / 16, (bh + 15) / 16, 1);
    }
    bloom_a.transition(c, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                       VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
  }

  void record_tonemap(VkCommandBuffer c) {
    hdr.transition(c, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                   VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    ldr.transition(c, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                   VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    struct {
      int32_t mapper, auto_exposure;
      float exposure, key;
      uint32_t avg_index;
      float bloom_strength;
    } push{static_cast<int32_t>(options.tone_mapper),
           options.auto_exposure ? 1 : 0,
           options.exposure,
           options.key,
           tiles_x * tiles_y,
           bloom_a ? options.bloom_strength : 0.0f};
    vkCmdBindDescriptorSets(c, VK_PIPELINE_BIND_POINT_COMPUTE, tonemap_pipeline_layout.handle(), 0,
                            1, &tonemap_set, 0, nullptr);
    vkCmdBindPipeline(c, VK_PIPELINE_BIND_POINT_COMPUTE, tonemap_pipe.handle());
    vkCmdPushConstants(c, tonemap_pipeline_layout.handle(), VK_SHADER_STAGE_ALL, 0, sizeof(push),
                       &push);
    vkCmdDispatch(c, tiles_x, tiles_y, 1);
  }

  // Interim wiring (the technique interface replaces it): passes without declared
  // resources, their own transitions, phases in today's order.
  void add(const std::string& name, Phase phase, Schedule schedule,
           std::function<void(VkCommandBuffer)> record, int nested = 0) {
    PassDesc p;
    p.name = name;
    p.technique = "renderer";
    p.phase = phase;
    p.schedule = schedule;
    p.nested_scopes = nested;
    p.record = [record](PassContext& ctx) { record(ctx.cmd()); };
    graph.add_pass(std::move(p));
  }

  Schedule shadow_schedule() const {
    const int period = options.shadow_update_period;
    const Changes changes = kLightsChanged | kParametersChanged;
    return period > 0 ? Schedule::every_n(period, 0, changes) : Schedule::on_change(changes);
  }

  void build_graph() {
    if (cascades)
      add("cascades", Phase::kShadows, Schedule::every_frame(),
          [this](VkCommandBuffer c) { record_cascades(c); });
    if (shadow_cubes || spot_maps)
      add("shadow_maps", Phase::kShadows, shadow_schedule(),
          [this](VkCommandBuffer c) { record_shadow_maps(c); });
    if (stencil_shadows && stencil_shadows->source() == SilhouetteSource::kGpu)
      add("silhouettes", Phase::kShadows, shadow_schedule(), [this](VkCommandBuffer c) {
        stencil_shadows->record_extraction(c, lights, options.volume_back_faces);
      });
    if (g_albedo) {
      add("gbuffer", Phase::kGeometry, Schedule::every_frame(),
          [this](VkCommandBuffer c) { record_gbuffer(c); });
      // With stencil shadows the per-light volume lighting below takes its place.
      if (!volumes())
        add("lighting", Phase::kLighting, Schedule::every_frame(),
            [this](VkCommandBuffer c) { record_deferred_lighting(c); });
    } else {
      add("forward", Phase::kGeometry, Schedule::every_frame(),
          [this](VkCommandBuffer c) { record_forward(c); });
    }
    if (stencil_shadows)
      add(
          "shadow_volumes", Phase::kLighting, Schedule::every_frame(),
          [this](VkCommandBuffer c) { record_volume_lighting(c); },
          2 * static_cast<int>(lights.size()));
    add("luminance", Phase::kPost, Schedule::every_frame(),
        [this](VkCommandBuffer c) { record_luminance(c); });
    if (bloom_a)
      add("bloom", Phase::kPost, Schedule::every_frame(),
          [this](VkCommandBuffer c) { record_bloom(c); });
    add("tonemap", Phase::kDisplay, Schedule::every_frame(),
        [this](VkCommandBuffer c) { record_tonemap(c); });
    graph.compile();
  }

  void write_frame_uniforms(const Camera& camera) {
    FrameUniforms u{};
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    const Bounds3 b = scene.bounds();
    const float dist = glm::length(camera.position - b.center());
    const float far_plane = std::max(dist + b.diagonal(), 1e-3f) * 1.01f;
    // 1e-3: float depth then resolves ~1e-4 of the distance at 2 m in a 4 m scene, well
    // below the shadow-volume cap offset.
    const float near_plane = far_plane * 1e-3f;
    u.view = camera.view_matrix();
    u.proj = camera.projection_matrix(aspect, near_plane, far_plane);
    u.view_proj = u.proj * u.view;
    view_proj = u.view_proj;
    u.inv_view_proj = glm::inverse(u.view_proj);
    u.camera_pos = vec4(camera.position, 0.0f);
    u.ambient = vec4(options.ambient, 0.0f);
    u.counts =
        glm::ivec4(static_cast<int>(lights.size()), options.half_lambert ? 1 : 0,
                   shadow_cubes || spot_maps || cascades ? static_cast<int>(options.shadows) : 0,
                   options.pcf_taps);
    u.shadow_config = vec4(options.shadow_bias, options.pcf_radius, options.vsm_tau, 1e-7f);
    u.options =
        glm::ivec4(options.single_light, static_cast<int>(lightmap_info.kind), prt ? 1 : 0, 0);
    if (prt) {
      const vec3 centre = scene.bounds().center();
      for (const Light& l : lights) {
        vec3 w;
        Color radiance;
        if (l.type == LightType::kDirectional) {
          w = -glm::normalize(l.direction);
          radiance = l.irradiance;
        } else if (l.type == LightType::kPoint || l.type == LightType::kSpot) {
          const vec3 to = l.position - centre;
          const float d2 = std::max(glm::dot(to, to), 1e-12f);
          w = to / std::sqrt(d2);
          radiance = l.intensity / d2;
          if (l.cosine_falloff)
            radiance *= std::max(-glm::dot(w, glm::normalize(l.direction)), 0.0f);
        } else {
          continue;
        }
        const float y[4] = {0.282095f, 0.488603f * w.y, 0.488603f * w.z, 0.488603f * w.x};
        for (int k = 0; k < 4; ++k) u.prt_light[k] += vec4(radiance * y[k], 0.0f);
      }
    }
    u.ambient.w = lightmap_info.intensity;
    if (cascades) u.cascade_splits = update_cascades(camera, aspect, near_plane, far_plane);
    u.extent = vec4(static_cast<float>(width), static_cast<float>(height),
                    1.0f / static_cast<float>(width), 1.0f / static_cast<float>(height));
    frame_ubo.write(&u, sizeof(u));
  }

  void render(const Camera& camera) {
    write_frame_uniforms(camera);
    silhouette_ms = -1.0;
    const int period = options.shadow_update_period;
    if (stencil_shadows && stencil_shadows->source() == SilhouetteSource::kCpu &&
        (volumes_dirty || (period > 0 && frame_index % static_cast<uint64_t>(period) == 0))) {
      silhouette_ms = stencil_shadows->build_on_cpu(lights, options.volume_back_faces);
      volumes_dirty = false;
    }
    timer.reserve(graph.timer_scopes());
    ILLUM_VK(vkResetCommandBuffer(cmd, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    ILLUM_VK(vkBeginCommandBuffer(cmd, &begin));
    timer.reset(cmd);
    graph.execute(cmd, frame_index++, &timer);
    ILLUM_VK(vkEndCommandBuffer(cmd));
    VkCommandBufferSubmitInfo cb{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cb.commandBuffer = cmd;
    VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    submit.commandBufferInfoCount = 1;
    submit.pCommandBufferInfos = &cb;
    ILLUM_VK(vkQueueSubmit2(context.queue(), 1, &submit, fence));
    ILLUM_VK(vkWaitForFences(context.device(), 1, &fence, VK_TRUE, UINT64_MAX));
    ILLUM_VK(vkResetFences(context.device(), 1, &fence));
    // Per-light scopes nest inside their pass: report one sum per name and depth.
    times.clear();
    for (const gpu::PassTime& t : timer.resolve()) {
      auto it = std::find_if(times.begin(), times.end(), [&](const gpu::PassTime& x) {
        return x.name == t.name && x.depth == t.depth;
      });
      if (it == times.end())
        times.push_back(t);
      else
        it->ms += t.ms;
    }
    if (silhouette_ms >= 0.0) times.push_back({"cpu:silhouettes", silhouette_ms});
  }
};

Renderer::Renderer(gpu::Context& context, const Scene& scene, const RendererOptions& options) {
  // Before anything is uploaded: Impl's members build GPU objects from these values.
  check_renderer_options(options);
  check_realtime_input(scene, options);
  impl_ = std::make_unique<Impl>(context, scene, options);
}

Renderer::~Renderer() = default;

void Renderer::render(const Camera& camera) {
  check_camera(camera);
  impl_->render(camera);
}

const std::vector<gpu::PassTime>& Renderer::pass_times() const {
  return impl_->times;
}

std::vector<std::string> Renderer::pass_order() const {
  return impl_->graph.order();
}

Image Renderer::hdr() {
  return impl_->hdr.readback();
}

float Renderer::log_average_luminance() {
  Impl& m = *impl_;
  // luminance_reduce.comp leaves L_avg after the tile partials.
  const VkDeviceSize offset = VkDeviceSize(m.tiles_x) * m.tiles_y * sizeof(float);
  gpu::Buffer staging(m.context, sizeof(float), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                      gpu::MemoryUsage::kReadback);
  m.context.immediate([&](VkCommandBuffer c) {
    gpu::memory_barrier(c, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                        VK_ACCESS_2_TRANSFER_READ_BIT);
    const VkBufferCopy copy{offset, 0, sizeof(float)};
    vkCmdCopyBuffer(c, m.luminance.handle(), staging.handle(), 1, &copy);
    gpu::memory_barrier(c, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  });
  float value = 0.0f;
  staging.read(&value, sizeof(value));
  return value;
}

gpu::GpuImage& Renderer::output_image() {
  return impl_->ldr;
}

Image Renderer::ldr() {
  Image img = impl_->ldr.readback();
  for (size_t i = 0; i < img.pixel_count(); ++i)
    for (int k = 0; k < 3; ++k) img.data()[i * 4 + k] = srgb_decode(img.data()[i * 4 + k]);
  return img;
}

const RendererOptions& Renderer::options() const {
  return impl_->options;
}

void Renderer::set_lightmap(const Lightmap& lightmap) {
  const size_t expected = lightmap.kind == LightmapKind::kPlain  ? 1
                          : lightmap.kind == LightmapKind::kRnm  ? 3
                          : lightmap.kind == LightmapKind::kShL1 ? 4
                                                                 : 0;
  if (lightmap.layers.size() != expected)
    throw Error(fmt::format("light-map: {} layers given, this kind needs {}",
                            lightmap.layers.size(), expected));
  Impl& m = *impl_;
  m.context.wait_idle();
  m.lightmap_info = lightmap;
  m.lightmap_info.layers.clear();
  VkImageView view = m.dummy_array.view();
  if (expected > 0) {
    const Image& first = lightmap.layers[0];
    gpu::ImageDesc d;
    d.width = static_cast<uint32_t>(first.width());
    d.height = static_cast<uint32_t>(first.height());
    d.layers = static_cast<uint32_t>(expected);
    d.array = true;
    d.format = VK_FORMAT_R16G16B16A16_SFLOAT;  // signed: SH coefficients can be negative
    d.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    m.lightmap_image = GpuImage(m.context, d);
    for (size_t l = 0; l < expected; ++l) {
      if (lightmap.layers[l].width() != first.width() ||
          lightmap.layers[l].height() != first.height())
        throw Error("light-map: all layers must have the same size");
      m.lightmap_image.upload(lightmap.layers[l], static_cast<uint32_t>(l));
    }
    view = m.lightmap_image.view();
  }
  gpu::DescriptorWriter()
      .image(m.frame_set, 6, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, view,
             m.clamp_linear.handle(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)
      .commit(m.context.device());
}

void Renderer::set_ambient_cubes(const AmbientCubeGrid& grid) {
  const glm::ivec3 n = grid.size;
  if (n.x < 1 || n.y < 1 || n.z < 1 ||
      grid.cubes.size() != static_cast<size_t>(n.x) * n.y * n.z * 6)
    throw Error(fmt::format("ambient cubes: {} values for a {}×{}×{} grid (need 6 per probe)",
                            grid.cubes.size(), n.x, n.y, n.z));
  Impl& m = *impl_;
  m.context.wait_idle();
  const Scene& scene = m.scene.scene();
  std::vector<vec4> data;
  std::fill(m.draw_cube.begin(), m.draw_cube.end(), 0);
  auto at = [&](int x, int y, int z, int f) {
    return grid.cubes[((static_cast<size_t>(z) * n.y + y) * n.x + x) * 6 + f];
  };
  for (int inst : grid.instances) {
    if (inst < 0 || static_cast<size_t>(inst) >= scene.instances.size())
      throw Error(fmt::format("ambient cubes: instance {} does not exist", inst));
    const Instance& in = scene.instances[static_cast<size_t>(inst)];
    Bounds3 b;
    for (const vec3& p : scene.meshes[static_cast<size_t>(in.mesh)].positions)
      b.extend(vec3(in.transform * vec4(p, 1.0f)));
    const vec3 g = glm::clamp((b.center() - grid.origin) / grid.spacing, vec3(0.0f), vec3(n - 1));
    const glm::ivec3 i0 = glm::min(glm::ivec3(glm::floor(g)), n - 1);
    const glm::ivec3 i1 = glm::min(i0 + 1, n - 1);
    const vec3 t = g - vec3(i0);
    const int cube = static_cast<int>(data.size() / 6);
    for (int f = 0; f < 6; ++f) {
      Color c(0.0f);
      for (int k = 0; k < 8; ++k) {
        const int x = k & 1 ? i1.x : i0.x, y = k & 2 ? i1.y : i0.y, z = k & 4 ? i1.z : i0.z;
        const float w = (k & 1 ? t.x : 1 - t.x) * (k & 2 ? t.y : 1 - t.y) * (k & 4 ? t.z : 1 - t.z);
        c += w * at(x, y, z, f);
      }
      data.emplace_back(c, 0.0f);
    }
    for (size_t di = 0; di < m.scene.draws().size(); ++di)
      if (m.scene.draw_instances()[di] == inst) m.draw_cube[di] = cube + 1;
  }
  if (data.empty()) data.resize(6, vec4(0.0f));
  m.ambient_cubes = gpu::Buffer(m.context, data.size() * sizeof(vec4),
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::kUpload);
  m.ambient_cubes.write(data.data(), data.size() * sizeof(vec4));
  gpu::DescriptorWriter()
      .buffer(m.frame_set, 7, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, m.ambient_cubes.handle())
      .commit(m.context.device());
}

void Renderer::set_prt_transfer(const std::vector<glm::vec4>& transfer) {
  Impl& m = *impl_;
  size_t vertices = 0;
  for (const Mesh& mesh : m.scene.scene().meshes) vertices += mesh.positions.size();
  if (transfer.size() != vertices)
    throw Error(fmt::format("PRT: {} transfer vectors for {} vertices", transfer.size(), vertices));
  if (m.options.technique != Technique::kForward)
    throw Error("PRT display needs the forward technique");
  m.context.wait_idle();
  m.prt_transfer = gpu::Buffer(m.context, std::max<size_t>(1, transfer.size()) * sizeof(vec4),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::kUpload);
  if (!transfer.empty()) m.prt_transfer.write(transfer.data(), transfer.size() * sizeof(vec4));
  gpu::DescriptorWriter()
      .buffer(m.frame_set, 8, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, m.prt_transfer.handle())
      .commit(m.context.device());
  m.prt = true;
}

bool Renderer::set_options(const RendererOptions& o) {
  check_renderer_options(o);
  check_single_light(o, impl_->lights.size());
  Impl& m = *impl_;
  const RendererOptions& c = m.options;
  if (o.width != c.width || o.height != c.height || o.technique != c.technique ||
      o.shadows != c.shadows || o.shadow_resolution != c.shadow_resolution ||
      o.shadow_update_period != c.shadow_update_period ||
      (o.bloom_strength > 0.0f) != (c.bloom_strength > 0.0f) ||
      o.deferred_lighting != c.deferred_lighting || o.silhouettes != c.silhouettes)
    return false;
  // The bias also offsets cascade rendering; back-face volumes change the geometry.
  if (o.shadow_bias != c.shadow_bias) m.graph.notify(kParametersChanged, "renderer");
  if (o.volume_back_faces != c.volume_back_faces) m.invalidate_volumes();
  m.options = o;
  return true;
}

void Renderer::update_lights(const std::vector<Light>& lights) {
  ILLUM_CHECK(lights.size() == impl_->lights.size(), "update_lights cannot change the light count");
  check_realtime_lights(lights);
  impl_->context.wait_idle();
  impl_->lights = lights;
  impl_->upload_lights();
  impl_->graph.notify(kLightsChanged);
  impl_->volumes_dirty = true;
}

}  // namespace illum::realtime
