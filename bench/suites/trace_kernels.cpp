// Google Benchmark kernels for the trace layer on a procedural mesh: single-ray closest
// hit, occlusion, 1024-ray streams, interaction(), and the raw Embree calls they wrap
// (single, stream, 16-wide packet) so the overhead of the wrapper is visible in one run.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <cmath>
#include <vector>

#include "illum/core/rng.h"
#include "illum/core/sampling.h"
#include "illum/trace/ray_tracer.h"

namespace illum {
namespace {

constexpr size_t kRayCount = 1 << 16;
constexpr size_t kStream = 1024;

// A closed, bumpy sphere (radius 1 ± 0.15) of 2·rings·segments triangles: enough
// structure for a non-trivial BVH, and every ray from inside hits it.
Mesh bumpy_sphere(int rings, int segments) {
  Mesh mesh;
  mesh.name = "bumpy-sphere";
  for (int i = 0; i <= rings; ++i) {
    const float theta = kPi * static_cast<float>(i) / rings;
    for (int j = 0; j <= segments; ++j) {
      const float phi = 2.0f * kPi * static_cast<float>(j) / segments;
      const vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta),
                   std::sin(theta) * std::sin(phi));
      const float r = 1.0f + 0.15f * std::sin(7.0f * theta) * std::cos(5.0f * phi);
      mesh.positions.push_back(r * d);
      mesh.normals.push_back(d);
      mesh.uv0.push_back(vec2(static_cast<float>(j) / segments, static_cast<float>(i) / rings));
    }
  }
  auto id = [segments](int i, int j) { return static_cast<uint32_t>(i * (segments + 1) + j); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      mesh.indices.insert(mesh.indices.end(), {id(i, j), id(i + 1, j), id(i, j + 1)});
      mesh.indices.insert(mesh.indices.end(), {id(i, j + 1), id(i + 1, j), id(i + 1, j + 1)});
    }
  return mesh;
}

struct Fixture {
  Scene scene;
  std::unique_ptr<RayTracer> tracer;
  std::vector<Ray> rays;         // closest-hit: from inside, unbounded
  std::vector<Ray> shadow_rays;  // occlusion: random extents, about half blocked

  Fixture() {
    scene.name = "bumpy-sphere";
    scene.meshes.push_back(bumpy_sphere(256, 512));  // 262,144 triangles
    scene.materials.push_back(Material{});
    scene.instances.push_back(Instance{});
    tracer = std::make_unique<RayTracer>(scene);
    Rng rng(7);
    for (size_t i = 0; i < kRayCount; ++i) {
      Ray r;
      r.origin = 0.6f * (vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 0.5f);
      r.direction = sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
      rays.push_back(r);
      r.tmax = 1.7f * rng.next_float();
      shadow_rays.push_back(r);
    }
  }
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

void BM_IntersectSingle(benchmark::State& state) {
  const Fixture& f = fixture();
  size_t i = 0;
  Hit hit;
  for (auto _ : state) {
    benchmark::DoNotOptimize(f.tracer->intersect(f.rays[i], &hit));
    i = (i + 1) % kRayCount;
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
}
BENCHMARK(BM_IntersectSingle);

void BM_OccludedSingle(benchmark::State& state) {
  const Fixture& f = fixture();
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(f.tracer->occluded(f.shadow_rays[i]));
    i = (i + 1) % kRayCount;
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
}
BENCHMARK(BM_OccludedSingle);

void BM_IntersectStream1024(benchmark::State& state) {
  const Fixture& f = fixture();
  std::vector<Hit> hits(kStream);
  size_t offset = 0;
  for (auto _ : state) {
    f.tracer->intersect(std::span<const Ray>(f.rays).subspan(offset, kStream), hits);
    benchmark::DoNotOptimize(hits.data());
    offset = (offset + kStream) % kRayCount;
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kStream));
}
BENCHMARK(BM_IntersectStream1024);

void BM_OccludedStream1024(benchmark::State& state) {
  const Fixture& f = fixture();
  std::vector<uint8_t> blocked(kStream);
  size_t offset = 0;
  for (auto _ : state) {
    f.tracer->occluded(std::span<const Ray>(f.shadow_rays).subspan(offset, kStream), blocked);
    benchmark::DoNotOptimize(blocked.data());
    offset = (offset + kStream) % kRayCount;
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kStream));
}
BENCHMARK(BM_OccludedStream1024);

