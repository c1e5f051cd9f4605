// Shadow maps (map: PCF, vsm: variance shadow maps) and the "none" method.
//
// A cube of distance/far for every point light and every spot wider than 60° (one cube-map
// array), one 2-D perspective map for every other spot (frustum = the cone widened by 4°,
// a 2-D array), and 4 cascaded shadow maps of the first directional light (S001 §4.2.1).
// Cube faces and spot maps are views of the "shadow_maps" pass: re-rendered when the lights
// change, every N frames, or k of them a frame in turn (round-robin); cascades follow the
// camera every frame. The lighting passes read them through this method's set (slot 3,
// shaders/shadow_set.glsl).
#include <algorithm>
#include <cmath>
#include <limits>

#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/scene_draw.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

// Shadow maps hold distance/far and, for VSM only, its square: PCF needs half the bytes.
// PCF's cascades are the depth buffer itself (an orthographic depth is the distance along
// the light over the view's depth range): no colour target, an empty fragment stage, and
// 16 bits by default (`map.cascade_depth`): an orthographic depth is linear, so d16 stores
// it to 1/65535 of the cascade's depth range everywhere — 1/13 of the default bias — and
// the H200 writes and tests it faster (cascades 0.345 → 0.286 ms at Sibenik 1080p,
// bench/results/raster.md#design-choices). The lookup's normal offset alone (1.5 texels)
// covers that rounding (at most a step): the splits and the depth range both follow the
// scene's diagonal, so cascade 0's half-width is a fixed part of its depth range — Sibenik:
// 13.5 of 166 m, an offset of 31 steps at 512² and 1.9 at the 8192² maximum
// (ShadowAgreement's "no bias" cases check it; `cascade_depth=d32` where it matters).
constexpr VkFormat kVsmFormat = VK_FORMAT_R32G32_SFLOAT;
constexpr VkFormat kPcfFormat = VK_FORMAT_R32_SFLOAT;
constexpr VkFormat kShadowDepthFormat = VK_FORMAT_D32_SFLOAT;
constexpr int kCascades = 4;

class NoShadows final : public ShadowMethod {
 public:
  using ShadowMethod::ShadowMethod;
  void declare(FrameGraph&) override {}
};

