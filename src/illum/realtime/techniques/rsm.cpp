// `rsm`: reflective shadow maps (Dachsbacher & Stamminger 2005; ALGORITHMS.md item 27). Per
// light, the scene drawn from the light's view(s) — a spot's cone as one perspective view (a
// cube when wider than kRsmMaxSpotHalfAngle), a point light's six cube faces, a directional
// light's orthographic box around the camera's view — into 2-D arrays of world position,
// normal and reflected flux, one layer per view, with the light table "rsm.views" saying which
// layers belong to which light (illum/realtime/rsm_views.h). It shades nothing itself: the
// light propagation volumes and VPLs inject from these maps.
//
// Flux per texel: Φ = I(ω)·Δω·ρ for point and spot lights, Δω the texel's exact solid angle
// (rsm_texel_solid_angle), so the texels of a light's views sum to the flux it sends into what
// they see, times the albedo; E·A·ρ for a directional light, A the texel's area on the light's
// plane (the box's side is fixed and its centre snapped to whole texels, so the map does not
// crawl as the camera moves).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "illum/core/error.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/rsm_views.h"
#include "illum/realtime/scene_draw.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

using rsm::kRsmMaxLayers;
using rsm::kRsmMaxSpotHalfAngle;
using rsm::kRsmViewCubeFace;
using rsm::kRsmViewOrthographic;
using rsm::kRsmViewPerspective;

constexpr VkFormat kPositionFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kNormalFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
// 32 bits: a texel's share of a light's flux is small (1/res² of it), below fp16's normal range
// for dim lights, and consumers sum many of them.
constexpr VkFormat kFluxFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

// One view of one light (a layer of every map).
struct LightView {
  int light = 0;
  int first_layer = 0;
  int layers = 1;
  int kind = kRsmViewPerspective;
  int face = 0;  // cube faces: 0..5
};

// −1 (every light) or the index of one of the frame's lights; the range check of the
// declaration cannot know how many lights the scene has.
int checked_lights(int index, size_t light_count) {
  if (index >= 0 && static_cast<size_t>(index) >= light_count)
    throw Error(
        fmt::format("-p rsm.lights={}: the scene has {} light(s) (-1: all)", index, light_count));
  return index;
}

class Rsm final : public Technique {
 public:
  Rsm(TechniqueContext& ctx, const TechniqueDecl& decl) : Technique(ctx, decl) {
    const int resolution = param<int>("resolution");
    if (resolution != 64 && resolution != 128 && resolution != 256)
      throw Error(fmt::format("-p rsm.resolution={}: one of 64, 128, 256", resolution));
    resolution_ = static_cast<uint32_t>(resolution);
    const std::vector<Light>& lights = ctx.lights();
    const int only = checked_lights(param<int>("lights"), lights.size());
    for (size_t i = 0; i < lights.size(); ++i) {
      if (only >= 0 && static_cast<int>(i) != only) continue;
      const Light& l = lights[i];
      LightView v;
      v.light = static_cast<int>(i);
      v.first_layer = static_cast<int>(views_.size());
      if (l.type == LightType::kDirectional) {
        v.kind = kRsmViewOrthographic;
        directional_ = true;
      } else if (l.type == LightType::kSpot && l.cone_half_angle <= radians(kRsmMaxSpotHalfAngle)) {
        v.kind = kRsmViewPerspective;
      } else if (l.type == LightType::kPoint || l.type == LightType::kSpot) {
        v.kind = kRsmViewCubeFace;
        v.layers = 6;
      } else {
        continue;
      }
      if (v.first_layer + v.layers > kRsmMaxLayers) break;  // rsm_views.h: left out
      for (int f = 0; f < v.layers; ++f) {
        v.face = f;
        views_.push_back(v);
      }
    }
    gpu::GraphicsPipelineDesc d;
    d.vertex_shader = "forward.vert";
    d.fragment_shader = "rsm.frag";
    d.vertex_input = mesh_vertex_input(false);
    d.cull = VK_CULL_MODE_NONE;  // scenes are two-sided
    d.color_formats = {kPositionFormat, kNormalFormat, kFluxFormat};
    d.depth_format = kDepthFormat;
    pipeline_ = gpu::Pipeline(ctx.gpu, ctx.globals.default_layout(), d);
    block_views_ = ctx.globals.add_views(static_cast<uint32_t>(std::max<size_t>(1, views_.size())));
    table_.resize(sizeof(rsm::RsmHeader) + layers() * sizeof(rsm::RsmView));
  }

