#include "prt_direct_spread.h"

#include <algorithm>

namespace illum::bench {

namespace {

// Calls visit(pixel index, hit or nullptr on a miss, interaction, taps) for every primary ray
// of bake::relight's sample grid, with the four bilinear taps its lookup reads (texel
// indices into the raster; relight_sample_offset and bilinear_texel_taps are relight's own).
template <typename Visit>
void for_each_lookup(const RayTracer& tracer, const atlas::TexelRaster& raster,
                     const Camera& camera, const bake::RelightOptions& relight, Visit&& visit) {
  const int w = raster.width, h = raster.height;
  for (int py = 0; py < relight.height; ++py)
    for (int px = 0; px < relight.width; ++px)
      for (int s = 0; s < relight.samples; ++s) {
        const vec2 f = bake::relight_sample_offset(s, relight.samples);
        const Ray ray =
            camera.generate_ray(float(px) + f.x, float(py) + f.y, relight.width, relight.height);
        const size_t pixel = size_t(py) * size_t(relight.width) + size_t(px);
        Hit hit;
        if (!tracer.intersect(ray, &hit)) {
          visit(pixel, static_cast<const Hit*>(nullptr), SurfaceInteraction{}, nullptr);
          continue;
        }
        const SurfaceInteraction si = tracer.interaction(ray, hit);
        const bake::TexelTaps lookup = bake::bilinear_texel_taps(si.uv1, w, h);
        size_t taps[4];
        for (int k = 0; k < 4; ++k) taps[k] = size_t(lookup.y[k]) * size_t(w) + size_t(lookup.x[k]);
        visit(pixel, &hit, si, taps);
      }
}

}  // namespace

atlas::TexelRaster texels_seen(const RayTracer& tracer, const atlas::TexelRaster& raster,
                               const Camera& camera, const bake::RelightOptions& relight,
                               int margin) {
  const int w = raster.width, h = raster.height;
  std::vector<uint8_t> tap(size_t(w) * size_t(h), 0);
  for_each_lookup(tracer, raster, camera, relight,
                  [&](size_t, const Hit* hit, const SurfaceInteraction&, const size_t* taps) {
                    if (hit)
                      for (int k = 0; k < 4; ++k) tap[taps[k]] = 1;
                  });
  atlas::TexelRaster seen;
  seen.width = w;
  seen.height = h;
  seen.sample_of.assign(raster.sample_of.size(), -1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int32_t s = raster.at(x, y);
      if (s < 0) continue;
      bool near = false;
      for (int dy = -margin; dy <= margin && !near; ++dy)
        for (int dx = -margin; dx <= margin && !near; ++dx) {
          const int xx = x + dx, yy = y + dy;
          near = xx >= 0 && yy >= 0 && xx < w && yy < h && tap[size_t(yy) * size_t(w) + size_t(xx)];
        }
      if (!near) continue;
      seen.sample_of[size_t(y) * size_t(w) + size_t(x)] = int32_t(seen.samples.size());
      seen.samples.push_back(raster.samples[size_t(s)]);
    }
  return seen;
}

std::vector<char> interior_lookups(const RayTracer& tracer, const atlas::TexelRaster& raster,
                                   const Camera& camera, const bake::RelightOptions& relight) {
  std::vector<char> interior(size_t(relight.width) * size_t(relight.height), 1);
  for_each_lookup(
      tracer, raster, camera, relight,
      [&](size_t pixel, const Hit* hit, const SurfaceInteraction& si, const size_t* taps) {
        char& inside = interior[pixel];
        if (!hit) {
          inside = 0;
          return;
        }
        for (int k = 0; k < 4 && inside; ++k) {
          const int32_t t = raster.sample_of[taps[k]];
          inside = t >= 0 && raster.samples[size_t(t)].instance == int(hit->instance) &&
                   glm::dot(raster.samples[size_t(t)].geometric_normal, si.ng) >= 0.999f;
        }
      });
  return interior;
}

std::vector<std::vector<Image>> direct_relit_over_seeds(const Scene& scene, const RayTracer& tracer,
                                                        const atlas::TexelRaster& seen,
                                                        const std::vector<bake::ShLight>& lights,
                                                        const Camera& camera,
                                                        const bake::RelightOptions& relight,
                                                        bake::PrtBakeOptions options,
                                                        uint64_t first_seed, int seeds) {
  options.mode = bake::PrtMode::kShadowed;
  options.stitch = false;
  options.vertices = false;
  options.texels = true;
  options.progress = false;
  std::vector<std::vector<Image>> images(size_t(std::max(seeds, 0)));
  for (int j = 0; j < seeds; ++j) {
    options.seed = first_seed + uint64_t(j);
    bake::PrtBake baked = bake::bake_prt(scene, tracer, seen, options);
    baked::PrtSet set;
    set.bands = baked.bands;
    set.mode = baked.mode;
    set.texel_transfer = std::move(baked.texel_transfer);
    for (const bake::ShLight& light : lights)
      images[size_t(j)].push_back(bake::relight(scene, tracer, set, light, camera, relight));
  }
  return images;
}

}  // namespace illum::bench
