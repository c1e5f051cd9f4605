#include "illum/trace/ray_tracer.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "illum/core/error.h"
#include "illum/scene/normal_map.h"

namespace illum {

namespace {

// Embree's stream API works on chunks; 64 matches its internal stream size and keeps the
// staging arrays (64 × 80 bytes) on the stack, so batches never allocate.
constexpr size_t kStreamChunk = 64;

const char* embree_error_name(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE:
      return "RTC_ERROR_NONE";
    case RTC_ERROR_UNKNOWN:
      return "RTC_ERROR_UNKNOWN";
    case RTC_ERROR_INVALID_ARGUMENT:
      return "RTC_ERROR_INVALID_ARGUMENT";
    case RTC_ERROR_INVALID_OPERATION:
      return "RTC_ERROR_INVALID_OPERATION";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "RTC_ERROR_OUT_OF_MEMORY";
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "RTC_ERROR_UNSUPPORTED_CPU";
    case RTC_ERROR_CANCELLED:
      return "RTC_ERROR_CANCELLED";
  }
  return "RTC_ERROR_?";
}

inline void to_embree(const Ray& ray, RTCRay* r) {
  r->org_x = ray.origin.x;
  r->org_y = ray.origin.y;
  r->org_z = ray.origin.z;
  r->tnear = ray.tmin;
  r->dir_x = ray.direction.x;
  r->dir_y = ray.direction.y;
  r->dir_z = ray.direction.z;
  r->time = 0.0f;
  r->tfar = ray.tmax;
  r->mask = 0xffffffffu;
  r->id = 0;
  r->flags = 0;
}

inline void to_embree(const Ray& ray, RTCRayHit* rh) {
  to_embree(ray, &rh->ray);
  rh->hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh->hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

// Embree's (u, v) are the weights of v1 and v2, the same convention as Hit::barycentric.
inline bool from_embree(const RTCRayHit& rh, Hit* hit) {
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
    *hit = Hit{};
    return false;
  }
  hit->t = rh.ray.tfar;
  hit->instance = rh.hit.geomID;
  hit->primitive = rh.hit.primID;
  hit->barycentric = vec2(rh.hit.u, rh.hit.v);
  return true;
}

// Rotates `v` out of the plane of `n` (Gram–Schmidt); returns false when nothing is left.
bool orthogonalize(const vec3& n, vec3* v) {
  const vec3 w = *v - glm::dot(*v, n) * n;
  const float len2 = glm::dot(w, w);
  if (!(len2 > 1e-12f) || !std::isfinite(len2)) return false;
  *v = w / std::sqrt(len2);
  return true;
}

// A shading normal that the geometry's own facing contradicts: seen at a grazing angle, a
// smoothed normal (averaged across a hard edge, as on Sibenik's capitals) can turn the
// viewer below its hemisphere while the triangle faces it, and every BSDF then returns
// nothing: black wedges along such edges, which the scene's true surface does not have.
// As Cycles does, the normal is bent towards ng until the mirror direction of wo leaves
// the geometric surface at least min(0.9·cos θg, 0.01) high (cos θg = wo·ng, on wo's side),
// the least bend found by bisection on the blend ns → ng (ng itself always qualifies: its
// mirror direction rises as steeply as wo). Normals that are already valid are untouched.
vec3 bent_for_valid_reflection(const vec3& ns, const vec3& ng, const vec3& wo) {
  const float side = glm::dot(wo, ng) < 0.0f ? -1.0f : 1.0f;
  const vec3 g = side * ng, n = side * ns;
  const float cos_g = glm::dot(g, wo);
  if (!(cos_g > 0.0f)) return ns;  // exactly grazing, or no direction (wo = 0)
  const float threshold = std::min(0.9f * cos_g, 0.01f);
  const auto rises = [&](const vec3& m) {
    return glm::dot(g, 2.0f * glm::dot(m, wo) * m - wo) >= threshold;
  };
  if (rises(n)) return ns;
  float lo = 0.0f, hi = 1.0f;
  for (int i = 0; i < 20; ++i) {
    const float mid = 0.5f * (lo + hi);
    (rises(glm::normalize(glm::mix(n, g, mid))) ? hi : lo) = mid;
  }
  return side * glm::normalize(glm::mix(n, g, hi));
}

}  // namespace

