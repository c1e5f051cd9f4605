#include "illum/scene/mesh_processing.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "illum/core/error.h"
#include "illum/scene/scene_validation.h"

namespace illum {

namespace {

bool finite2(const vec2& v) {
  return std::isfinite(v.x) && std::isfinite(v.y);
}
bool finite4(const vec4& v) {
  return is_finite(vec3(v)) && std::isfinite(v.w);
}

void check_size(const Mesh& mesh, size_t size, const char* what, const std::string& origin) {
  if (size != 0 && size != mesh.positions.size())
    throw Error(fmt::format("{}: mesh '{}' has {} {} for {} vertices", origin, mesh.name, size,
                            what, mesh.positions.size()));
}

double squared_diagonal(const Mesh& mesh) {
  Bounds3 b;
  for (const vec3& p : mesh.positions) b.extend(p);
  const double d = static_cast<double>(b.diagonal());
  return d * d;
}

}  // namespace

void add_warning(Scene& scene, const std::string& message) {
  scene.warnings.push_back(message);
}

void validate_mesh(const Mesh& mesh, const std::string& origin, size_t material_count) {
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const bool ok = is_finite(mesh.positions[i]) &&
                    (i >= mesh.normals.size() || is_finite(mesh.normals[i])) &&
                    (i >= mesh.uv0.size() || finite2(mesh.uv0[i])) &&
                    (i >= mesh.uv1.size() || finite2(mesh.uv1[i])) &&
                    (i >= mesh.tangents.size() || finite4(mesh.tangents[i]));
    if (!ok)
      throw Error(fmt::format("{}: mesh '{}' has non-finite vertex {}", origin, mesh.name, i));
  }
  check_size(mesh, mesh.normals.size(), "normals", origin);
  check_size(mesh, mesh.uv0.size(), "uv0 coordinates", origin);
  check_size(mesh, mesh.uv1.size(), "uv1 coordinates", origin);
  check_size(mesh, mesh.tangents.size(), "tangents", origin);
  if (mesh.indices.size() % 3 != 0)
    throw Error(fmt::format("{}: mesh '{}' has {} indices, not a multiple of 3", origin, mesh.name,
                            mesh.indices.size()));
  for (size_t i = 0; i < mesh.indices.size(); ++i) {
    if (mesh.indices[i] >= mesh.positions.size())
      throw Error(
          fmt::format("{}: mesh '{}' triangle {} uses vertex {}, but it has only {} vertices",
                      origin, mesh.name, i / 3, mesh.indices[i], mesh.positions.size()));
  }
  if (mesh.material < 0 || static_cast<size_t>(mesh.material) >= material_count)
    throw Error(fmt::format("{}: mesh '{}' uses material {}, but there are {} materials", origin,
                            mesh.name, mesh.material, material_count));
}

bool is_degenerate_triangle(const vec3& a, const vec3& b, const vec3& c, uint32_t ia, uint32_t ib,
                            uint32_t ic, double scale_sq) {
  if (ia == ib || ib == ic || ia == ic) return true;
  if (a == b || b == c || a == c) return true;
  // Double precision so the cross product of long edges does not cancel to noise.
  const glm::dvec3 e1 = glm::dvec3(b) - glm::dvec3(a);
  const glm::dvec3 e2 = glm::dvec3(c) - glm::dvec3(a);
  const double area = 0.5 * glm::length(glm::cross(e1, e2));
  return area <= kDegenerateRelArea * scale_sq;
}

size_t drop_degenerate_triangles(Mesh& mesh) {
  const double scale_sq = squared_diagonal(mesh);
  size_t kept = 0;
  const size_t n = mesh.triangle_count();
  for (size_t t = 0; t < n; ++t) {
    const uint32_t i0 = mesh.indices[3 * t], i1 = mesh.indices[3 * t + 1],
                   i2 = mesh.indices[3 * t + 2];
    if (is_degenerate_triangle(mesh.positions[i0], mesh.positions[i1], mesh.positions[i2], i0, i1,
                               i2, scale_sq))
      continue;
    mesh.indices[3 * kept] = i0;
    mesh.indices[3 * kept + 1] = i1;
    mesh.indices[3 * kept + 2] = i2;
    ++kept;
  }
  mesh.indices.resize(3 * kept);
  return n - kept;
}