void BM_Interaction(benchmark::State& state) {
  const Fixture& f = fixture();
  std::vector<Hit> hits(kRayCount);
  f.tracer->intersect(f.rays, hits);
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(f.tracer->interaction(f.rays[i], hits[i]));
    i = (i + 1) % kRayCount;
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
}
BENCHMARK(BM_Interaction);

// --- raw Embree, for the wrapper's overhead ----------------------------------------------

void fill(const Ray& ray, RTCRayHit* rh) {
  rh->ray.org_x = ray.origin.x;
  rh->ray.org_y = ray.origin.y;
  rh->ray.org_z = ray.origin.z;
  rh->ray.tnear = ray.tmin;
  rh->ray.dir_x = ray.direction.x;
  rh->ray.dir_y = ray.direction.y;
  rh->ray.dir_z = ray.direction.z;
  rh->ray.time = 0.0f;
  rh->ray.tfar = ray.tmax;
  rh->ray.mask = 0xffffffffu;
  rh->ray.id = 0;
  rh->ray.flags = 0;
  rh->hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

void BM_RawEmbreeIntersect1(benchmark::State& state) {
  const Fixture& f = fixture();
  const RTCScene scene = static_cast<RTCScene>(f.tracer->embree_scene());
  size_t i = 0;
  for (auto _ : state) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    fill(f.rays[i], &rh);
    rtcIntersect1(scene, &context, &rh);
    benchmark::DoNotOptimize(rh.hit.primID);
    i = (i + 1) % kRayCount;
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
}
BENCHMARK(BM_RawEmbreeIntersect1);

// rtcIntersect1M over 1024 rays with the incoherent (default) and coherent context flags.
void BM_RawEmbreeIntersect1M(benchmark::State& state) {
  const Fixture& f = fixture();
  const RTCScene scene = static_cast<RTCScene>(f.tracer->embree_scene());
  std::vector<RTCRayHit> rh(kStream);
  size_t offset = 0;
  for (auto _ : state) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    if (state.range(0)) context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    for (size_t k = 0; k < kStream; ++k) fill(f.rays[offset + k], &rh[k]);
    rtcIntersect1M(scene, &context, rh.data(), kStream, sizeof(RTCRayHit));
    benchmark::DoNotOptimize(rh.data());
    offset = (offset + kStream) % kRayCount;
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kStream));
}
BENCHMARK(BM_RawEmbreeIntersect1M)->Arg(0)->Arg(1);

// 16-wide SoA packets (rtcIntersect16), the alternative to streams for batches.
void BM_RawEmbreeIntersect16(benchmark::State& state) {
  const Fixture& f = fixture();
  const RTCScene scene = static_cast<RTCScene>(f.tracer->embree_scene());
  alignas(64) RTCRayHit16 packet;
  alignas(64) int valid[16];
  for (int& v : valid) v = -1;
  size_t offset = 0;
  for (auto _ : state) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t base = 0; base < kStream; base += 16) {
      for (int k = 0; k < 16; ++k) {
        const Ray& r = f.rays[offset + base + k];
        packet.ray.org_x[k] = r.origin.x;
        packet.ray.org_y[k] = r.origin.y;
        packet.ray.org_z[k] = r.origin.z;
        packet.ray.tnear[k] = r.tmin;
        packet.ray.dir_x[k] = r.direction.x;
        packet.ray.dir_y[k] = r.direction.y;
        packet.ray.dir_z[k] = r.direction.z;
        packet.ray.time[k] = 0.0f;
        packet.ray.tfar[k] = r.tmax;
        packet.ray.mask[k] = 0xffffffffu;
        packet.ray.id[k] = 0;
        packet.ray.flags[k] = 0;
        packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, scene, &context, &packet);
      benchmark::DoNotOptimize(packet.hit.primID);
    }
    offset = (offset + kStream) % kRayCount;
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kStream));
}
BENCHMARK(BM_RawEmbreeIntersect16);

}  // namespace
}  // namespace illum

BENCHMARK_MAIN();