struct RayTracer::Impl {
  // Everything interaction() needs about one instance, in world space.
  // The per-vertex attributes interaction() reads for one triangle, gathered so that a hit
  // touches two or three adjacent cache lines instead of the index buffer plus three
  // scattered vertices in each of four arrays (Sibenik: 17 % of the render time was
  // interaction() waiting for those loads). Absent attributes are zero; the mesh-level
  // flags say which are real.
  struct TriangleRecord {
    vec3 p[3];   // world-space positions (the same values as `positions`)
    vec3 n[3];   // object-space vertex normals
    vec2 uv[3];  // uv0
    vec4 t[3];   // object-space tangents
  };

  struct InstanceData {
    const Mesh* mesh = nullptr;
    std::vector<TriangleRecord> triangles;
    bool has_normals = false, has_uv0 = false, has_tangents = false;
    // World-space positions (see the constructor for the two extra elements at the end).
    std::vector<vec3> positions;
    // A copy of the mesh's indices with degenerate triangles disabled; empty when the
    // mesh has none and Embree reads Mesh::indices directly.
    std::vector<uint32_t> culled_indices;
    mat3 linear{1.0f};         // object → world for directions (tangents)
    mat3 normal_matrix{1.0f};  // inverse transpose of `linear`, for normals
    int light = -1;
  };

  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<InstanceData> instances;
  Bounds3 bounds;

  // Embree reports errors through a C callback, possibly from its build threads; C++
  // exceptions must not unwind through it, so the first message is recorded here and
  // thrown by `throw_if_error` after the call returns.
  std::mutex error_mutex;
  std::string error;

  static void on_error(void* user, RTCError code, const char* message) {
    auto* self = static_cast<Impl*>(user);
    std::lock_guard lock(self->error_mutex);
    if (self->error.empty())
      self->error = fmt::format("{}: {}", embree_error_name(code), message ? message : "");
  }

  void throw_if_error(const Scene& s, const char* during) {
    std::string message;
    {
      std::lock_guard lock(error_mutex);
      message.swap(error);
    }
    if (message.empty()) {
      const RTCError code = rtcGetDeviceError(device);
      if (code == RTC_ERROR_NONE) return;
      message = embree_error_name(code);
    }
    throw Error(fmt::format("scene '{}'{}: Embree error while {}: {}", s.name,
                            s.source_path.empty() ? "" : " (" + s.source_path + ")", during,
                            message));
  }

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

RayTracer::RayTracer(const Scene& scene) : scene_(scene), impl_(std::make_unique<Impl>()) {
  Impl& im = *impl_;
  const std::string where = fmt::format(
      "scene '{}'{}", scene.name, scene.source_path.empty() ? "" : " (" + scene.source_path + ")");

  // ILLUM_EMBREE_CONFIG passes an Embree device configuration (e.g. "threads=1,verbose=1")
  // for profiling and debugging without a rebuild.
  const char* config = std::getenv("ILLUM_EMBREE_CONFIG");
  im.device = rtcNewDevice(config);
  if (!im.device)
    throw Error(fmt::format("{}: cannot create the Embree device{}{}: {}", where,
                            config ? " with ILLUM_EMBREE_CONFIG=" : "", config ? config : "",
                            embree_error_name(rtcGetDeviceError(nullptr))));
  rtcSetDeviceErrorFunction(im.device, &Impl::on_error, &im);

  im.scene = rtcNewScene(im.device);
  // Robust: no traversal shortcuts that can miss hits at shared edges or grazing angles;
  // the renderers rely on closed meshes staying closed.
  rtcSetSceneFlags(im.scene, RTC_SCENE_FLAG_ROBUST);
  // Static scenes are built once and traced many times: spend the time on a SAH build
  // with spatial splits.
  rtcSetSceneBuildQuality(im.scene, RTC_BUILD_QUALITY_HIGH);
  im.throw_if_error(scene, "creating the scene");

  im.instances.resize(scene.instances.size());
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& light = scene.lights[i];
    if (light.type != LightType::kArea) continue;
    if (light.instance < 0 || static_cast<size_t>(light.instance) >= scene.instances.size())
      throw Error(fmt::format("{}: area light '{}' refers to instance {} of {}", where, light.name,
                              light.instance, scene.instances.size()));
    int& slot = im.instances[static_cast<size_t>(light.instance)].light;
    if (slot < 0) slot = static_cast<int>(i);  // first declaration wins
  }

  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    Impl::InstanceData& data = im.instances[i];
    if (inst.mesh < 0 || static_cast<size_t>(inst.mesh) >= scene.meshes.size())
      throw Error(fmt::format("{}: instance '{}' refers to mesh {} of {}", where, inst.name,
                              inst.mesh, scene.meshes.size()));
    const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
    data.mesh = &mesh;
    data.linear = mat3(inst.transform);
    const float det = glm::determinant(data.linear);
    if (!(std::abs(det) > 0.0f) || !std::isfinite(det))
      throw Error(fmt::format("{}: instance '{}' has a singular or non-finite transform", where,
                              inst.name));
    data.normal_matrix = glm::transpose(glm::inverse(data.linear));

