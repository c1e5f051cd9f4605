#include "illum/realtime/renderer.h"

#include <algorithm>
#include <map>
#include <optional>

#include "illum/core/color.h"
#include "illum/gpu/buffer.h"
#include "illum/gpu/vk_check.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/frame_graph.h"
#include "illum/realtime/frame_resources.h"
#include "illum/realtime/gpu_scene.h"
#include "illum/realtime/gpu_types.h"
#include "illum/realtime/renderer_input.h"
#include "illum/realtime/scene_draw.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

bool structural_change(const TechniqueDecl& t, const RenderSettings& a, const RenderSettings& b) {
  for (const ParamDecl& p : t.params)
    if (p.change == ParamChange::kStructural &&
        a.value(t.name + "." + p.key) != b.value(t.name + "." + p.key))
      return true;
  return false;
}

bool per_frame_change(const TechniqueDecl& t, const RenderSettings& a, const RenderSettings& b) {
  for (const ParamDecl& p : t.params)
    if (p.change == ParamChange::kPerFrame &&
        a.value(t.name + "." + p.key) != b.value(t.name + "." + p.key))
      return true;
  return false;
}

// The order techniques are built and declared in: the shadow method (the pipeline asks it
// how lights are shadowed), the pipeline, then the add-ons in registry order.
std::vector<const TechniqueDecl*> build_order(const RenderSettings& s) {
  std::vector<const TechniqueDecl*> order = {find_technique(s.shadows), find_technique(s.pipeline)};
  for (const TechniqueDecl& t : technique_registry())
    if (t.kind == TechniqueKind::kAddOn && s.active(t.name)) order.push_back(&t);
  return order;
}

}  // namespace

struct Renderer::Impl {
  using Techniques = std::vector<std::unique_ptr<Technique>>;

  gpu::Context& context;
  GpuScene scene;
  std::vector<Light> lights;
  RenderSettings settings;
  VkFormat depth_format;
  FrameGlobals globals;
  LightingInputs inputs;
  FrameResources resources;
  OcclusionCuller occlusion;
  SceneDrawer drawer;
  BakedData baked;
  FrameView view;
  TechniqueContext tctx;
  // Built techniques in build order, and (while configure() builds) the ones just built.
  Techniques techniques;
  std::map<std::string, std::unique_ptr<Technique>> fresh;
  std::unique_ptr<FrameGraph> graph;
  gpu::GpuTimer timer;
  VkCommandPool pool = VK_NULL_HANDLE;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  uint64_t frame_index = 0;
  std::optional<Camera> last_camera;
  std::vector<gpu::PassTime> times;

  Impl(gpu::Context& c, const Scene& s, const RenderSettings& settings_in)
      : context(c),
        scene(c, s),
        lights(realtime_lights(s)),
        settings(settings_in),
        depth_format(gpu::pick_depth_stencil_format(c)),
        globals(c, scene, lights.size()),
        inputs(c, globals),
        resources(c),
        occlusion(c, scene, resources),
        drawer(scene, globals, &occlusion),
        tctx(c, scene, globals, resources, drawer, depth_format),
        timer(c) {
    tctx.lights_ = &lights;
    tctx.settings_ = &settings;
    tctx.view_ = &view;
    tctx.baked_ = &baked;
    tctx.pipeline_ = [this] { return dynamic_cast<FramePipeline*>(technique(settings.pipeline)); };
    tctx.shadow_method_ = [this] {
      return dynamic_cast<ShadowMethod*>(technique(settings.shadows));
    };
    tctx.lighting_inputs_ = &inputs;
    tctx.shading_sets_ = [this](VkDescriptorSet pipeline_set) {
      std::array<VkDescriptorSet, 3> sets = {
          pipeline_set ? pipeline_set : globals.neutral_set(kPipelineSet),
          globals.neutral_set(kShadowSet), inputs.set()};
      for (const Technique* t : active())
        if (t->shading_slot() == static_cast<int>(kShadowSet)) sets[1] = t->shading_set();
      return sets;
    };
    tctx.shading_reads_ = [this](VkPipelineStageFlags2 shaders, InputReads which) {
      std::vector<Access> reads;
      for (const Technique* t : active())
        for (const std::string& r : t->shading_reads()) reads.push_back({r, kSampled, shaders});
      for (const Access& a : inputs.reads(shaders, which)) reads.push_back(a);
      return reads;
    };
    tctx.graph_ = [this] { return graph.get(); };
    globals.upload_lights(lights);
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
    configure(settings_in, {}, /*first=*/true);
  }

