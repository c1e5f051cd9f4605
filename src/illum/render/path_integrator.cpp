#include "illum/render/path_integrator.h"

#include <tbb/enumerable_thread_specific.h>

#include <functional>

#include "illum/core/error.h"
#include "illum/render/light_sampler.h"
#include "illum/render/path_radiance.h"

namespace illum {

PathIntegrator::PathIntegrator(const Params& params) {
  max_bounces_ = params.get_int_in("max_bounces", 8, 0, 1024);
  rr_depth_ = params.get_int_in("rr_depth", 3, 1, 1024);
  const std::string mode = params.get<std::string>("bounces", "all");
  if (mode == "all") {
    bounces_ = Bounces::kAll;
  } else if (mode == "direct") {
    bounces_ = Bounces::kDirect;
  } else if (mode == "indirect1") {
    bounces_ = Bounces::kIndirect1;
  } else {
    throw Error(fmt::format("{}: bounces must be all, direct or indirect1, not '{}'",
                            params.where("bounces"), mode));
  }
}

Image PathIntegrator::render(const RayTracer& tracer, const Camera& camera,
                             const RenderOptions& options) {
  warn_about_scene(tracer.scene(), true, "path");
  const LightSampler lights(tracer.scene());
  PathRadianceOptions transport;
  transport.max_bounces = max_bounces_;
  transport.rr_depth = rr_depth_;
  if (bounces_ == Bounces::kDirect) transport.k_max = 1;
  if (bounces_ == Bounces::kIndirect1) transport.k_min = transport.k_max = 2;
  const PathRadiance pt(tracer, lights, transport);
  // Counted per thread: one shared atomic added to after every camera sample kept its
  // cache line moving between the cores. A native TLS key per instance makes local() a
  // pthread_getspecific instead of a search of TBB's table of threads.
  tbb::enumerable_thread_specific<int64_t, tbb::cache_aligned_allocator<int64_t>,
                                  tbb::ets_key_per_instance>
      rays(int64_t{0});
  stats_ = {};
  Image image = render_tiles(
      camera, options, "path",
      [&](const Ray& ray, SobolSampler& sampler) { return pt.camera(ray, sampler, &rays.local()); },
      &stats_.render);
  stats_.rays = rays.combine(std::plus<int64_t>());
  return image;
}

}  // namespace illum