class ShadowMaps final : public ShadowMethod {
 public:
  ShadowMaps(TechniqueContext& ctx, const TechniqueDecl& decl, bool vsm)
      : ShadowMethod(ctx, decl), vsm_(vsm), descriptors_(ctx.gpu) {
    resolution_ = static_cast<uint32_t>(param<int>("resolution"));
    if (!vsm_ && param<std::string>("cascade_depth") == "d16")
      cascade_depth_format_ = VK_FORMAT_D16_UNORM;
    update_period_ = param<int>("update_period");
    views_per_frame_ = param<int>("views_per_frame");
    const std::vector<Light>& lights = ctx.lights();
    for (size_t i = 0; i < lights.size(); ++i) {
      const Light& l = lights[i];
      if (l.type == LightType::kSpot && l.cone_half_angle <= kMaxSpotMapHalfAngle) {
        if (spot_lights_.size() < kMaxSpotMaps) spot_lights_.push_back(static_cast<int>(i));
      } else if (l.type == LightType::kPoint || l.type == LightType::kSpot) {
        if (cube_lights_.size() < kMaxShadowCubes) cube_lights_.push_back(static_cast<int>(i));
      }
    }
    for (size_t i = 0; i < lights.size() && cascade_light_ < 0; ++i)
      if (lights[i].type == LightType::kDirectional) cascade_light_ = static_cast<int>(i);

    const VkPipelineLayout layout = ctx.globals.default_layout();
    gpu::GraphicsPipelineDesc sh;
    sh.vertex_shader = "shadow_cube.vert";
    sh.fragment_shader = "shadow_cube.frag";
    sh.vertex_input = mesh_vertex_input(true);
    sh.cull = VK_CULL_MODE_NONE;
    sh.color_formats = {format()};
    sh.depth_format = kShadowDepthFormat;
    if (!cube_lights_.empty() || !spot_lights_.empty()) {
      radial_ = gpu::Pipeline(ctx.gpu, layout, sh);
      radial_count_ = CountingPipelines(ctx.gpu, layout, sh);
    }
    if (cascade_light_ >= 0) {
      if (vsm_) {
        sh.fragment_shader = "shadow_dir.frag";
      } else {
        sh.vertex_shader = "shadow_depth.vert";
        sh.fragment_shader = "depth_only.frag";  // empty: see the shader
        sh.color_formats = {};
      }
      sh.depth_clamp = ctx.gpu.depth_clamp();  // casters behind the cascade's near plane
      sh.depth_format = vsm_ ? kShadowDepthFormat : cascade_depth_format_;
      ortho_ = gpu::Pipeline(ctx.gpu, layout, sh);
      ortho_count_ = CountingPipelines(ctx.gpu, layout, sh);
    }
    const size_t views = 6 * cube_lights_.size() + spot_lights_.size() + kCascades;
    views_ = gpu::Buffer(ctx.gpu, views * sizeof(glm::mat4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                         gpu::MemoryUsage::kUpload);
    // The maps are drawn from the camera block (shadow_cube.vert reads views[push.view]); set 3
    // keeps the lookups' copy of each view × projection.
    block_views_ = ctx.globals.add_views(static_cast<uint32_t>(views));
    shadow_lights_ =
        gpu::Buffer(ctx.gpu, std::max<size_t>(1, lights.size()) * sizeof(GpuShadowLight),
                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::kUpload);
    uniforms_ = gpu::Buffer(ctx.gpu, sizeof(ShadowUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                            gpu::MemoryUsage::kUpload);
    set_ = descriptors_.allocate(ctx.globals.layout(kShadowSet));
  }

  int shading_slot() const override { return kShadowSet; }
  VkDescriptorSet shading_set() const override { return set_; }
  std::vector<std::string> shading_reads() const override {
    std::vector<std::string> reads;
    if (!cube_lights_.empty()) reads.push_back("shadow.cubes");
    if (!spot_lights_.empty()) reads.push_back("shadow.spots");
    if (cascade_light_ >= 0) reads.push_back("shadow.cascades");
    return reads;
  }

  void declare(FrameGraph& graph) override {
    auto map = [&](const char* name, uint32_t layers, bool cube, bool array, VkFormat f) {
      ResourceDesc r;
      r.name = name;
      r.width = r.height = resolution_;
      r.format = f;
      r.layers = layers;
      r.cube = r.cube_array = cube;
      r.array = array;
      r.extra_usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT;  // Renderer::read_resource
      graph.add_resource(r);
    };
    const bool radial = !cube_lights_.empty() || !spot_lights_.empty();
    if (!radial && cascade_light_ < 0) return;
    if (radial || vsm_) {
      ResourceDesc depth;
      depth.name = kViewDepth;
      depth.width = depth.height = resolution_;
      depth.format = kShadowDepthFormat;
      graph.add_resource(depth);
    }
    if (cascade_light_ >= 0) {
      map(kCascadeMaps, kCascades, false, false, cascade_format());
      PassDesc p;
      p.name = "cascades";
      p.technique = name();
      p.phase = Phase::kShadows;
      // Occlusion culling samples the depth between each view's two halves.
      const char* depth = vsm_ ? kViewDepth : kCascadeMaps;
      p.accesses = {{depth, kDepthAttachment}, {depth, kSampled, kComputeShader}};
      if (vsm_) p.accesses.push_back({kCascadeMaps, kColorAttachment});
      p.nested_scopes = 2 * kCascades;
      p.record = [this](PassContext& pass) {
        for (int k = 0; k < kCascades; ++k)
          render_view(pass, ortho_, ortho_count_, kCascadeMaps, static_cast<uint32_t>(k),
                      cascade_view_offset() + k, cascade_light_);
      };
      graph.add_pass(std::move(p));
    }
    if (!radial) return;
    PassDesc p;
    p.name = "shadow_maps";
    p.technique = name();
    p.phase = Phase::kShadows;
    if (!cube_lights_.empty()) {
      map("shadow.cubes", static_cast<uint32_t>(6 * cube_lights_.size()), true, false, format());
      p.accesses.push_back({"shadow.cubes", kColorAttachment});
    }
    if (!spot_lights_.empty()) {
      map("shadow.spots", static_cast<uint32_t>(spot_lights_.size()), false, true, format());
      p.accesses.push_back({"shadow.spots", kColorAttachment});
    }
    p.accesses.push_back({kViewDepth, kDepthAttachment});
    p.accesses.push_back({kViewDepth, kSampled, kComputeShader});
    // The maps depend on the lights and the geometry only (bias, PCF and τ are applied
    // when they are looked up).
    const Changes changes = kLightsChanged | kGeometryChanged;
    const int items = static_cast<int>(6 * cube_lights_.size() + spot_lights_.size());
    p.schedule = views_per_frame_ > 0 ? Schedule::round_robin(items, views_per_frame_, changes)
                 : update_period_ > 0 ? Schedule::every_n(update_period_, 0, changes)
                                      : Schedule::on_change(changes);
    p.schedule.items = items;
    p.nested_scopes = 2 * items;  // each view's occlusion culling, beside the pass's scope
    p.record = [this](PassContext& pass) {
      const size_t cube_views = 6 * cube_lights_.size();
      for (int v : pass.items()) {
        const size_t view = static_cast<size_t>(v);
        if (view < cube_views)
          render_view(pass, radial_, radial_count_, "shadow.cubes", static_cast<uint32_t>(view), v,
                      cube_lights_[view / 6]);
        else
          render_view(pass, radial_, radial_count_, "shadow.spots",
                      static_cast<uint32_t>(view - cube_views), v, spot_lights_[view - cube_views]);
      }
    };
    graph.add_pass(std::move(p));
  }

  void bind() override {
    FrameResources& r = ctx_.resources;
    const FrameGlobals& g = ctx_.globals;
    // PCF compares single texels; VSM filters the moments.
    const VkSampler sampler = vsm_ ? g.clamp_linear().handle() : g.nearest().handle();
    const auto ro = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    const auto cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    auto view = [&](const char* name, const gpu::GpuImage& dummy) {
      return r.has(name) ? r.image(name).view() : dummy.view();
    };
    // The frame graph leaves a sampled depth image read-only as a depth attachment.
    const VkImageLayout cascades_layout =
        r.has(kCascadeMaps) && is_depth_format(cascade_format())
            ? VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_STENCIL_ATTACHMENT_OPTIMAL
            : ro;
    gpu::DescriptorWriter()
        .buffer(set_, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, uniforms_.handle())
        .buffer(set_, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, views_.handle())
        .image(set_, 2, cis, view("shadow.cubes", g.dummy_cube()), sampler, ro)
        .image(set_, 3, cis, view(kCascadeMaps, g.dummy_array()), sampler, cascades_layout)
        .image(set_, 4, cis, view("shadow.spots", g.dummy_array()), sampler, ro)
        .buffer(set_, 5, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, shadow_lights_.handle())
        .commit(ctx_.gpu.device());
  }

  void update() override {
    const std::vector<Light>& lights = ctx_.lights();
    std::vector<GpuShadowLight> sl(std::max<size_t>(1, lights.size()));
    for (size_t i = 0; i < lights.size(); ++i) {
      sl[i].slot = glm::ivec4(-1, 0, 0, 0);
      sl[i].params = vec4(shadow_far(lights[i]), 0.0f, 0.0f, 0.0f);
    }
    std::vector<glm::mat4> views;
    std::vector<FrameView> cameras;  // the same views for the camera block
    for (size_t s = 0; s < cube_lights_.size(); ++s) {
      const Light& l = lights[static_cast<size_t>(cube_lights_[s])];
      GpuShadowLight& g = sl[static_cast<size_t>(cube_lights_[s])];
      g.slot = glm::ivec4(static_cast<int>(s), static_cast<int>(views.size()), 6, 0);
      const float far_plane = g.params.x;
      // No y flip: Vulkan and OpenGL both map NDC y = −1 to the first row in memory, so the
      // OpenGL cube-face conventions (face axes and up vectors) apply unchanged.
      const mat4 proj = glm::perspectiveRH_ZO(radians(90.0f), 1.0f, far_plane * 1e-4f, far_plane);
      for (int f = 0; f < 6; ++f) {
        cameras.push_back(light_view(cube_face_view(l.position, f), proj, l.position,
                                     far_plane * 1e-4f, far_plane));
        views.push_back(cameras.back().view_proj);
      }
    }
    for (size_t s = 0; s < spot_lights_.size(); ++s) {
      const Light& l = lights[static_cast<size_t>(spot_lights_[s])];
      GpuShadowLight& g = sl[static_cast<size_t>(spot_lights_[s])];
      g.slot = glm::ivec4(static_cast<int>(s), static_cast<int>(views.size()), 1, 1);
      const float far_plane = g.params.x;
      // A few degrees beyond the cone so PCF taps and the normal offset stay on the map.
      const float half_fov = std::min(l.cone_half_angle + radians(4.0f), radians(80.0f));
      g.params.y = std::tan(half_fov);
      const vec3 dir = glm::normalize(l.direction);
      const vec3 up = std::abs(dir.y) > 0.99f ? vec3(1, 0, 0) : vec3(0, 1, 0);
      const mat4 proj = glm::perspectiveRH_ZO(2.0f * half_fov, 1.0f, far_plane * 1e-4f, far_plane);
      cameras.push_back(light_view(glm::lookAtRH(l.position, l.position + dir, up), proj,
                                   l.position, far_plane * 1e-4f, far_plane));
      views.push_back(cameras.back().view_proj);
    }
    ShadowUniforms u{};
    // PCF reads taps, bias and radius; VSM τ and the minimum variance.
    u.config = glm::ivec4(static_cast<int>(vsm_ ? ShadowLookup::kVsm : ShadowLookup::kMap),
                          vsm_ ? 0 : param<int>("pcf_taps"), 0, 0);
    u.params = vec4(vsm_ ? 0.0f : param<float>("bias"), vsm_ ? 0.0f : param<float>("pcf_radius"),
                    vsm_ ? param<float>("tau") : 0.0f, 1e-7f);
    if (cascade_light_ >= 0) {
      GpuShadowLight& g = sl[static_cast<size_t>(cascade_light_)];
      glm::vec4 half_widths(0.0f);
      cascade_receivers_.clear();
      u.cascade_splits = update_cascades(&views, &cameras, &half_widths, &cascade_receivers_);
      g.slot = glm::ivec4(-1, static_cast<int>(views.size()) - kCascades, kCascades, 0);
      g.params = half_widths;
    }
    for (size_t k = 0; k < cameras.size(); ++k)
      ctx_.globals.set_view(block_views_[static_cast<uint32_t>(k)], cameras[k],
                            {resolution_, resolution_});
    if (views.empty()) views.emplace_back(1.0f);
    views_.write(views.data(), views.size() * sizeof(glm::mat4));
    view_matrices_ = std::move(views);
    shadow_lights_.write(sl.data(), sl.size() * sizeof(GpuShadowLight));
    uniforms_.write(&u, sizeof(u));
  }

 private:
  static constexpr const char* kCascadeMaps = "shadow.cascades";
  // The depth buffer the cube faces and spot maps (and VSM's cascades) are rendered with.
  static constexpr const char* kViewDepth = "shadow.depth";
  VkFormat format() const { return vsm_ ? kVsmFormat : kPcfFormat; }
  VkFormat cascade_format() const { return vsm_ ? kVsmFormat : cascade_depth_format_; }
  int cascade_view_offset() const {
    return static_cast<int>(6 * cube_lights_.size() + spot_lights_.size());
  }
  float shadow_far(const Light& l) const {
    if (l.range > 0.0f) return l.range;
    const Bounds3 b = ctx_.scene.bounds();
    return glm::length(l.position - b.center()) + b.diagonal() + 1e-3f;
  }

  // One view of the scene into one layer of `target` (shadow_cube: radial distance / far,
  // shadow_dir: orthographic depth and its square for VSM; PCF's cascades: the depth layer).
  void render_view(PassContext& pass, const gpu::Pipeline& pipeline,
                   const CountingPipelines& counter, const char* target, uint32_t layer, int view,
                   int light) {
    const bool depth_map = is_depth_format(ctx_.resources.image(target).desc().format);
    DrawTargets t;
    if (depth_map) {
      t.depth = ctx_.resources.image(target).layer_view(layer);
      t.depth_resource = target;
      t.depth_layer = layer;
    } else {
      t.colors = {
          {ctx_.resources.image(target).layer_view(layer), true, {{1.0f, 1.0f, 0.0f, 0.0f}}}};
      t.depth = ctx_.resources.image(kViewDepth).view();
      t.depth_resource = kViewDepth;
      t.store_depth = false;
    }
    // The last view's depth test (or its occlusion culling) is done with it.
    pass.use(t.depth_resource, kDepthAttachment);
    t.extent = {resolution_, resolution_};
    SceneView v;
    v.view = static_cast<int>(block_views_[static_cast<uint32_t>(view)]);
    v.light_index = light;
    v.per_draw = false;
    v.cull = view_matrices_.at(static_cast<size_t>(view));
    if (depth_map) v.clip_from_world = v.cull;
    v.cull_depth = &pipeline != &ortho_;  // the cascades clamp casters behind their near plane
    if (&pipeline == &ortho_ && param<bool>("caster_culling"))
      v.receivers = cascade_receivers_.at(static_cast<size_t>(view - cascade_view_offset()));
    v.front_to_back = true;
    if (&pipeline == &ortho_) v.depth_key = SceneView::DepthKey::kCentre;  // cluster_depth
    v.occlusion = SceneView::Occlusion::kTwoPhase;
    v.occlusion_key = "shadow." + std::to_string(view);  // every view keeps its own history
    using D = gpu::RasterFill::Depth;
    std::vector<VkFormat> colors;
    if (!depth_map) colors = {format()};
    const VkFormat depth = ctx_.resources.image(t.depth_resource).desc().format;
    ctx_.drawer.render_counted(
        pass, t, pipeline, counter, ctx_.globals.default_layout(),
        {ctx_.globals.neutral_set(kPipelineSet), set_, ctx_.globals.neutral_set(kInputsSet)}, v,
        {resolution_, resolution_, colors, depth, D::kWrite},
        {resolution_, resolution_, colors, depth, D::kReject});
  }

  // The part of a cascade's map its lookups can read, as a clip transform for
  // SceneView::receivers: the light-space box of its slice of the camera's frustum (`corners`,
  // world space; `clip` the cascade's view, `texel` and `half_width` its texel and half side,
  // `depth` its depth range in world units), widened by the lookup's reach — the normal offset
  // (1.5 texels), the PCF radius and one texel for the nearest texel's rounding (VSM: its
  // bilinear footprint) — on every side. A caster outside it laterally writes no texel a
  // lookup reads; with PCF one wholly beyond its far side (farther from the light than every
  // receiver) changes no comparison either (removing it only raises the stored depth where it
  // was the nearest, and it was behind the receiver there). VSM's filtered moments do mix
  // such casters in, so VSM culls laterally only.
  glm::mat4 receiver_region(const glm::mat4& clip, const vec3 corners[8], float texel,
                            float half_width, float depth) const {
    const float reach_texels = 2.5f + (vsm_ ? 0.0f : param<float>("pcf_radius"));
    const float reach = reach_texels * texel;  // world units
    vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
    for (int c = 0; c < 8; ++c) {
      const vec3 p = vec3(clip * vec4(corners[c], 1.0f));
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    // Orthographic: a world distance d is d / half_width in x and y, d / depth in z.
    const float pad_xy = reach / half_width, pad_z = reach / depth;
    lo -= vec3(pad_xy, pad_xy, 0.0f);
    hi += vec3(pad_xy, pad_xy, pad_z);
    const float z_far = vsm_ ? std::numeric_limits<float>::max() : std::max(hi.z, 1e-6f);
    // x, y: [lo, hi] → [−1, 1]; z: scaled by 1 / z_far, so only "beyond the far side" (z > 1)
    // culls and everything in front of the slice (z < 0 included: depth-clamped casters) stays.
    mat4 s(1.0f);
    s[0][0] = 2.0f / (hi.x - lo.x);
    s[1][1] = 2.0f / (hi.y - lo.y);
    s[2][2] = 1.0f / z_far;
    s[3][0] = -(hi.x + lo.x) / (hi.x - lo.x);
    s[3][1] = -(hi.y + lo.y) / (hi.y - lo.y);
    return s * clip;
  }

  // Cascaded shadow maps (S001 §4.2.1): the view frustum split between uniform and
  // logarithmic (λ = 0.5); each split's bounding sphere gets an orthographic light view,
  // snapped to whole texels so the maps do not shimmer as the camera moves. Appends the
  // cascades' matrices to `views` and the regions their lookups read to `receivers`; returns
  // the splits.
  glm::vec4 update_cascades(std::vector<glm::mat4>* views, std::vector<FrameView>* cameras,
                            glm::vec4* half_widths, std::vector<glm::mat4>* receivers) const {
    const FrameView& fv = ctx_.view();
    const Camera& camera = fv.camera;
    const float near_plane = fv.near_plane, aspect = fv.aspect;
    float far_plane = fv.far_plane;
    const Light& l = ctx_.lights()[static_cast<size_t>(cascade_light_)];
    const vec3 dir = glm::normalize(l.direction);
    const mat4 inv_view = glm::inverse(camera.view_matrix());
    const float tan_half = std::tan(0.5f * camera.fov_y);
    const float scene_extent = ctx_.scene.bounds().diagonal();
    // The splits divide the part of the view depth that can hold geometry: up to the scene's
    // farthest bounding-box corner (not the camera's far plane, which may lie far beyond it and
    // would stretch the first cascade over most of the scene). Rounded up to a quarter octave so
    // the cascades keep their size, and their texel grid, while the camera moves a little.
    float depth_max = near_plane;
    const Bounds3 b = ctx_.scene.bounds();
    for (int c = 0; c < 8; ++c) {
      const vec3 p((c & 1) ? b.max.x : b.min.x, (c & 2) ? b.max.y : b.min.y,
                   (c & 4) ? b.max.z : b.min.z);
      depth_max = std::max(depth_max, -(camera.view_matrix() * vec4(p, 1.0f)).z);
    }
    const float octaves =
        std::ceil(4.0f * std::log2(std::max(depth_max / near_plane, 2.0f))) / 4.0f;
    far_plane = std::min(far_plane, near_plane * std::exp2(octaves));
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
      const float texel = 2.0f * radius / static_cast<float>(resolution_);
      vec4 origin = view * vec4(center, 1.0f);
      const vec2 snapped = glm::floor(vec2(origin) / texel) * texel;
      view = glm::translate(mat4(1.0f), vec3(snapped - vec2(origin), 0.0f)) * view;
      const mat4 proj =
          glm::orthoRH_ZO(-radius, radius, -radius, radius, 0.0f, scene_extent + radius);
      // The eye of an orthographic view: where its view matrix puts the origin.
      cameras->push_back(
          light_view(view, proj, vec3(glm::inverse(view)[3]), 0.0f, scene_extent + radius));
      views->push_back(cameras->back().view_proj);
      (*half_widths)[k] = radius;
      receivers->push_back(receiver_region(proj * view, corners, texel, radius, scene_extent));
      prev = split;
    }
    return splits;
  }

  bool vsm_;
  uint32_t resolution_ = 512;
  VkFormat cascade_depth_format_ = kShadowDepthFormat;  // PCF's cascades: d32 or d16
  int update_period_ = 0, views_per_frame_ = 0;
  std::vector<int> cube_lights_;  // light index of each cube
  // Narrow spot lights get one 2-D perspective map (the cone's frustum) instead of 6 faces.
  std::vector<int> spot_lights_;
  int cascade_light_ = -1;
  gpu::Pipeline radial_, ortho_;
  CountingPipelines radial_count_, ortho_count_;
  gpu::Buffer views_, shadow_lights_, uniforms_;
  std::vector<glm::mat4> view_matrices_;      // views_'s contents, for culling on the CPU
  ViewSlots block_views_;                     // the same views in the camera block
  std::vector<glm::mat4> cascade_receivers_;  // receiver_region of each cascade
  gpu::DescriptorAllocator descriptors_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
};

// The parameters map and vsm share (each declares its own copy; the aliases set both).
std::vector<ParamDecl> map_params() {
  return {
      int_param("resolution", 512, 16, 8192, "side of a cube face, spot map or cascade (texels)")
          .structural()
          .aka("shadow_resolution")
          .slider(UiHint::kPowerOfTwo, 64, 4096),
      int_param("update_period", 0, 0, 1000000,
                "0: re-render the cube and spot maps only when the lights change; N: every N "
                "frames (cascades follow the camera every frame)")
          .structural()
          .aka("shadow_update_period")
          .slider(UiHint::kLinear, 0, 30),
      bool_param("caster_culling", true,
                 "cascades: draw only the clusters that can cast into the texels their lookups "
                 "read (the slice of the view frustum, widened by the lookup's reach); the "
                 "image does not change"),
      int_param("views_per_frame", 0, 0, 1000,
                "k > 0: re-render k cube faces or spot maps a frame in turn (round-robin) "
                "instead of all at once; all of them still when the lights change")
          .structural()
          .slider(UiHint::kLinear, 0, 12),
  };
}

}  // namespace

TechniqueDecl no_shadows_technique() {
  TechniqueDecl t;
  t.name = "none";
  t.kind = TechniqueKind::kShadowMethod;
  t.summary = "no shadows";
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<NoShadows>(ctx, *find_technique("none"));
  };
  return t;
}