  ~Impl() {
    context.wait_idle();
    graph.reset();
    techniques.clear();
    if (fence) vkDestroyFence(context.device(), fence, nullptr);
    if (pool) vkDestroyCommandPool(context.device(), pool, nullptr);
  }

  // The technique named `name` among those just built, else among the built ones.
  Technique* technique(const std::string& name) const {
    const auto f = fresh.find(name);
    if (f != fresh.end()) return f->second.get();
    for (const auto& t : techniques)
      if (t->name() == name) return t.get();
    return nullptr;
  }

  // The techniques of `settings` in build order (built ones, or just built ones).
  std::vector<Technique*> active() const {
    std::vector<Technique*> out;
    for (const TechniqueDecl* d : build_order(settings))
      if (Technique* t = technique(d->name)) out.push_back(t);
    return out;
  }

  static std::vector<LightingContribution> contributions(const std::vector<Technique*>& list) {
    std::vector<LightingContribution> out;
    for (const Technique* t : list)
      for (LightingContribution& c : t->lighting_inputs()) out.push_back(std::move(c));
    return out;
  }

  std::unique_ptr<FrameGraph> assemble(const std::vector<Technique*>& list) {
    auto g = std::make_unique<FrameGraph>();
    // Which inputs are active, and what their passes read, before anything declares.
    inputs.set_reads(contributions(list));
    // The pipeline declares first: its shading pass and the stencil volumes' per-light
    // passes both run in the lighting phase, and the lights add onto what the shading wrote.
    std::vector<Technique*> order = list;
    std::stable_partition(order.begin(), order.end(), [](const Technique* t) {
      return dynamic_cast<const FramePipeline*>(t) != nullptr;
    });
    for (Technique* t : order) t->declare(*g);
    g->require("ldr", "the 8-bit output needs the tonemap add-on (do not --disable tonemap)");
    g->compile();
    return g;
  }

  // See Renderer::configure; `force` names techniques to build anew whatever changed (their
  // data changed: the baked lighting).
  std::vector<std::string> configure(const RenderSettings& next,
                                     const std::vector<std::string>& force, bool first = false) {
    next.check();
    check_single_light(next.get<int>("lighting.single_light"), lights.size());
    const RenderSettings previous = settings;
    std::vector<std::string> built;
    settings = next;  // the techniques read their parameters from here while they are built
    try {
      fresh.clear();
      for (const TechniqueDecl* d : build_order(next)) {
        if (!d->create) continue;
        const bool was = !first && previous.active(d->name);
        bool rebuild = !was || structural_change(*d, previous, next) ||
                       std::find(force.begin(), force.end(), d->name) != force.end();
        // The pipeline builds what the shadow method's kind of shadowing needs.
        if (d->kind == TechniqueKind::kFramePipeline && !rebuild && fresh.count(next.shadows)) {
          const Technique* old_shadows = nullptr;
          for (const auto& t : techniques)
            if (t->name() == previous.shadows) old_shadows = t.get();
          rebuild =
              !old_shadows || dynamic_cast<const ShadowMethod*>(old_shadows)->masks_lights() !=
                                  tctx.shadow_method().masks_lights();
        }
        if (!rebuild) continue;
        fresh[d->name] = d->create(tctx);
        built.push_back(d->name);
      }
      std::unique_ptr<FrameGraph> next_graph = assemble(active());
      context.wait_idle();
      if (graph) {
        next_graph->inherit(*graph, [&](const std::string& technique_name) {
          return std::find(built.begin(), built.end(), technique_name) == built.end();
        });
      }
      // Keep the techniques still in use; drop the others (after the GPU is done with them).
      Techniques kept;
      for (const TechniqueDecl* d : build_order(next)) {
        if (!d->create) continue;
        auto f = fresh.find(d->name);
        if (f != fresh.end()) {
          kept.push_back(std::move(f->second));
          continue;
        }
        for (auto& t : techniques)
          if (t && t->name() == d->name) kept.push_back(std::move(t));
      }
      fresh.clear();
      techniques = std::move(kept);
      graph = std::move(next_graph);
    } catch (...) {
      fresh.clear();
      settings = previous;
      if (graph) {
        // The kept techniques' own state as it was, on a graph bound to the same resources.
        std::unique_ptr<FrameGraph> restored = assemble(active());
        restored->inherit(*graph, [](const std::string&) { return true; });
        graph = std::move(restored);
        realize_and_bind();
      }
      throw;
    }
    realize_and_bind();
    for (const auto& t : techniques) {
      const TechniqueDecl& d = *find_technique(t->name());
      if (!first && std::find(built.begin(), built.end(), t->name()) == built.end() &&
          per_frame_change(d, previous, next))
        graph->notify(kParametersChanged, t->name());
    }
    return built;
  }

