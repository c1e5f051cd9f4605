// Baked lighting in the ambient term, as three lighting inputs (lighting_inputs.h): `lightmap`
// (plain, RNM, SH-L1, dominant at uv1; shaders/inputs/lightmap.glsl), `probes` (the probes'
// irradiance volume on dynamic instances, per pixel, shaders/probe_volume.glsl, or one
// ambient cube per instance; inputs/probes.glsl) and `prt` (transfer per vertex, per texel or
// VQ-compressed, 1..8 bands, relit each frame by a sun projected to SH on the CPU;
// shaders/prt.glsl). The data stays with the renderer (Renderer::set_lightmap, ...);
// switching the add-on on uploads it and contributes the inputs the data holds.
#include <glm/gtc/packing.hpp>

#include "illum/core/sh.h"
#include "illum/realtime/frame_globals.h"
#include "illum/realtime/realtime_lights.h"
#include "illum/realtime/technique_context.h"
#include "illum/realtime/technique_registry.h"
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

// Points of `channels` floats as half floats, two per word, each point padded to an even
// count so that a point starts on a word (prt.glsl's prt_half).
std::vector<uint32_t> pack_halves(const std::vector<float>& values, int channels) {
  const size_t stride = static_cast<size_t>(channels + (channels & 1));
  const size_t points = values.size() / static_cast<size_t>(channels);
  std::vector<uint32_t> words(points * stride / 2, 0u);
  for (size_t p = 0; p < points; ++p)
    for (size_t c = 0; c < static_cast<size_t>(channels); ++c) {
      const size_t k = p * stride + c;
      const uint32_t h = glm::packHalf1x16(values[p * static_cast<size_t>(channels) + c]);
      words[k / 2] |= (k & 1) ? h << 16 : h;
    }
  return words;
}

PrtLookup chosen_lookup(const PrtTransfer& prt, const std::string& name) {
  if (prt.empty()) return PrtLookup::kNone;
  const PrtLookup lookup = name == "vertices"   ? PrtLookup::kVertices
                           : name == "vq"       ? PrtLookup::kVq
                           : name == "texels"   ? PrtLookup::kTexels
                           : prt.texels.empty() ? PrtLookup::kVertices
                                                : PrtLookup::kTexels;  // auto
  const bool has = lookup == PrtLookup::kVertices ? !prt.vertices.empty()
                   : lookup == PrtLookup::kTexels ? !prt.texels.empty()
                                                  : !prt.vq_indices.empty();
  if (!has)
    throw Error(fmt::format("baked.prt_lookup={}: the PRT data holds no {} transfer", name,
                            name == "vq"         ? "VQ-compressed"
                            : name == "vertices" ? "vertex"
                                                 : "texel"));
  return lookup;
}