TechniqueDecl shadow_map_technique() {
  TechniqueDecl t;
  t.name = "map";
  t.kind = TechniqueKind::kShadowMethod;
  t.summary =
      "shadow maps of distance/far: a cube per point light and wide spot, a 2-D map per spot up "
      "to 60°, 4 cascades for the first directional light; PCF with rotated Poisson taps";
  t.params = map_params();
  t.params.push_back(
      int_param("pcf_taps", 16, 1, 64, "PCF taps (1: hard shadows)").aka("pcf_taps"));
  t.params.push_back(float_param("pcf_radius", 1.5f, 0.0f, 64.0f, "PCF radius in texels")
                         .aka("pcf_radius")
                         .slider(UiHint::kLinear, 0, 8));
  t.params.push_back(
      float_param("bias", 0.002f, 0.0f, 1.0f, "depth bias relative to the light's far distance")
          .aka("shadow_bias")
          .slider(UiHint::kLogarithmic, 0, 0.02));
  t.params.push_back(enum_param("cascade_depth", "d16", {"d16", "d32"},
                                "the cascades' depth format: d16 stores the linear orthographic "
                                "depth to 1/65535 of a cascade's depth range")
                         .structural());
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<ShadowMaps>(ctx, *find_technique("map"), false);
  };
  return t;
}

TechniqueDecl vsm_technique() {
  TechniqueDecl t;
  t.name = "vsm";
  t.kind = TechniqueKind::kShadowMethod;
  t.summary =
      "variance shadow maps (S001 §4.2): the maps of `map` with the second moment, Chebyshev's "
      "bound with the light-bleeding threshold τ";
  t.params = map_params();
  t.params.push_back(float_param("tau", 0.2f, 0.0f, 0.99f,
                                 "light-bleeding threshold: [τ, 1] is remapped to [0, 1]")
                         .aka("vsm_tau"));
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<ShadowMaps>(ctx, *find_technique("vsm"), true);
  };
  return t;
}

}  // namespace illum::realtime
