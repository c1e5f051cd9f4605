// The real-time renderer: uploads a Scene once, then renders frames headless into an HDR
// float target and an 8-bit tone-mapped target through a frame graph of passes:
//   shadow_maps (cube maps of point lights and wide spots, one 2-D map per spot light up
//            to 60°; on change or every N frames)
//   forward  (depth pre-pass, then S002 §4.1 Phong with depth EQUAL, all lights,
//            shadow-map lookups; with stencil shadows it writes depth + emission + ambient)
//   gbuffer, lighting (deferred: compact G-buffer after a depth pre-pass, then one compute
//            dispatch over all lights, or per-light volumes)
//   silhouettes (stencil shadows, GPU source: compute extraction of every light's volumes;
//            on change or every N frames)
//   shadow_volumes (stencil shadows, forward or deferred: per light a z-fail stencil pass,
//            timed as "stencil_volumes", and an additive lighting pass, "volume_lighting")
//   luminance (log-average) → tonemap (Reinhard / ACES / AgX, sRGB)
// Every pass is timed with GPU timestamps.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "illum/core/image.h"
#include "illum/core/params.h"
#include "illum/gpu/context.h"
#include "illum/gpu/gpu_image.h"
#include "illum/gpu/gpu_timer.h"
#include "illum/realtime/gpu_types.h"
#include "illum/realtime/render_settings.h"
#include "illum/scene/scene.h"

namespace illum::realtime {

enum class Technique { kForward, kDeferred };
// Deferred lighting: one compute dispatch over the G-buffer looping over the lights, or
// per-light volumes with the stencil trick (S001 §4.1).
enum class DeferredLighting { kCompute, kVolumes };
enum class ToneMapOp : int { kClamp = 0, kReinhard = 1, kAces = 2, kAgx = 3 };
// Where stencil shadow volumes are built: a compute pass drawn indirectly (GPU), or
// ShadowVolumeBuilder on the CPU (the simple reference, uploaded each rebuild).
enum class SilhouetteSource { kCpu, kGpu };

// δ of the log-average luminance: keeps black pixels from sending the mean log to −∞
// (shaders/luminance.comp uses the same value).
inline constexpr float kLogAverageDelta = 1e-4f;

struct RendererOptions {
  int width = 512;
  int height = 512;
  Technique technique = Technique::kForward;
  ShadowMode shadows = ShadowMode::kMap;
  int shadow_resolution = 512;  // cube face side
  // 0: re-render shadow maps (and rebuild shadow volumes) only when lights change; N: every
  // N frames.
  int shadow_update_period = 0;
  int pcf_taps = 16;               // 1 = hard shadows
  float pcf_radius = 1.5f;         // in shadow-map texels
  float shadow_bias = 0.002f;      // relative to the light's far distance
  float vsm_tau = 0.2f;            // VSM light-bleeding threshold
  bool volume_back_faces = false;  // shadow volumes from back-facing casters (S002 §4.3)
  SilhouetteSource silhouettes = SilhouetteSource::kGpu;
  bool half_lambert = false;
  Color ambient{0.0f};  // constant ambient radiance factor (× albedo)
  ToneMapOp tone_mapper = ToneMapOp::kAces;
  bool auto_exposure = true;  // exposure × key / L_avg (log-average luminance)
  float exposure = 1.0f;
  float key = 0.18f;
  float bloom_strength = 0.0f;  // 0 = no bloom passes
  float bloom_threshold = 1.0f;
  int single_light = -1;  // ≥ 0: light only with this light (debugging, tests)
  DeferredLighting deferred_lighting = DeferredLighting::kCompute;

