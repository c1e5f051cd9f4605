#include "illum/render/photon_tracer.h"

#include <chrono>

namespace illum {

namespace {

struct TaggedPhoton {
  Photon photon;
  uint8_t map;  // 0 global, 1 shadow
};

Photon to_photon(const PhotonEvent& ev, float scale) {
  return Photon{ev.p, ev.wi, ev.power * scale, ev.ng};
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

PhotonMaps build_photon_maps(const RayTracer& tracer, const LightSampler& lights,
                             const PhotonMapSettings& settings) {
  PhotonMaps maps;
  auto t0 = std::chrono::steady_clock::now();
  std::vector<Photon> caustic;
  if (settings.caustic_photons > 0) {
    const float scale = 1.0f / static_cast<float>(settings.caustic_photons);
    PhotonPathSettings path = settings.path;
    path.shadow_photons = false;
    caustic = trace_photons_parallel<Photon>(
        lights, settings.caustic_photons, settings.seed, 0xC0C0,
        [&](int64_t, const LightEmission& e, Rng& rng, std::vector<Photon>& sink) {
          trace_photon_path(
              tracer, e, rng, path,
              [&](const PhotonEvent& ev) {
                // The first non-delta hit ends every caustic path, stored or not.
                if (ev.specular_bounces > 0 && ev.diffuse_bounces == 0)
                  sink.push_back(to_photon(ev, scale));
                return false;
              },
              [](const PhotonEvent&) {});
        });
    maps.caustic_emitted = settings.caustic_photons;
  }
  std::vector<Photon> global, shadow;
  if (settings.global_photons > 0) {
    const float scale = 1.0f / static_cast<float>(settings.global_photons);
    const bool with_shadow = settings.path.shadow_photons;
    std::vector<TaggedPhoton> all = trace_photons_parallel<TaggedPhoton>(
        lights, settings.global_photons, settings.seed, 0x610B,
        [&](int64_t, const LightEmission& e, Rng& rng, std::vector<TaggedPhoton>& sink) {
          trace_photon_path(
              tracer, e, rng, settings.path,
              [&](const PhotonEvent& ev) {
                if (ev.diffuse_bounces > 0) sink.push_back({to_photon(ev, scale), 0});
                if (with_shadow && ev.depth == 0) sink.push_back({to_photon(ev, scale), 1});
                return true;
              },
              [&](const PhotonEvent& ev) {
                sink.push_back({to_photon(ev, scale), 1});
              });
        });
    for (const TaggedPhoton& t : all) (t.map == 0 ? global : shadow).push_back(t.photon);
    maps.global_emitted = settings.global_photons;
  }
  maps.trace_seconds = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  maps.global = PhotonMap(std::move(global));
  maps.caustic = PhotonMap(std::move(caustic));
  maps.shadow = PhotonMap(std::move(shadow));
  maps.build_seconds = seconds_since(t0);
  return maps;
}

}  // namespace illum