  // GPU objects for the graph's resources (new ones make their writers run in full), and
  // every technique's descriptor sets pointed at them.
  void realize_and_bind() {
    for (const std::string& created : resources.realize(*graph, globals_width(), globals_height()))
      graph->invalidate_writers(created);
    for (const auto& t : techniques) t->bind();
    std::vector<Technique*> list;
    for (const auto& t : techniques) list.push_back(t.get());
    inputs.bind(contributions(list));
  }

  uint32_t globals_width() const { return static_cast<uint32_t>(settings.width); }
  uint32_t globals_height() const { return static_cast<uint32_t>(settings.height); }

  void update_view(const Camera& camera) {
    view = camera_view(camera, scene.bounds(), globals_width(), globals_height());
    view.index = frame_index;
  }

  void render(const Camera& camera, bool counting = false) {
    // Lavapipe crashes on queries around depth-tested draws in frames that also build shadow
    // volumes on the GPU: no rasterized-triangle counts there.
    timer.set_counting(counting, !(context.is_software() && tctx.shadow_method().masks_lights()));
    if (last_camera &&
        (last_camera->position != camera.position || last_camera->look_at != camera.look_at ||
         last_camera->up != camera.up || last_camera->fov_y != camera.fov_y))
      graph->notify(kCameraChanged);
    last_camera = camera;
    occlusion.set_enabled(settings.get<bool>("scene_draw.occlusion_culling"),
                          settings.get<bool>("scene_draw.occlusion_culling_shadows"));
    update_view(camera);
    globals.update(view, settings, lights.size(), globals_width(), globals_height());
    for (const auto& t : techniques) t->update();
    // What techniques raised since the last frame (in update() above, or while recording
    // it); raised while this frame records, they apply to the next.
    for (const auto& [changes, technique] : tctx.raised_) graph->notify(changes, technique);
    tctx.raised_.clear();
    timer.reserve(graph->timer_scopes());
    ILLUM_VK(vkResetCommandBuffer(cmd, 0));
    gpu::record_one_time(cmd, [&](VkCommandBuffer c) {
      timer.reset(c);
      graph->execute(c, frame_index++, &timer);
    });
    context.submit_and_wait(cmd, fence);
    // Per-light scopes repeat under their pass: one sum per name and depth.
    times.clear();
    for (const gpu::PassTime& t : timer.resolve()) {
      auto it = std::find_if(times.begin(), times.end(), [&](const gpu::PassTime& x) {
        return x.name == t.name && x.depth == t.depth;
      });
      if (it == times.end()) {
        times.push_back(t);
      } else {
        it->ms += t.ms;
        it->bytes += t.bytes;
        it->triangles += t.triangles;
        if (t.rasterized >= 0.0) it->rasterized = std::max(0.0, it->rasterized) + t.rasterized;
        if (t.vertices >= 0.0) it->vertices = std::max(0.0, it->vertices) + t.vertices;
        if (t.quads >= 0.0) {
          it->quads = std::max(0.0, it->quads) + t.quads;
          it->quad_samples = std::max(0.0, it->quad_samples) + t.quad_samples;
        }
        if (t.clusters >= 0.0) it->clusters = std::max(0.0, it->clusters) + t.clusters;
        it->fills.insert(it->fills.end(), t.fills.begin(), t.fills.end());
      }
    }
    for (const gpu::PassTime& t : graph->cpu_times()) times.push_back(t);
  }

