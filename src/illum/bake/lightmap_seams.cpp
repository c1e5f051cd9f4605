#include "illum/bake/lightmap_seams.h"

#include "illum/bake/lightmap_coplanar.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "illum/core/error.h"
#include "illum/core/parallel.h"
#include "illum/core/rng.h"

namespace illum::bake {
namespace {

// How far past a back face a moved sample lands, in texel sizes: far above float rounding
// at any scene scale offset_ray_origin handles (1e-4 of the coordinates), far below a texel,
// so the sample still stands for its texel.
constexpr float kPastFace = 0.01f;
constexpr int kDirections = 8;

struct TriangleCorners {
  vec3 p[3];
  vec2 uv[3];  // in texels
};

TriangleCorners corners(const Scene& scene, const atlas::TexelRaster& raster,
                        const atlas::TexelSample& s) {
  const Instance& inst = scene.instances[static_cast<size_t>(s.instance)];
  const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
  TriangleCorners c;
  for (int k = 0; k < 3; ++k) {
    const uint32_t v = mesh.indices[3 * static_cast<size_t>(s.triangle) + static_cast<size_t>(k)];
    c.p[k] = vec3(inst.transform * vec4(mesh.positions[v], 1.0f));
    c.uv[k] = mesh.uv1[v] * vec2(float(raster.width), float(raster.height));
  }
  return c;
}

// The closest back-face hit among the tangent-plane rays from `p` (lifted off the plane of
// normal `ng`), as a distance along `*direction`; infinity when every ray is free or hits
// a front face first.
float nearest_back_face(const RayTracer& tracer, const vec3& p, const vec3& ng, float reach,
                        vec3* direction) {
  const Frame frame = Frame::from_normal(ng);
  float nearest = kInf;
  for (int k = 0; k < kDirections; ++k) {
    const float angle = float(k) * (2.0f * kPi / kDirections);
    const vec3 dir = std::cos(angle) * frame.t + std::sin(angle) * frame.b;
    // Lifted as a ray leaving the surface is (offset_ray_origin along the normal), so the
    // sample's own triangle and a coplanar face it lies on are not hit.
    Ray ray{offset_ray_origin(p, ng, ng), dir, 0.0f, reach};
    Hit hit;
    if (!tracer.intersect(ray, &hit)) continue;
    const SurfaceInteraction si = tracer.interaction(ray, hit);
    if (glm::dot(si.ng, dir) > 0.0f && hit.t < nearest) {
      nearest = hit.t;
      *direction = dir;
    }
  }
  return nearest;
}

// One triangle edge, its end points ordered by their quantised keys so both triangles of a
// shared edge list them alike.
struct EdgeEnd {
  glm::i64vec3 key;
  vec2 uv;  // texels
  vec3 normal;
};
struct TriangleEdge {
  EdgeEnd end[2];
  int instance;
  vec3 world[2];      // the end points, in end[] order
  vec3 plane_normal;  // the triangle's geometric normal (zero when degenerate)
  vec3 inward;        // in the triangle's plane, across the edge into the triangle
};

// An open edge for find_coplanar_seams; shading normals fall back to the plane's (a mesh
// without normals is shaded flat).
OpenEdge open_edge(const TriangleEdge& e) {
  OpenEdge o;
  for (int k = 0; k < 2; ++k) {
    o.p[k] = e.world[k];
    o.uv[k] = e.end[k].uv;
    o.normal[k] = e.end[k].normal == vec3(0.0f) ? e.plane_normal : e.end[k].normal;
  }
  o.plane_normal = e.plane_normal;
  o.inward = e.inward;
  return o;
}

bool key_less(const glm::i64vec3& a, const glm::i64vec3& b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  return a.z < b.z;
}

struct EdgeKeyHash {
  size_t operator()(const std::pair<glm::i64vec3, glm::i64vec3>& k) const {
    uint64_t h = 0x9e3779b97f4a7c15ull;
    for (const glm::i64vec3* v : {&k.first, &k.second})
      for (int i = 0; i < 3; ++i) h = hash_mix(h, static_cast<uint64_t>((*v)[i]));
    return static_cast<size_t>(h);
  }
};

}  // namespace

Seams find_seams(const Scene& scene, int width, int height, const SeamFindOptions& options) {
  if (width < 1 || height < 1)
    throw Error(fmt::format("seams: atlas size {}x{} must be positive", width, height));
  // The scene's extent, for the default tolerance.
  vec3 lo(kInf), hi(-kInf);
  for (const Instance& inst : scene.instances) {
    const Mesh& mesh = scene.meshes[size_t(inst.mesh)];
    if (mesh.uv1.empty()) continue;
    for (const vec3& p : mesh.positions) {
      const vec3 w = vec3(inst.transform * vec4(p, 1.0f));
      lo = glm::min(lo, w);
      hi = glm::max(hi, w);
    }
  }
  Seams seams;
  if (!(hi.x >= lo.x)) return seams;
  // Split vertices of one mesh have bit-equal positions; neighbours in other meshes come
  // through their own transforms, hence a tolerance well above float rounding of the
  // coordinates (1e-7 relative) and far below any modelled feature.
  const float tol =
      options.tolerance > 0.0f ? options.tolerance : 1e-6f * std::max(glm::length(hi - lo), 1e-6f);
  const vec2 size{float(width), float(height)};
  const auto quantise = [&](const vec3& p) {
    return glm::i64vec3(std::llround(double(p.x) / tol), std::llround(double(p.y) / tol),
                        std::llround(double(p.z) / tol));
  };

  std::vector<TriangleEdge> edges;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const Mesh& mesh = scene.meshes[size_t(inst.mesh)];
    if (mesh.uv1.size() != mesh.positions.size()) continue;
    const mat3 normal_matrix = glm::transpose(glm::inverse(mat3(inst.transform)));
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
      const uint32_t* idx = &mesh.indices[3 * t];
      vec3 world[3];
      for (int k = 0; k < 3; ++k)
        world[k] = vec3(inst.transform * vec4(mesh.positions[idx[k]], 1.0f));
      const vec3 cross = glm::cross(world[1] - world[0], world[2] - world[0]);
      const float cross_length = glm::length(cross);
      const vec3 plane_normal = cross_length > 0.0f ? cross / cross_length : vec3(0.0f);
      for (int k = 0; k < 3; ++k) {
        TriangleEdge e;
        e.instance = int(i);
        for (int j = 0; j < 2; ++j) {
          const uint32_t v = idx[(k + j) % 3];
          e.world[j] = world[(k + j) % 3];
          e.end[j].key = quantise(e.world[j]);
          e.end[j].uv = mesh.uv1[v] * size;
          e.end[j].normal = mesh.normals.size() == mesh.positions.size()
                                ? glm::normalize(normal_matrix * mesh.normals[v])
                                : vec3(0.0f);
        }
        if (e.end[0].key == e.end[1].key) continue;  // degenerate at this tolerance
        e.plane_normal = plane_normal;
        const vec3 along = glm::normalize(e.world[1] - e.world[0]);
        e.inward = glm::cross(plane_normal, along);  // unit: both unit and perpendicular
        if (glm::dot(e.inward, world[(k + 2) % 3] - e.world[0]) < 0.0f) e.inward = -e.inward;
        if (key_less(e.end[1].key, e.end[0].key)) {
          std::swap(e.end[0], e.end[1]);
          std::swap(e.world[0], e.world[1]);
        }
        edges.push_back(e);
      }
    }
  }
  std::unordered_map<std::pair<glm::i64vec3, glm::i64vec3>, std::vector<int>, EdgeKeyHash> by_key;
  for (size_t i = 0; i < edges.size(); ++i)
    by_key[{edges[i].end[0].key, edges[i].end[1].key}].push_back(int(i));

  // Walk the edges in their own order (not the hash map's) so the samples are deterministic.
  for (size_t i = 0; i < edges.size(); ++i) {
    const std::vector<int>& group = by_key.at({edges[i].end[0].key, edges[i].end[1].key});
    for (const int j : group) {
      if (j <= int(i)) continue;  // each pair once
      const TriangleEdge& a = edges[i];
      const TriangleEdge& b = edges[size_t(j)];
      bool smooth = true, split = false;
      for (int k = 0; k < 2; ++k) {
        smooth = smooth && glm::dot(a.end[k].normal, b.end[k].normal) >= kSeamNormalCos;
        split = split || glm::length(a.end[k].uv - b.end[k].uv) > 1e-3f;
      }
      if (!smooth || !split) continue;
      ++seams.edges;
      if (a.instance == b.instance) ++seams.within_instance;
      const float texels =
          std::max(glm::length(a.end[1].uv - a.end[0].uv), glm::length(b.end[1].uv - b.end[0].uv));
      const int n = std::max(2, int(std::ceil(texels * float(kSeamSamplesPerTexel))));
      for (int k = 0; k < n; ++k) {
        const float u = (float(k) + 0.5f) / float(n);
        seams.samples.push_back(
            {{glm::mix(a.end[0].uv, a.end[1].uv, u), glm::mix(b.end[0].uv, b.end[1].uv, u)}});
      }
    }
  }
  if (options.coplanar) {
    // Open edges: no other edge has both their end points (chart and mesh borders; an edge
    // shared with a crease or a seam is not open, its other side is taken).
    std::vector<OpenEdge> open;
    for (const TriangleEdge& e : edges)
      if (e.plane_normal != vec3(0.0f) && by_key.at({e.end[0].key, e.end[1].key}).size() == 1)
        open.push_back(open_edge(e));
    seams.coplanar_pairs = find_coplanar_seams(open, tol, seams.samples);
  }
  return seams;
}