  void declare(FrameGraph& graph) override {
    auto map = [&](const char* name, VkFormat format) {
      ResourceDesc r;
      r.name = name;
      r.width = r.height = resolution_;
      r.format = format;
      r.layers = layers();
      r.array = true;
      // Read back by tests, shown by -p debug.show=NAME:LAYER.
      r.extra_usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
      graph.add_resource(r);
    };
    map(rsm::kPosition, kPositionFormat);
    map(rsm::kNormal, kNormalFormat);
    map(rsm::kFlux, kFluxFormat);
    map(rsm::kDepth, kDepthFormat);
    ResourceDesc table;
    table.name = rsm::kViews;
    table.kind = ResourceDesc::Kind::kBuffer;
    table.bytes = table_.size();
    table.extra_usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    graph.add_resource(table);

    PassDesc p;
    p.name = "rsm";
    p.technique = name();
    p.phase = Phase::kShadows;
    p.accesses = {{rsm::kPosition, kColorAttachment},
                  {rsm::kNormal, kColorAttachment},
                  {rsm::kFlux, kColorAttachment},
                  {rsm::kDepth, kDepthAttachment},
                  {rsm::kViews, kTransferDst}};
    // Like the shadow maps: the maps depend on the lights and the geometry; a directional
    // light's box follows the camera.
    Changes changes = kLightsChanged | kGeometryChanged | kParametersChanged;
    if (directional_) changes |= kCameraChanged;
    const int period = param<int>("period");
    p.schedule = period > 0 ? Schedule::every_n(period, 0, changes) : Schedule::on_change(changes);
    p.record = [this](PassContext& pass) { record(pass); };
    graph.add_pass(std::move(p));
  }

  void bind() override {}

  void update() override {
    const std::vector<Light>& lights = ctx_.lights();
    rsm::RsmHeader header{};
    header.counts =
        glm::ivec4(static_cast<int>(views_.size()), static_cast<int>(resolution_), 0, 0);
    std::vector<rsm::RsmView> table(layers());
    cameras_.assign(layers(), FrameView{});
    for (size_t k = 0; k < views_.size(); ++k) {
      const LightView& lv = views_[k];
      const Light& l = lights.at(static_cast<size_t>(lv.light));
      if (lv.face == 0) ++header.counts.z;
      rsm::RsmView& t = table[k];
      float w = 0.0f;
      vec3 axis;
      if (lv.kind == kRsmViewOrthographic) {
        cameras_[k] = directional_view(l, &w);
        axis = glm::normalize(l.direction);
      } else {
        cameras_[k] = radial_view(l, lv, &w, &axis);
      }
      t.view_proj = cameras_[k].view_proj;
      t.inv_view_proj = cameras_[k].inv_view_proj;
      t.position_type = vec4(cameras_[k].camera.position, static_cast<float>(gpu_type(l)));
      t.direction = vec4(axis, w);
      t.info = glm::ivec4(lv.light, lv.first_layer, lv.layers, lv.kind);
      ctx_.globals.set_view(block_views_[static_cast<uint32_t>(k)], cameras_[k],
                            {resolution_, resolution_});
    }
    std::memcpy(table_.data(), &header, sizeof(header));
    std::memcpy(table_.data() + sizeof(header), table.data(), table.size() * sizeof(rsm::RsmView));
  }