// The direction towards the sun of baked.sun_azimuth / sun_elevation (degrees; y up,
// azimuth 0 towards +z, 90 towards +x): illum relight's --sun is its negative.
vec3 sun_towards(float azimuth_deg, float elevation_deg) {
  const float az = radians(azimuth_deg), el = radians(elevation_deg);
  return vec3(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
}

class Baked final : public Technique {
 public:
  Baked(TechniqueContext& ctx, const TechniqueDecl& decl) : Technique(ctx, decl) {
    const BakedData& data = ctx.baked();
    const FrameGlobals& g = ctx.globals;
    const Lightmap& lm = data.lightmap;
    VkImageView lightmap = g.dummy_array().view();
    if (lm.kind != LightmapKind::kNone) {
      const Image& first = lm.layers.at(0);
      gpu::ImageDesc d;
      d.width = static_cast<uint32_t>(first.width());
      d.height = static_cast<uint32_t>(first.height());
      d.layers = static_cast<uint32_t>(lm.layers.size());
      d.array = true;
      d.format = VK_FORMAT_R16G16B16A16_SFLOAT;  // signed: SH coefficients can be negative
      d.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
      lightmap_ = gpu::GpuImage(ctx.gpu, d);
      for (size_t l = 0; l < lm.layers.size(); ++l)
        lightmap_.upload(lm.layers[l], static_cast<uint32_t>(l));
      lightmap = lightmap_.view();
    }
    auto storage = [&](const void* bytes, size_t size, gpu::Buffer* buffer) -> VkBuffer {
      if (size == 0) return g.dummy_buffer().handle();
      *buffer =
          gpu::Buffer(ctx.gpu, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::kUpload);
      buffer->write(bytes, size);
      return buffer->handle();
    };
    const VkBuffer cubes = storage(data.cubes.data(), data.cubes.size() * sizeof(vec4), &cubes_);
    lookup_ = chosen_lookup(data.prt, param<std::string>("prt_lookup"));
    std::vector<uint32_t> points, indices;
    if (lookup_ != PrtLookup::kNone) {
      const PrtTransfer& prt = data.prt;
      points = pack_halves(lookup_ == PrtLookup::kVertices ? prt.vertices
                           : lookup_ == PrtLookup::kTexels ? prt.texels
                                                           : prt.vq_representatives,
                           prt.channels());
      if (lookup_ == PrtLookup::kVq) {
        indices.assign((prt.vq_indices.size() + 1) / 2, 0u);
        for (size_t i = 0; i < prt.vq_indices.size(); ++i)
          indices[i / 2] |= uint32_t(prt.vq_indices[i]) << (i & 1 ? 16 : 0);
      }
    }
    const VkBuffer prt = storage(points.data(), points.size() * sizeof(uint32_t), &prt_);
    const VkBuffer vq = storage(indices.data(), indices.size() * sizeof(uint32_t), &vq_);
    const VkBuffer draw_cube =
        storage(data.draw_cube.data(), data.draw_cube.size() * sizeof(int), &draw_cube_);
    // The probe volume as 32-bit floats in a storage buffer (DESIGN.md decisions): 112 bytes a
    // probe, read with 8 fetches per pixel whose weights include each probe's validity.
    const VkBuffer probes =
        storage(data.probes.probes.data(), data.probes.probes.size() * sizeof(float), &probes_);
    auto ubo = [&](size_t size) {
      return gpu::Buffer(ctx.gpu, size, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                         gpu::MemoryUsage::kUpload);
    };
    lightmap_ubo_ = ubo(sizeof(LightmapInputUniforms));
    prt_ubo_ = ubo(sizeof(PrtInputUniforms));
    probes_ubo_ = ubo(sizeof(ProbesInputUniforms));
    const VkSampler sampler = g.clamp_linear().handle();
    const auto ssbo = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    const auto uniform = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    // Only the inputs the data holds: the others stay neutral (flag 0).
    if (lm.kind != LightmapKind::kNone)
      contributions_.push_back({"lightmap",
                                [this, lightmap, sampler, uniform](
                                    gpu::DescriptorWriter& w, VkDescriptorSet set, uint32_t base) {
                                  w.buffer(set, base, uniform, lightmap_ubo_.handle())
                                      .image(set, base + 1,
                                             VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, lightmap,
                                             sampler, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
                                },
                                {}});
    if (lookup_ != PrtLookup::kNone)
      contributions_.push_back({"prt",
                                [this, prt, vq, ssbo, uniform](gpu::DescriptorWriter& w,
                                                               VkDescriptorSet set, uint32_t base) {
                                  w.buffer(set, base, uniform, prt_ubo_.handle())
                                      .buffer(set, base + 1, ssbo, prt)
                                      .buffer(set, base + 2, ssbo, vq);
                                },
                                {}});
    if (!data.draw_cube.empty())
      contributions_.push_back({"probes",
                                [this, cubes, draw_cube, probes, ssbo, uniform](
                                    gpu::DescriptorWriter& w, VkDescriptorSet set, uint32_t base) {
                                  w.buffer(set, base, uniform, probes_ubo_.handle())
                                      .buffer(set, base + 1, ssbo, cubes)
                                      .buffer(set, base + 2, ssbo, draw_cube)
                                      .buffer(set, base + 3, ssbo, probes);
                                },
                                {}});
  }

  std::vector<LightingContribution> lighting_inputs() const override { return contributions_; }
  void declare(FrameGraph&) override {}  // no passes: the pipelines' shading reads the inputs

  void update() override {
    const BakedData& data = ctx_.baked();
    LightmapInputUniforms lm{};
    lm.info = glm::ivec4(static_cast<int>(data.lightmap.kind), 0, 0, 0);
    lm.intensity = vec4(param<float>("intensity"), 0.0f, 0.0f, 0.0f);
    lightmap_ubo_.write(&lm, sizeof(lm));
    ProbesInputUniforms pr{};
    pr.info = glm::ivec4(static_cast<int>(data.draw_cube.size()), 0, 0, 0);
    if (!data.probes.empty()) {
      const bool per_pixel = param<std::string>("probe_lookup") == "pixel";
      pr.size = glm::ivec4(data.probes.size, per_pixel ? kProbeLookupPixel : 0);
      pr.origin = vec4(data.probes.origin, 0.0f);
      pr.spacing = vec4(data.probes.spacing, 0.0f);
    }
    probes_ubo_.write(&pr, sizeof(pr));
    PrtInputUniforms u{};
    u.info = glm::ivec4(static_cast<int>(lookup_), 0, 0, 0);
    if (lookup_ != PrtLookup::kNone) {
      // The sun as illum relight projects it: L_i = E·Y_i(s), s towards the sun, world frame.
      const int bands = data.prt.bands;
      const int n = sh::coefficient_count(bands);
      u.info.y = n;
      u.size = glm::ivec4(data.prt.width, data.prt.height,
                          data.prt.channels() + (data.prt.channels() & 1), 0);
      std::vector<float> y(static_cast<size_t>(n));
      sh::evaluate<float>(
          bands, sun_towards(param<float>("sun_azimuth"), param<float>("sun_elevation")), y);
      const float e = param<float>("sun_irradiance");
      for (int i = 0; i < n; ++i) u.light[i] = vec4(vec3(e * y[static_cast<size_t>(i)]), 0.0f);
    }
    prt_ubo_.write(&u, sizeof(u));
  }

 private:
  gpu::GpuImage lightmap_;
  gpu::Buffer cubes_, prt_, draw_cube_, vq_, probes_, lightmap_ubo_, prt_ubo_, probes_ubo_;
  PrtLookup lookup_ = PrtLookup::kNone;
  std::vector<LightingContribution> contributions_;
};

}  // namespace

TechniqueDecl baked_technique() {
  TechniqueDecl t;
  t.name = "baked";
  t.kind = TechniqueKind::kAddOn;
  t.summary =
      "baked lighting shown in the ambient term: light-maps (plain, RNM, SH-L1), the probes' "
      "irradiance volume on dynamic instances, PRT transfer relit by a sun (per vertex, per texel "
      "or VQ; "
      "--baked DIR); switched on when such data is given";
  t.params = {
      float_param("intensity", 1.0f, 0.0f, 1e6f, "multiplies the light-map")
          .slider(UiHint::kLogarithmic, 0.01, 16),
      float_param("sun_azimuth", 0.0f, -360.0f, 360.0f,
                  "PRT sun: azimuth in degrees about +y (0: the sun towards +z, 90: towards +x)")
          .slider(UiHint::kLinear, -180.0, 180.0),
      float_param("sun_elevation", 45.0f, -90.0f, 90.0f,
                  "PRT sun: elevation in degrees above the xz plane"),
      float_param("sun_irradiance", kPi, 0.0f, 1e6f,
                  "PRT sun: irradiance E on a surface facing it (π: a white surface facing it "
                  "shows radiance 1, as illum relight's default)")
          .slider(UiHint::kLogarithmic, 0.01, 100),
      enum_param("prt_lookup", "auto", {"auto", "texels", "vertices", "vq"},
                 "PRT lookup (illum relight --lookup): auto = texels when baked, else vertices")
          .structural(),
      enum_param("probe_lookup", "pixel", {"pixel", "instance"},
                 "dynamic instances: pixel = trilinear SH-L2 lookup of the probe volume per pixel "
                 "with validity weights; instance = one ambient cube per instance at its centre"),
  };
  t.create = [](TechniqueContext& ctx) -> std::unique_ptr<Technique> {
    return std::make_unique<Baked>(ctx, *find_technique("baked"));
  };
  return t;
}

}  // namespace illum::realtime