namespace {

// The four texels and weights of a bilinear lookup (clamp to edge).
struct Taps {
  int texel[4];
  float weight[4];
};

Taps bilinear_taps(int width, int height, const vec2& texel) {
  const float px = texel.x - 0.5f, py = texel.y - 0.5f;
  const float fx0 = std::floor(px), fy0 = std::floor(py);
  const float fx = px - fx0, fy = py - fy0;
  const int x0 = int(fx0), y0 = int(fy0);
  const auto at = [&](int x, int y) {
    return std::clamp(y, 0, height - 1) * width + std::clamp(x, 0, width - 1);
  };
  return Taps{{at(x0, y0), at(x0 + 1, y0), at(x0, y0 + 1), at(x0 + 1, y0 + 1)},
              {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy}};
}

}  // namespace

Color bilinear_lookup(const Image& layer, const vec2& texel) {
  const Taps taps = bilinear_taps(layer.width(), layer.height(), texel);
  Color c(0.0f);
  for (int k = 0; k < 4; ++k)
    c += taps.weight[k] * layer.rgb(taps.texel[k] % layer.width(), taps.texel[k] / layer.width());
  return c;
}

SeamStitchStats stitch_seams(const Seams& seams, const atlas::TexelRaster& raster,
                             std::vector<Image>& layers, const SeamStitchOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const int width = raster.width, height = raster.height;
  for (const Image& layer : layers)
    if (layer.width() != width || layer.height() != height || layer.channels() < 3)
      throw Error(fmt::format("seam stitching: a layer of {}x{} for a {}x{} raster", layer.width(),
                              layer.height(), width, height));
  if (!(options.covered_weight > 0.0f) || !(options.gutter_weight > 0.0f) ||
      options.max_iterations < 1)
    throw Error("seam stitching: the regulariser's weights must be positive");
  SeamStitchStats stats;
  stats.samples = int64_t(seams.samples.size());
  if (seams.samples.empty() || layers.empty()) return stats;

  // Rows of R (8 taps: side 0 with +w, side 1 with −w) over the unknowns (touched texels).
  struct Row {
    int var[8];
    float w[8];
  };
  std::vector<Row> rows(seams.samples.size());
  std::unordered_map<int, int> var_of;
  std::vector<int> texel_of;
  for (size_t r = 0; r < seams.samples.size(); ++r)
    for (int side = 0; side < 2; ++side) {
      const Taps taps = bilinear_taps(width, height, seams.samples[r].side[side]);
      for (int k = 0; k < 4; ++k) {
        auto [it, added] = var_of.try_emplace(taps.texel[k], int(texel_of.size()));
        if (added) texel_of.push_back(taps.texel[k]);
        rows[r].var[4 * side + k] = it->second;
        rows[r].w[4 * side + k] = side == 0 ? taps.weight[k] : -taps.weight[k];
      }
    }
  const size_t n = texel_of.size();
  stats.texels = int64_t(n);
  std::vector<double> lambda(n), diag(n);
  for (size_t i = 0; i < n; ++i)
    lambda[i] =
        raster.sample_of[size_t(texel_of[i])] >= 0 ? options.covered_weight : options.gutter_weight;
  diag = lambda;
  for (const Row& row : rows)
    for (int k = 0; k < 8; ++k) diag[size_t(row.var[k])] += double(row.w[k]) * row.w[k];

  // All channels of all layers at once (K right-hand sides, one matrix), each with its own
  // CG scalars; unknowns are the changes δ: (RᵀR + Λ) δ = −RᵀR x⁰.
  const size_t channels = 3 * layers.size();
  const size_t count = n * channels;
  const auto value = [&](size_t c, size_t i) -> float& {
    const int t = texel_of[i];
    return layers[c / 3].pixel(t % width, t / width)[c % 3];
  };
  // Entries held at zero radiance (the active set of the non-negativity constraint): their
  // δ is −x⁰ and they take no part in the solve.
  std::vector<char> held(count, 0);
  // y = (RᵀR + Λ) x, x and y [unknown][channel].
  const auto apply = [&](const std::vector<double>& x, std::vector<double>& y, bool with_lambda) {
    std::fill(y.begin(), y.end(), 0.0);
    for (const Row& row : rows)
      for (size_t c = 0; c < channels; ++c) {
        double s = 0.0;
        for (int k = 0; k < 8; ++k) s += double(row.w[k]) * x[size_t(row.var[k]) * channels + c];
        for (int k = 0; k < 8; ++k) y[size_t(row.var[k]) * channels + c] += double(row.w[k]) * s;
      }
    if (with_lambda)
      for (size_t i = 0; i < n; ++i)
        for (size_t c = 0; c < channels; ++c)
          y[i * channels + c] += lambda[i] * x[i * channels + c];
  };
  std::vector<double> x0(count), b(count), delta(count, 0.0), residual(count), z(count), p(count),
      ap(count), held_delta(count);
  for (size_t i = 0; i < n; ++i)
    for (size_t c = 0; c < channels; ++c) x0[i * channels + c] = value(c, i);

  // Preconditioned CG on the free entries, from the current δ (warm start after a round
  // that held more entries at zero). Returns the iterations it took.
  const auto solve_free = [&]() {
    // b = −RᵀR x⁰ − (RᵀR + Λ) δ_held, on the free entries; the residual starts from δ.
    for (size_t k = 0; k < count; ++k) held_delta[k] = held[k] ? -x0[k] : 0.0;
    apply(x0, b, false);
    apply(held_delta, ap, true);
    for (size_t k = 0; k < count; ++k) b[k] = held[k] ? 0.0 : -b[k] - ap[k];
    for (size_t k = 0; k < count; ++k)
      if (held[k]) delta[k] = 0.0;
    apply(delta, ap, true);
    std::vector<double> rz(channels, 0.0), norm_b(channels, 0.0), alpha(channels), beta(channels);
    for (size_t i = 0; i < n; ++i)
      for (size_t c = 0; c < channels; ++c) {
        const size_t k = i * channels + c;
        residual[k] = held[k] ? 0.0 : b[k] - ap[k];
        z[k] = residual[k] / diag[i];
        p[k] = z[k];
        rz[c] += residual[k] * z[k];
        norm_b[c] += b[k] * b[k];
      }
    std::vector<bool> done(channels, false);
    std::vector<double> rr0(channels, 0.0);
    for (size_t k = 0; k < count; ++k) rr0[k % channels] += residual[k] * residual[k];
    for (size_t c = 0; c < channels; ++c)
      done[c] = norm_b[c] == 0.0 || rr0[c] <= options.tolerance * options.tolerance * norm_b[c];
    int iteration = 0;
    for (; iteration < options.max_iterations; ++iteration) {
      if (std::all_of(done.begin(), done.end(), [](bool d) { return d; })) break;
      apply(p, ap, true);
      for (size_t k = 0; k < count; ++k)
        if (held[k]) ap[k] = 0.0;
      std::vector<double> pap(channels, 0.0);
      for (size_t k = 0; k < count; ++k) pap[k % channels] += p[k] * ap[k];
      for (size_t c = 0; c < channels; ++c)
        alpha[c] = done[c] || pap[c] <= 0.0 ? 0.0 : rz[c] / pap[c];
      std::vector<double> rr(channels, 0.0), rz_next(channels, 0.0);
      for (size_t i = 0; i < n; ++i)
        for (size_t c = 0; c < channels; ++c) {
          const size_t k = i * channels + c;
          delta[k] += alpha[c] * p[k];
          residual[k] -= alpha[c] * ap[k];
          z[k] = residual[k] / diag[i];
          rr[c] += residual[k] * residual[k];
          rz_next[c] += residual[k] * z[k];
        }
      for (size_t c = 0; c < channels; ++c) {
        if (rr[c] <= options.tolerance * options.tolerance * norm_b[c]) done[c] = true;
        beta[c] = rz[c] > 0.0 ? rz_next[c] / rz[c] : 0.0;
        rz[c] = rz_next[c];
      }
      for (size_t k = 0; k < count; ++k) p[k] = z[k] + beta[k % channels] * p[k];
    }
    return iteration;
  };

  // Light is never negative, and the least-squares agreement alone can push a dark texel
  // beside a bright seam below zero. Active set: entries the solve drives below zero are
  // held at zero and the rest solved again, until none is; the few a round limit leaves
  // (none in the scenes tried) are clamped.
  int iteration = solve_free();
  for (int round = 0; round < kMaxNonNegativeRounds; ++round) {
    bool added = false;
    for (size_t k = 0; k < count; ++k)
      if (!held[k] && x0[k] + delta[k] < 0.0) held[k] = added = true;
    if (!added) break;
    ++stats.held_at_zero_rounds;
    iteration += solve_free();
  }
  stats.iterations = iteration;
  for (size_t i = 0; i < n; ++i)
    for (size_t c = 0; c < channels; ++c) {
      const size_t k = i * channels + c;
      stats.held_at_zero += held[k];
      value(c, i) = held[k] ? 0.0f : std::max(0.0f, static_cast<float>(x0[k] + delta[k]));
    }
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

StitchReport stitch_baked_layers(const Scene& scene, const atlas::TexelRaster& raster,
                                 std::vector<Image>& layers, bool coplanar) {
  const auto start = std::chrono::steady_clock::now();
  const Seams seams = find_seams(scene, raster.width, raster.height, {.coplanar = coplanar});
  StitchReport report;
  report.solve = stitch_seams(seams, raster, layers);
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report.seam_edges = seams.edges;
  report.coplanar_edges = seams.coplanar_pairs;
  return report;
}

float texel_world_size(const Scene& scene, const atlas::TexelRaster& raster,
                       const atlas::TexelSample& s) {
  const TriangleCorners c = corners(scene, raster, s);
  // World edges E = J · uv edges; J = E · inverse(uv edges) (3×2), then the largest
  // singular value from the 2×2 JᵀJ.
  const glm::dvec2 d1(c.uv[1] - c.uv[0]), d2(c.uv[2] - c.uv[0]);
  const double det = d1.x * d2.y - d1.y * d2.x;
  if (!(std::abs(det) > 0.0)) return 0.0f;
  const glm::dvec3 e1(c.p[1] - c.p[0]), e2(c.p[2] - c.p[0]);
  const glm::dvec3 ju = (d2.y * e1 - d1.y * e2) / det;  // ∂p/∂u per texel
  const glm::dvec3 jv = (d1.x * e2 - d2.x * e1) / det;  // ∂p/∂v per texel
  const double a = glm::dot(ju, ju), b = glm::dot(ju, jv), d = glm::dot(jv, jv);
  const double lambda = 0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + b * b);
  return static_cast<float>(std::sqrt(lambda));
}