    if (mesh.indices.size() % 3 != 0)
      throw Error(fmt::format("{}: mesh '{}' has {} indices, not a multiple of 3", where, mesh.name,
                              mesh.indices.size()));
    const size_t vertex_count = mesh.positions.size();
    for (uint32_t index : mesh.indices)
      if (index >= vertex_count)
        throw Error(fmt::format("{}: mesh '{}' has vertex index {} of {}", where, mesh.name, index,
                                vertex_count));

    // Layout: the world-space vertices, then a NaN sentinel that degenerate triangles are
    // pointed at, then padding for Embree's 16-byte loads past the last vertex.
    const uint32_t sentinel = static_cast<uint32_t>(vertex_count);
    data.positions.resize(vertex_count + 2, vec3(0.0f));
    data.positions[sentinel] = vec3(std::numeric_limits<float>::quiet_NaN());
    for (size_t v = 0; v < vertex_count; ++v) {
      const vec3 p = vec3(inst.transform * vec4(mesh.positions[v], 1.0f));
      data.positions[v] = p;
      // Embree skips triangles with non-finite vertices; keep them out of the bounds too.
      if (is_finite(p)) im.bounds.extend(p);
    }
    if (mesh.indices.empty()) continue;  // nothing to hit; the id stays unused

    data.has_normals = mesh.normals.size() == vertex_count;
    data.has_uv0 = mesh.uv0.size() == vertex_count;
    data.has_tangents = mesh.tangents.size() == vertex_count;
    data.triangles.resize(mesh.triangle_count());
    for (size_t f = 0; f < data.triangles.size(); ++f) {
      Impl::TriangleRecord& r = data.triangles[f];
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = mesh.indices[3 * f + static_cast<size_t>(k)];
        r.p[k] = data.positions[v];
        r.n[k] = data.has_normals ? mesh.normals[v] : vec3(0.0f);
        r.uv[k] = data.has_uv0 ? mesh.uv0[v] : vec2(0.0f);
        r.t[k] = data.has_tangents ? mesh.tangents[v] : vec4(0.0f);
      }
    }

    // Zero-area triangles (repeated or collinear vertices, in world space) have no
    // well-defined normal, yet Embree's float arithmetic can report hits on them for rays
    // aimed exactly along them. Embree drops triangles with a NaN vertex at build time, so
    // those triangles get a private index buffer entry pointing at the sentinel; the
    // shared mesh indices are used as they are when there are none (the common case:
    // loaders already drop them).
    const size_t triangle_count = mesh.triangle_count();
    const uint32_t* indices = mesh.indices.data();
    for (size_t f = 0; f < triangle_count; ++f) {
      const uint32_t* tri = &mesh.indices[3 * f];
      const glm::dvec3 a(data.positions[tri[0]]), b(data.positions[tri[1]]),
          c(data.positions[tri[2]]);
      const glm::dvec3 n = glm::cross(b - a, c - a);
      if (n.x != 0.0 || n.y != 0.0 || n.z != 0.0) continue;
      if (data.culled_indices.empty()) data.culled_indices = mesh.indices;
      std::fill_n(&data.culled_indices[3 * f], 3, sentinel);
    }
    if (!data.culled_indices.empty()) indices = data.culled_indices.data();

    RTCGeometry geom = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                               data.positions.data(), 0, sizeof(vec3), vertex_count + 1);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices, 0,
                               3 * sizeof(uint32_t), triangle_count);
    rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_HIGH);
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(im.scene, geom, static_cast<unsigned>(i));
    rtcReleaseGeometry(geom);
    im.throw_if_error(scene, fmt::format("adding instance '{}'", inst.name).c_str());
  }

  rtcCommitScene(im.scene);
  im.throw_if_error(scene, "building the BVH");
}