 private:
  uint32_t layers() const { return static_cast<uint32_t>(std::max<size_t>(1, views_.size())); }

  // The type the GPU light table gives the light (common.glsl kLight*).
  static int gpu_type(const Light& l) {
    if (l.type == LightType::kDirectional) return 2;
    if (l.type == LightType::kSpot) return l.cosine_falloff ? 3 : 1;
    return 0;
  }

  float far_plane(const Light& l) const {
    if (l.range > 0.0f) return l.range;
    const Bounds3 b = ctx_.scene.bounds();
    return glm::length(l.position - b.center()) + b.diagonal() + 1e-3f;
  }

  // A spot's cone (the square frustum whose inscribed circle is the cone) or one cube face.
  FrameView radial_view(const Light& l, const LightView& lv, float* tan_half, vec3* axis) const {
    const float far = far_plane(l), near = far * 1e-4f;
    if (lv.kind == kRsmViewPerspective) {
      const vec3 dir = glm::normalize(l.direction);
      const vec3 up = std::abs(dir.y) > 0.99f ? vec3(1, 0, 0) : vec3(0, 1, 0);
      *tan_half = std::tan(l.cone_half_angle);
      *axis = dir;
      const mat4 proj = glm::perspectiveRH_ZO(2.0f * l.cone_half_angle, 1.0f, near, far);
      return light_view(glm::lookAtRH(l.position, l.position + dir, up), proj, l.position, near,
                        far);
    }
    // The cube faces of the shadow maps.
    *tan_half = 1.0f;
    *axis = cube_face_axis(lv.face);
    const mat4 proj = glm::perspectiveRH_ZO(radians(90.0f), 1.0f, near, far);
    return light_view(cube_face_view(l.position, lv.face), proj, l.position, near, far);
  }

  // The orthographic box of a directional light: the sphere around the camera's frustum up to
  // `distance` (its radius does not change as the camera turns), its centre snapped to whole
  // texels in the light's plane, deep enough for the whole scene. `*texel_area`: m² per texel.
  FrameView directional_view(const Light& l, float* texel_area) const {
    const vec3 dir = glm::normalize(l.direction);
    const vec3 up = std::abs(dir.y) > 0.99f ? vec3(1, 0, 0) : vec3(0, 1, 0);
    const Bounds3 b = ctx_.scene.bounds();
    const FrameView& cam = ctx_.view();
    float reach = param<float>("distance");
    if (reach <= 0.0f) reach = b.diagonal();
    const RsmBox box = rsm_directional_box(cam.inv_view_proj, cam.camera.position, cam.near_plane,
                                           std::min(reach, cam.far_plane));
    const mat4 light = glm::lookAtRH(vec3(0.0f), dir, up);
    const float texel = 2.0f * box.radius / static_cast<float>(resolution_);
    vec3 c = vec3(light * vec4(box.centre, 1.0f));
    c.x = std::round(c.x / texel) * texel;
    c.y = std::round(c.y / texel) * texel;
    // Depth: every corner of the scene's bounds, so casters outside the box's sphere still
    // occlude (the view looks down −z: depth = −z).
    float lo = std::numeric_limits<float>::max(), hi = -lo;
    for (int i = 0; i < 8; ++i) {
      const vec3 corner((i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y,
                        (i & 4) ? b.max.z : b.min.z);
      const float depth = -(light * vec4(corner, 1.0f)).z;
      lo = std::min(lo, depth);
      hi = std::max(hi, depth);
    }
    const float margin = 1e-3f * std::max(b.diagonal(), 1e-3f);
    lo -= margin;
    hi += margin;
    const float r = box.radius;
    const mat4 proj = glm::orthoRH_ZO(c.x - r, c.x + r, c.y - r, c.y + r, lo, hi);
    *texel_area = texel * texel;
    const vec3 centre = vec3(glm::inverse(light) * vec4(c.x, c.y, -0.5f * (lo + hi), 1.0f));
    return light_view(light, proj, centre, lo, hi);
  }

  void record(PassContext& pass) {
    const VkCommandBuffer cmd = pass.cmd();
    vkCmdUpdateBuffer(cmd, ctx_.resources.buffer(rsm::kViews).handle(), 0, table_.size(),
                      table_.data());
    FrameResources& r = ctx_.resources;
    for (uint32_t k = 0; k < layers(); ++k) {
      DrawTargets t;
      const VkClearColorValue zero{};
      t.colors = {{r.image(rsm::kPosition).layer_view(k), true, zero},
                  {r.image(rsm::kNormal).layer_view(k), true, zero},
                  {r.image(rsm::kFlux).layer_view(k), true, zero}};
      t.depth = r.image(rsm::kDepth).layer_view(k);
      t.depth_resource = rsm::kDepth;
      t.depth_layer = k;
      t.extent = {resolution_, resolution_};
      if (views_.empty()) {  // no light to draw: the one layer is cleared
        ctx_.drawer.begin(cmd, t);
        ctx_.drawer.end(cmd);
        continue;
      }
      SceneView v = SceneView::from(static_cast<int>(block_views_[k]), cameras_[k].view_proj, true);
      v.light_index = views_[k].light;
      ctx_.drawer.render(
          cmd, t, {&pipeline_}, ctx_.globals.default_layout(),
          {ctx_.globals.neutral_set(kPipelineSet), ctx_.globals.neutral_set(kShadowSet),
           ctx_.globals.neutral_set(kInputsSet)},
          v);
    }
  }

  uint32_t resolution_ = 128;
  bool directional_ = false;
  std::vector<LightView> views_;
  std::vector<FrameView> cameras_;
  std::vector<unsigned char> table_;  // the "rsm.views" buffer's bytes
  gpu::Pipeline pipeline_;
  ViewSlots block_views_;
};

}  // namespace