  // Reads the options above from `params` (keys as the field names; enums by name:
  // technique forward|deferred, shadows none|map|vsm|volume, tone_mapper
  // clamp|reinhard|aces|agx, deferred_lighting compute|volumes, silhouettes cpu|gpu). Unknown
  // keys are left for the caller's check_all_used().
  static RendererOptions from_params(const Params& params);
  // Interim: the renderer's options from the technique settings (render_settings.h).
  static RendererOptions from_settings(const RenderSettings& settings);
};

ToneMapOp tone_map_op_from_string(const std::string& name);
ShadowMode shadow_mode_from_string(const std::string& name);
Technique technique_from_string(const std::string& name);
DeferredLighting deferred_lighting_from_string(const std::string& name);
SilhouetteSource silhouette_source_from_string(const std::string& name);

// The scene's lights as the real-time renderer uses them: point, spot and directional
// lights unchanged; each area light becomes a hemispherical spot light at its emitter's
// centroid, facing along the emitter's normal, with the far-field intensity of a Lambertian
// emitter, L·A·cos θ (Light::cosine_falloff; flux πLA). Environment lights are ignored.
std::vector<Light> realtime_lights(const Scene& scene);
// Point, spot and directional lights: the ones the real-time passes light with (and that
// cast stencil shadows); realtime_lights() passes environment lights through unlit.
bool lit_in_real_time(const Light& light);

// Baked light-map data for display (uv1 coordinates). Layers: kPlain 1 (irradiance/π, RGB),
// kRnm 3 (the Source basis maps, tangent space), kShL1 4 (radiance SH coefficients Y00,
// Y1−1 (y), Y10 (z), Y11 (x), tangent space). All layers share one size.
enum class LightmapKind : int { kNone = 0, kPlain = 1, kRnm = 2, kShL1 = 3 };
struct Lightmap {
  LightmapKind kind = LightmapKind::kNone;
  std::vector<Image> layers;
  float intensity = 1.0f;
};

// A regular grid of ambient cubes (probes) lighting dynamic objects: each listed instance
// takes the cube trilinearly interpolated at its world-bounds centre (clamped to the grid)
// instead of the light-map / constant ambient. cubes[((z·ny + y)·nx + x)·6 + face], faces
// +x, −x, +y, −y, +z, −z; radiance-like values multiplied by albedo.
struct AmbientCubeGrid {
  glm::ivec3 size{0};
  vec3 origin{0.0f}, spacing{1.0f};
  std::vector<Color> cubes;
  std::vector<int> instances;
};

class Renderer {
 public:
  Renderer(gpu::Context& context, const Scene& scene, const RendererOptions& options);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Records, submits and waits for one frame.
  void render(const Camera& camera);
  // Per-pass GPU milliseconds of the last frame (passes that ran), in execution order; a
  // "cpu:" prefix marks CPU work of that frame (silhouette extraction).
  const std::vector<gpu::PassTime>& pass_times() const;
  std::vector<std::string> pass_order() const;

  Image hdr();  // linear radiance, RGBA
  // The log-average luminance of the last frame's HDR image as the GPU computed it for
  // auto-exposure, L_avg = exp(mean over pixels of ln(kLogAverageDelta + max(L, 0))) with L
  // the Rec.709 luminance; the tone mapper then scales by exposure · key / L_avg (Reinhard
  // et al. 2002). Reads back from the GPU.
  float log_average_luminance();
  // The 8-bit sRGB-encoded output image (for presenting: blit it to a swapchain image).
  gpu::GpuImage& output_image();
  Image ldr();  // tone-mapped display values (linear, decoded from the sRGB target), RGBA

  const RendererOptions& options() const;
  // Applies `options` in place when only per-frame values differ from the current ones
  // (PCF taps/radius, bias, VSM τ, half-Lambert, ambient, tone mapper, exposure, key, bloom
  // strength/threshold while bloom stays on, volume_back_faces, single_light) and returns
  // true. Returns false, changing nothing, when a structural option differs (size,
  // technique, deferred lighting, shadow mode, shadow resolution or update period, bloom
  // on/off, silhouette source): the caller then builds a new Renderer. Lets `illum view` change
  // parameters without a rebuild.
  bool set_options(const RendererOptions& options);
  // Binds baked light-map data (replacing the constant ambient); throws Error on a wrong
  // layer count or mismatched sizes.
  void set_lightmap(const Lightmap& lightmap);
  void set_ambient_cubes(const AmbientCubeGrid& grid);
  // PRT (forward technique): per-vertex SH-L1 transfer vectors T_i = ∫ V(ω) max(n·ω, 0)
  // Y_i(ω) dω (basis order Y00, Y1−1, Y10, Y11), one per vertex of every mesh in scene order.
  // Each frame the lights are projected to SH-L1 (directional: E·Y_i(−d); point/spot:
  // I/d²·Y_i at the scene centre, i.e. treated as distant) and the shader outputs
  // emission + ambient + albedo/π · Σ T_i·L_i in place of the per-light loop.
  void set_prt_transfer(const std::vector<glm::vec4>& transfer);
  // Light changes re-render the shadow maps (on-change schedule). `lights` replaces the
  // renderer's lights (as realtime_lights() made them), same count.
  void update_lights(const std::vector<Light>& lights);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace illum::realtime