RayTracer::~RayTracer() = default;

bool RayTracer::intersect(const Ray& ray, Hit* hit) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  to_embree(ray, &rh);
  rtcIntersect1(impl_->scene, &context, &rh);
  return from_embree(rh, hit);
}

bool RayTracer::occluded(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r;
  to_embree(ray, &r);
  rtcOccluded1(impl_->scene, &context, &r);
  return r.tfar < 0.0f;  // Embree sets tfar to −inf on a hit
}

void RayTracer::intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
  ILLUM_CHECK(hits.size() >= rays.size(), "{} hits for {} rays", hits.size(), rays.size());
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit staging[kStreamChunk];
  for (size_t begin = 0; begin < rays.size(); begin += kStreamChunk) {
    const size_t n = std::min(kStreamChunk, rays.size() - begin);
    for (size_t i = 0; i < n; ++i) to_embree(rays[begin + i], &staging[i]);
    rtcIntersect1M(impl_->scene, &context, staging, static_cast<unsigned>(n), sizeof(RTCRayHit));
    for (size_t i = 0; i < n; ++i) from_embree(staging[i], &hits[begin + i]);
  }
}

void RayTracer::occluded(std::span<const Ray> rays, std::span<uint8_t> blocked) const {
  ILLUM_CHECK(blocked.size() >= rays.size(), "{} results for {} rays", blocked.size(), rays.size());
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay staging[kStreamChunk];
  for (size_t begin = 0; begin < rays.size(); begin += kStreamChunk) {
    const size_t n = std::min(kStreamChunk, rays.size() - begin);
    for (size_t i = 0; i < n; ++i) to_embree(rays[begin + i], &staging[i]);
    rtcOccluded1M(impl_->scene, &context, staging, static_cast<unsigned>(n), sizeof(RTCRay));
    for (size_t i = 0; i < n; ++i) blocked[begin + i] = staging[i].tfar < 0.0f ? 1 : 0;
  }
}