void compute_normals(Mesh& mesh) {
  const size_t nv = mesh.positions.size();
  if (mesh.normals.size() != nv) mesh.normals.assign(nv, vec3(0.0f));
  std::vector<bool> missing(nv);
  bool any_missing = false;
  for (size_t i = 0; i < nv; ++i) {
    missing[i] = glm::dot(mesh.normals[i], mesh.normals[i]) == 0.0f;
    any_missing = any_missing || missing[i];
  }
  if (any_missing) {
    // The unnormalized cross product is twice the triangle's area times its unit normal,
    // so summing it weights by area.
    std::vector<vec3> sum(nv, vec3(0.0f));
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
      const uint32_t i[3] = {mesh.indices[3 * t], mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]};
      const vec3 n = glm::cross(mesh.positions[i[1]] - mesh.positions[i[0]],
                                mesh.positions[i[2]] - mesh.positions[i[0]]);
      for (uint32_t v : i) sum[v] += n;
    }
    for (size_t v = 0; v < nv; ++v) {
      if (missing[v]) mesh.normals[v] = sum[v];
    }
  }
  for (vec3& n : mesh.normals) {
    const float len = glm::length(n);
    n = len > 0.0f && std::isfinite(len) ? n / len : vec3(0.0f, 1.0f, 0.0f);
  }
}

void compute_tangents(Mesh& mesh) {
  const size_t nv = mesh.positions.size();
  if (mesh.tangents.size() == nv && nv > 0) {
    for (size_t v = 0; v < nv; ++v) {
      const vec3 n = mesh.normals[v];
      vec3 t = vec3(mesh.tangents[v]);
      t -= n * glm::dot(n, t);
      const float len = glm::length(t);
      t = len > 1e-8f ? t / len : Frame::from_normal(n).t;
      mesh.tangents[v] = vec4(t, mesh.tangents[v].w < 0.0f ? -1.0f : 1.0f);
    }
    return;
  }
  mesh.tangents.clear();
  if (mesh.uv0.size() != nv || nv == 0) return;
  std::vector<vec3> tan(nv, vec3(0.0f)), bitan(nv, vec3(0.0f));
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    const uint32_t i[3] = {mesh.indices[3 * t], mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]};
    const vec3 e1 = mesh.positions[i[1]] - mesh.positions[i[0]];
    const vec3 e2 = mesh.positions[i[2]] - mesh.positions[i[0]];
    const vec2 d1 = mesh.uv0[i[1]] - mesh.uv0[i[0]];
    const vec2 d2 = mesh.uv0[i[2]] - mesh.uv0[i[0]];
    const float det = d1.x * d2.y - d2.x * d1.y;
    if (std::abs(det) < 1e-20f) continue;  // no uv parameterization on this triangle
    const vec3 tt = (e1 * d2.y - e2 * d1.y) / det;
    const vec3 bt = (e2 * d1.x - e1 * d2.x) / det;
    const float lt = glm::length(tt), lb = glm::length(bt);
    if (!(lt > 0.0f) || !(lb > 0.0f) || !std::isfinite(lt) || !std::isfinite(lb)) continue;
    // Corner-angle weights (as MikkTSpace) make the result independent of how a
    // polygon was split into triangles.
    for (int c = 0; c < 3; ++c) {
      const vec3 p = mesh.positions[i[c]];
      const vec3 a = mesh.positions[i[(c + 1) % 3]] - p;
      const vec3 b = mesh.positions[i[(c + 2) % 3]] - p;
      const float la = glm::length(a), lbb = glm::length(b);
      if (la <= 0.0f || lbb <= 0.0f) continue;
      const float angle = std::acos(std::clamp(glm::dot(a, b) / (la * lbb), -1.0f, 1.0f));
      tan[i[c]] += angle * tt / lt;
      bitan[i[c]] += angle * bt / lb;
    }
  }
  mesh.tangents.resize(nv);
  for (size_t v = 0; v < nv; ++v) {
    const vec3 n = mesh.normals[v];
    vec3 t = tan[v] - n * glm::dot(n, tan[v]);
    const float len = glm::length(t);
    t = len > 1e-8f ? t / len : Frame::from_normal(n).t;
    const float w = glm::dot(glm::cross(n, t), bitan[v]) < 0.0f ? -1.0f : 1.0f;
    mesh.tangents[v] = vec4(t, w);
  }
}