TexelPushOut keep_texels_out_of_geometry(const Scene& scene, const RayTracer& tracer,
                                         atlas::TexelRaster& raster) {
  atlas::check_texel_raster(scene, raster, "texel push-out");
  const int64_t count = static_cast<int64_t>(raster.samples.size());
  std::vector<uint8_t> reject(raster.samples.size(), 0);
  std::atomic<int64_t> moved{0};
  parallel_for(
      count,
      [&](int64_t begin, int64_t end) {
        for (int64_t i = begin; i < end; ++i) {
          atlas::TexelSample& s = raster.samples[static_cast<size_t>(i)];
          const float h = texel_world_size(scene, raster, s);
          if (!(h > 0.0f) || !std::isfinite(h)) continue;
          vec3 dir(0.0f);
          const float t = nearest_back_face(tracer, s.position, s.geometric_normal, h, &dir);
          if (!(t < kInf)) continue;
          const vec3 moved_to = s.position + (t + kPastFace * h) * dir;
          vec3 again(0.0f);
          if (nearest_back_face(tracer, moved_to, s.geometric_normal, h, &again) < kInf) {
            reject[static_cast<size_t>(i)] = 1;
            continue;
          }
          s.position = moved_to;
          moved.fetch_add(1, std::memory_order_relaxed);
        }
      },
      64);

  TexelPushOut out;
  out.moved = moved.load();
  size_t kept = 0;
  for (size_t i = 0; i < raster.samples.size(); ++i) {
    const atlas::TexelSample& s = raster.samples[i];
    const size_t texel = size_t(s.y) * size_t(raster.width) + size_t(s.x);
    if (reject[i]) {
      raster.sample_of[texel] = -1;
      ++out.rejected;
      continue;
    }
    raster.samples[kept] = s;
    raster.sample_of[texel] = static_cast<int32_t>(kept);
    ++kept;
  }
  raster.samples.resize(kept);
  return out;
}

}  // namespace illum::bake