  void switch_on_baked() {
    RenderSettings next = settings;
    next.enable("baked");
    context.wait_idle();
    configure(next, {"baked"});
  }
};

Renderer::Renderer(gpu::Context& context, const Scene& scene, const RenderSettings& settings) {
  // Before anything is uploaded: Impl's members build GPU objects from these values.
  settings.check();
  check_realtime_input(scene, settings.get<int>("lighting.single_light"));
  impl_ = std::make_unique<Impl>(context, scene, settings);
}

Renderer::~Renderer() = default;

void Renderer::render(const Camera& camera) {
  check_camera(camera);
  impl_->render(camera);
}

const std::vector<gpu::PassTime>& Renderer::pass_times() const {
  return impl_->times;
}

const std::vector<gpu::PassTime>& Renderer::measure_work(const Camera& camera) {
  check_camera(camera);
  impl_->render(camera, /*counting=*/true);
  impl_->timer.set_counting(false);
  return impl_->times;
}

bool Renderer::measure_shading(const Camera& camera, int repeats, ShadingTime* out, Image* image) {
  check_camera(camera);
  impl_->render(camera);
  return impl_->tctx.pipeline().measure_shading(repeats, out, image);
}

std::vector<std::string> Renderer::pass_order() const {
  return impl_->graph->order();
}

Image Renderer::hdr() {
  return impl_->resources.image("hdr").readback();
}

Image Renderer::read_resource(const std::string& name, uint32_t layer) {
  Impl& m = *impl_;
  // A history resource: "NAME" and "NAME.previous" are the copies the graph gives those names.
  const std::string suffix = ".previous";
  const bool previous = name.size() > suffix.size() && name.ends_with(suffix);
  const std::string base = previous ? name.substr(0, name.size() - suffix.size()) : name;
  if (!m.resources.has_image(base) ||
      (previous && !(m.graph && m.graph->has_resource(base) && m.graph->resource(base).history)))
    throw Error("no frame image named '" + name + "'");
  const int copy = m.graph && m.graph->has_resource(base) ? m.graph->copy_index(name) : 0;
  gpu::GpuImage& image = m.resources.image(base, copy);
  // A 3-D image's "layers" are its depth slices.
  const uint32_t layers = image.desc().depth > 1 ? image.desc().depth : image.desc().layers;
  if (layer >= layers)
    throw Error("frame resource '" + name + "' has no layer " + std::to_string(layer));
  if (!(image.desc().usage & VK_IMAGE_USAGE_TRANSFER_SRC_BIT))
    throw Error("frame resource '" + name + "' is not declared readable (extra_usage)");
  return image.readback(layer);
}