SurfaceInteraction RayTracer::interaction(const Ray& ray, const Hit& hit) const {
  ILLUM_CHECK(hit.valid() && hit.instance < impl_->instances.size(), "invalid hit (instance {})",
              hit.instance);
  const Impl::InstanceData& data = impl_->instances[hit.instance];
  const Mesh& mesh = *data.mesh;
  ILLUM_CHECK(hit.primitive < mesh.triangle_count(), "primitive {} of {}", hit.primitive,
              mesh.triangle_count());
  const Impl::TriangleRecord& tri = data.triangles[hit.primitive];
  SurfaceInteraction si;
  si.t = hit.t;
  si.instance = hit.instance;
  si.primitive = hit.primitive;
  si.material = mesh.material;
  si.light = data.light;

  // The point from the barycentrics on the world-space triangle, not origin + t·dir: the
  // latter carries the error of t times the ray length and can land behind the surface.
  const float b1 = hit.barycentric.x, b2 = hit.barycentric.y, b0 = 1.0f - b1 - b2;
  const vec3& p0 = tri.p[0];
  const vec3& p1 = tri.p[1];
  const vec3& p2 = tri.p[2];
  si.p = b0 * p0 + b1 * p1 + b2 * p2;

  const vec3 e1 = p1 - p0, e2 = p2 - p0;
  const vec3 cross = glm::cross(e1, e2);
  const float cross_len = glm::length(cross);
  si.ng = cross_len > 0.0f ? cross / cross_len : vec3(0.0f, 0.0f, 1.0f);

  const float dir_len = glm::length(ray.direction);
  si.wo = dir_len > 0.0f ? -ray.direction / dir_len : vec3(0.0f);

  vec2 uv0(0.0f);
  const bool has_uv0 = data.has_uv0;
  if (has_uv0) uv0 = b0 * tri.uv[0] + b1 * tri.uv[1] + b2 * tri.uv[2];
  si.uv0 = uv0;
  if (mesh.uv1.size() == mesh.positions.size()) {  // light-map uvs: bakers only, not gathered
    const uint32_t* idx = &mesh.indices[3 * static_cast<size_t>(hit.primitive)];
    si.uv1 = b0 * mesh.uv1[idx[0]] + b1 * mesh.uv1[idx[1]] + b2 * mesh.uv1[idx[2]];
  }

  // Shading normal: interpolated vertex normals, carried to world space by the normal
  // matrix, then put on ng's side. ng (the winding) is the authority on which side is
  // "front"; a vertex normal that disagrees with it is an artefact of smoothing (or of a
  // mirroring transform) and would make the shading frame point into the surface.
  const bool has_normals = data.has_normals;
  vec3 n_obj(0.0f);
  vec3 ns = si.ng;
  if (has_normals) {
    n_obj = b0 * tri.n[0] + b1 * tri.n[1] + b2 * tri.n[2];
    const vec3 n = data.normal_matrix * n_obj;
    const float len = glm::length(n);
    if (len > 0.0f && std::isfinite(len)) ns = n / len;
  }
  if (glm::dot(ns, si.ng) < 0.0f) ns = -ns;

  // Tangent and bitangent in world space: the mesh's tangent (glTF: bitangent = w · n × t,
  // formed in object space so mirroring transforms and the ng-side flip above cannot turn
  // it around), carried by the object→world matrix since both are directions, not normals.
  // Without mesh tangents but with uv0, ∂p/∂u and ∂p/∂v of the triangle, so a normal map
  // still follows the texture; otherwise the frame is any one around ns.
  vec3 tangent(0.0f), bitangent(0.0f);
  bool has_tangent = false;
  if (data.has_tangents) {
    const vec4 t4 = b0 * tri.t[0] + b1 * tri.t[1] + b2 * tri.t[2];
    const vec3 n_ref = has_normals ? n_obj : glm::cross(e1, e2);
    tangent = data.linear * vec3(t4);
    bitangent = data.linear * ((t4.w < 0.0f ? -1.0f : 1.0f) * glm::cross(n_ref, vec3(t4)));
    has_tangent = true;
  } else if (has_uv0) {
    const vec2 d1 = tri.uv[1] - tri.uv[0], d2 = tri.uv[2] - tri.uv[0];
    const float det = d1.x * d2.y - d1.y * d2.x;
    if (std::abs(det) > 1e-20f) {
      tangent = (d2.y * e1 - d1.y * e2) / det;
      bitangent = (d1.x * e2 - d2.x * e1) / det;
      has_tangent = true;
    }
  }
  if (has_tangent) has_tangent = orthogonalize(ns, &tangent);

  // Normal mapping (scene/normal_map.h: the glTF convention).
  if (has_tangent && has_uv0 && si.material >= 0 &&
      static_cast<size_t>(si.material) < scene_.materials.size()) {
    const Material& material = scene_.materials[static_cast<size_t>(si.material)];
    const Image* map = normal_map_of(scene_, material);
    vec3 mapped;
    if (map && orthogonalize(ns, &bitangent) &&
        mapped_normal(*map, material.normal_scale, uv0, tangent, bitangent, ns, &mapped)) {
      ns = glm::dot(mapped, si.ng) < 0.0f ? -mapped : mapped;
      has_tangent = orthogonalize(ns, &tangent);
    }
  }

  const vec3 bent = bent_for_valid_reflection(ns, si.ng, si.wo);
  if (bent != ns) {
    ns = bent;
    if (has_tangent) has_tangent = orthogonalize(ns, &tangent);
  }
  si.ns = ns;
  if (has_tangent)
    si.shading = Frame(tangent, glm::cross(ns, tangent), ns);  // right-handed: t × b = n
  else
    si.shading = Frame::from_normal(ns);
  return si;
}

Bounds3 RayTracer::bounds() const {
  return impl_->bounds;
}

void* RayTracer::embree_scene() const {
  return impl_->scene;
}

}  // namespace illum