RsmBox rsm_directional_box(const mat4& inv_view_proj, const vec3& eye, float near_plane,
                           float distance) {
  // The near plane's corners, and the same rays out to `distance` along the view's depth.
  std::vector<vec3> corners;
  for (int i = 0; i < 4; ++i) {
    const vec4 ndc((i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f, 0.0f, 1.0f);
    const vec4 p = inv_view_proj * ndc;
    const vec3 n = vec3(p) / p.w;
    corners.push_back(n);
    corners.push_back(eye + (n - eye) * (distance / std::max(near_plane, 1e-6f)));
  }
  RsmBox box;
  // The centre of the slice's bounding box, and the farthest corner from it.
  vec3 lo = corners[0], hi = corners[0];
  for (const vec3& c : corners) {
    lo = glm::min(lo, c);
    hi = glm::max(hi, c);
  }
  box.centre = 0.5f * (lo + hi);
  box.radius = 0.0f;
  for (const vec3& c : corners) box.radius = std::max(box.radius, glm::length(c - box.centre));
  return box;
}

TechniqueDecl rsm_technique() {
  TechniqueDecl t;
  t.name = "rsm";
  t.kind = TechniqueKind::kAddOn;
  t.summary =
      "reflective shadow maps: per light view, world position, normal and reflected flux "
      "(I·Δω·ρ, or E·A·ρ) in 2-D arrays for the indirect-light techniques; shades nothing";
  t.params = {
      int_param("resolution", 128, 64, 256, "side of each light view in texels: 64, 128 or 256")
          .structural(),
      int_param("lights", -1, -1, 1 << 20, "-1: every light; k: light k alone").structural(),
      float_param("distance", 0.0f, 0.0f, 1e6f,
                  "directional lights: the box covers the camera's view up to this distance "
                  "(0: the scene's diagonal)"),
      int_param("period", 0, 0, 60,
                "0: re-render when the lights, geometry or (directional) camera change; N: "
                "also every N frames")
          .structural(),
  };
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<Rsm>(ctx, *find_technique("rsm"));
  };
  return t;
}

}  // namespace illum::realtime