void transform_mesh(Mesh& mesh, const mat4& transform) {
  const mat3 linear(transform);
  const mat3 normal_matrix = glm::transpose(glm::inverse(linear));
  const float det = glm::determinant(linear);
  for (vec3& p : mesh.positions) p = vec3(transform * vec4(p, 1.0f));
  for (vec3& n : mesh.normals) {
    const vec3 m = normal_matrix * n;
    const float len = glm::length(m);
    n = len > 0.0f ? m / len : m;  // zero stays zero: "missing", filled later
  }
  for (vec4& t : mesh.tangents) {
    vec3 m = linear * vec3(t);
    const float len = glm::length(m);
    if (len > 0.0f) m /= len;
    t = vec4(m, det < 0.0f ? -t.w : t.w);
  }
  if (det < 0.0f) {
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
      std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
  }
}

void finalize_scene(Scene& scene, const std::string& origin) {
  for (const Mesh& mesh : scene.meshes) validate_mesh(mesh, origin, scene.materials.size());
  validate_scene_values(scene, origin);

  size_t dropped = 0;
  for (Mesh& mesh : scene.meshes) dropped += drop_degenerate_triangles(mesh);
  if (dropped > 0)
    add_warning(scene, fmt::format("{}: dropped {} degenerate triangles (repeated vertices or "
                                   "zero area)",
                                   origin, dropped));

  // Remove meshes without triangles and renumber instances and the lights that refer to them.
  std::vector<int> mesh_map(scene.meshes.size(), -1);
  std::vector<Mesh> meshes;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    if (scene.meshes[m].indices.empty()) continue;
    mesh_map[m] = static_cast<int>(meshes.size());
    meshes.push_back(std::move(scene.meshes[m]));
  }
  scene.meshes = std::move(meshes);
  std::vector<int> instance_map(scene.instances.size(), -1);
  std::vector<Instance> instances;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    Instance inst = scene.instances[i];
    inst.mesh = mesh_map[inst.mesh];
    if (inst.mesh < 0) continue;
    instance_map[i] = static_cast<int>(instances.size());
    instances.push_back(inst);
  }
  scene.instances = std::move(instances);
  std::vector<Light> lights;
  for (Light light : scene.lights) {
    if (light.type == LightType::kArea) {
      if (light.instance < 0 || static_cast<size_t>(light.instance) >= instance_map.size() ||
          instance_map[light.instance] < 0)
        continue;  // its geometry was empty or removed
      light.instance = instance_map[light.instance];
    }
    lights.push_back(light);
  }
  scene.lights = std::move(lights);

  for (Mesh& mesh : scene.meshes) {
    compute_normals(mesh);
    compute_tangents(mesh);
  }

  std::set<int> lit;
  for (const Light& light : scene.lights) {
    if (light.type == LightType::kArea) lit.insert(light.instance);
  }
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const Mesh& mesh = scene.meshes[inst.mesh];
    if (!scene.materials[mesh.material].is_emissive() || lit.count(static_cast<int>(i))) continue;
    Light light;
    light.name = inst.name;
    light.type = LightType::kArea;
    light.instance = static_cast<int>(i);
    scene.lights.push_back(light);
  }

  if (scene.triangle_count() == 0)
    add_warning(scene, fmt::format("{}: scene has no triangles", origin));
}

}  // namespace illum