AutoExposure Renderer::auto_exposure() {
  Impl& m = *impl_;
  if (!m.resources.has("luminance"))
    throw Error("auto exposure: the luminance add-on (auto-exposure) is off");
  // luminance_reduce.comp leaves the mean log2 luminance and the exposure after the bins.
  const VkDeviceSize offset = kExposureMeanOffset;
  float values[2] = {0.0f, 0.0f};
  gpu::Buffer staging(m.context, sizeof(values), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                      gpu::MemoryUsage::kReadback);
  m.context.immediate([&](VkCommandBuffer c) {
    gpu::memory_barrier(c, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                        VK_ACCESS_2_TRANSFER_READ_BIT);
    const VkBufferCopy copy{offset, 0, sizeof(values)};
    vkCmdCopyBuffer(c, m.resources.buffer("luminance").handle(), staging.handle(), 1, &copy);
    gpu::memory_barrier(c, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  });
  staging.read(values, sizeof(values));
  AutoExposure out;
  out.mean_log2 = values[0];
  out.exposure = values[1];
  return out;
}

gpu::GpuImage& Renderer::output_image() {
  return impl_->resources.image("ldr");
}

Image Renderer::ldr() {
  Image img = impl_->resources.image("ldr").readback();
  for (size_t i = 0; i < img.pixel_count(); ++i)
    for (int k = 0; k < 3; ++k) img.data()[i * 4 + k] = srgb_decode(img.data()[i * 4 + k]);
  return img;
}

const RenderSettings& Renderer::settings() const {
  return impl_->settings;
}

std::vector<std::string> Renderer::configure(const RenderSettings& settings) {
  return impl_->configure(settings, {});
}

void Renderer::set_lightmap(const Lightmap& lightmap) {
  const size_t expected = lightmap.kind == LightmapKind::kPlain      ? 1
                          : lightmap.kind == LightmapKind::kRnm      ? 3
                          : lightmap.kind == LightmapKind::kShL1     ? 4
                          : lightmap.kind == LightmapKind::kDominant ? 3
                                                                     : 0;
  if (lightmap.layers.size() != expected)
    throw Error(fmt::format("light-map: {} layers given, this kind needs {}",
                            lightmap.layers.size(), expected));
  for (const Image& layer : lightmap.layers)
    if (layer.width() != lightmap.layers[0].width() ||
        layer.height() != lightmap.layers[0].height())
      throw Error("light-map: all layers must have the same size");
  impl_->baked.lightmap = lightmap;
  impl_->switch_on_baked();
}

void Renderer::set_probe_volume(const ProbeVolume& volume) {
  Impl& m = *impl_;
  probe_instance_cubes(volume, m.scene.scene(), m.scene.draw_instances(), &m.baked);
  m.baked.probes = volume;
  m.switch_on_baked();
}

void Renderer::set_prt(const PrtTransfer& prt) {
  Impl& m = *impl_;
  if (prt.bands < 1 || prt.channels() / 3 > kMaxPrtCoefficients)
    throw Error(fmt::format("PRT: {} bands; the display shows 1..8", prt.bands));
  const size_t channels = static_cast<size_t>(prt.channels());
  size_t vertices = 0;
  for (const Mesh& mesh : m.scene.scene().meshes) vertices += mesh.positions.size();
  if (!prt.vertices.empty() && prt.vertices.size() != vertices * channels)
    throw Error(fmt::format("PRT: {} vertex transfer values for {} vertices × {} channels",
                            prt.vertices.size(), vertices, channels));
  const size_t texels =
      static_cast<size_t>(std::max(prt.width, 0)) * static_cast<size_t>(std::max(prt.height, 0));
  if (!prt.texels.empty() && prt.texels.size() != texels * channels)
    throw Error(fmt::format("PRT: {} texel transfer values for a {}x{} atlas × {} channels",
                            prt.texels.size(), prt.width, prt.height, channels));
  if (!prt.vq_indices.empty()) {
    const size_t count = prt.vq_representatives.size() / channels;
    if (prt.vq_indices.size() != texels || count == 0 ||
        prt.vq_representatives.size() != count * channels)
      throw Error(fmt::format("PRT: VQ data does not fit a {}x{} atlas × {} channels", prt.width,
                              prt.height, channels));
    for (uint16_t i : prt.vq_indices)
      if (i >= count)
        throw Error(fmt::format("PRT: VQ index {} past {} representatives", i, count));
  }
  if (prt.vertices.empty() && prt.texels.empty() && prt.vq_indices.empty())
    throw Error("PRT: no vertex, texel or VQ transfer given");
  m.baked.prt = prt;
  m.switch_on_baked();
}

void Renderer::update_lights(const std::vector<Light>& lights) {
  ILLUM_CHECK(lights.size() == impl_->lights.size(), "update_lights cannot change the light count");
  check_realtime_lights(lights);
  impl_->context.wait_idle();
  impl_->lights = lights;
  impl_->globals.upload_lights(lights);
  impl_->graph->notify(kLightsChanged);
}

}  // namespace illum::realtime
