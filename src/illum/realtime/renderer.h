// The real-time renderer: uploads a Scene once, then renders frames headless into an HDR
// float target ("hdr") and an 8-bit tone-mapped target ("ldr"). A frame is assembled from
// techniques (technique.h, listed in technique_registry.cpp): the globals, one frame
// pipeline (forward, deferred), one shadow method (none, map, vsm, volume) and the add-ons
// switched on (baked, luminance, bloom, tonemap, ...). Each declares its resources and
// passes to a frame graph (frame_graph.h), which orders them, derives their barriers, runs
// them on their schedules and times each with GPU timestamps. The renderer only
// orchestrates: it builds the techniques, assembles and realizes the graph, writes the
// frame uniforms and submits.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "illum/core/auto_exposure.h"
#include "illum/core/image.h"
#include "illum/gpu/context.h"
#include "illum/gpu/gpu_image.h"
#include "illum/gpu/gpu_timer.h"
#include "illum/realtime/baked_data.h"
#include "illum/realtime/gpu_types.h"
#include "illum/realtime/measure/shading_bound.h"
#include "illum/realtime/realtime_lights.h"
#include "illum/realtime/render_settings.h"
#include "illum/scene/scene.h"

namespace illum::realtime {

class Renderer {
 public:
  // Throws Error naming the problem for bad settings, bad scene input (renderer_input.h) or
  // a technique the device cannot run (volume without depthClamp).
  Renderer(gpu::Context& context, const Scene& scene, const RenderSettings& settings);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Records, submits and waits for one frame.
  void render(const Camera& camera);
  // GPU milliseconds of the last frame's timer scopes, in execution order (a pass's nested
  // scopes, depth > 0, follow it; one entry per name and depth, summed over lights), then
  // the CPU work of that frame as "cpu:NAME" (the CPU silhouette build).
  const std::vector<gpu::PassTime>& pass_times() const;
  std::vector<std::string> pass_order() const;
  // Renders one more frame whose pass times also carry counted overdraw (occlusion queries
  // around the draws whose cost is their fragment count: stencil shadow volumes) and returns
  // them; each scope's fills and bytes say what bounds it (illum-bench raster). Its times
  // include the counting draws: time other frames.
  const std::vector<gpu::PassTime>& measure_work(const Camera& camera);
  // Renders one more frame, then the shading bound of the pipeline's fragment lighting pass
  // (measure/shading_bound.h: that lighting over a G-buffer of the same view, one full-screen
  // pass timed `repeats` times; `image`: its output). False where the pipeline has none.
  bool measure_shading(const Camera& camera, int repeats, ShadingTime* out, Image* image = nullptr);

  Image hdr();  // linear radiance, RGBA
  // One layer (of a 3-D image: depth slice) of a named frame resource as the last frame left
  // it (depth formats as depth in [0, 1]), for tests and inspection; "NAME" and
  // "NAME.previous" of a history resource are the copies they name after that frame. Throws
  // Error for an unknown name or layer.
  Image read_resource(const std::string& name, uint32_t layer = 0);
  // The auto exposure the GPU computed from the last frame's HDR image by core's rule
  // (core/auto_exposure.h: histogram, percentiles, target grey; `counted` left 0); the tone
  // mapper scales by tonemap.exposure × it. Reads back from the GPU; throws Error with the
  // luminance add-on off.
  AutoExposure auto_exposure();
  // The 8-bit sRGB-encoded output image (for presenting: blit it to a swapchain image).
  gpu::GpuImage& output_image();
  Image ldr();  // tone-mapped display values (linear, decoded from the sRGB target), RGBA

  const RenderSettings& settings() const;
  // Applies `settings` to the running renderer: per-frame parameter values at the next frame
  // (a change also re-runs the owning technique's passes scheduled on a parameter change);
  // a technique switched on, replaced (another pipeline or shadow method) or with a changed
  // structural parameter is built anew, the others are kept with their resources, cached
  // shadow maps and history; a new size re-creates the frame-sized resources. Returns the
  // names of the techniques built anew. Throws Error, changing nothing, for bad settings or
  // a technique that cannot be built.
  std::vector<std::string> configure(const RenderSettings& settings);

  // Baked lighting, shown by the `baked` add-on (switched on by these; replacing the
  // constant ambient). set_lightmap throws Error on a wrong layer count or mismatched sizes.
  void set_lightmap(const Lightmap& lightmap);
  // The probes lighting the instances volume.instances (probe_volume.h): per pixel, or one
  // ambient cube per instance (baked.probe_lookup). Throws Error as check_probe_volume.
  void set_probe_volume(const ProbeVolume& volume);
  // PRT transfer (baked_data.h), shown in every frame pipeline: the ambient term becomes
  // albedo × max(Σ T_i L_i, 0) with L_i the `baked` add-on's sun (baked.sun_*) projected to
  // SH each frame; the scene's lights still add their own light (a caller showing a bake
  // removes them: baked_display). Throws Error for bands outside 1..8, sizes that do not fit
  // the scene's vertices or the atlas, a VQ index past the representatives, or no data.
  void set_prt(const PrtTransfer& prt);
  // Light changes re-render the shadow maps and rebuild the volumes (their schedules name
  // the lights). `lights` replaces the renderer's lights (as realtime_lights() made them),
  // same count.
  void update_lights(const std::vector<Light>& lights);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace illum::realtime
