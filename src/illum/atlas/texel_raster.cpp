#include "illum/atlas/texel_raster.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "illum/core/error.h"
#include "illum/core/parallel.h"

// Conservative coverage without the seed's GPU trick (S000 §2.7.1 draws every seam edge
// as a line offset by half a texel because hardware rasterization only fills texels whose
// centre is inside): on the CPU the exact set is as cheap. A texel square is touched by a
// triangle iff it overlaps the triangle with positive area; since the part of a triangle
// inside one row of texels is convex and spans no more than that row, the texels it
// touches in the row are exactly those whose x-interval meets the x-range of that part.
// So each triangle is clipped to each row it crosses, and the row's span read off.

namespace illum::atlas {
namespace {

constexpr int kMaxSize = 16384;        // as AtlasOptions::resolution
constexpr double kUvTolerance = 1e-5;  // uv1 a packer rounded just past [0,1] is accepted
constexpr int kBandRows = 8;           // rows per parallel work item (owned exclusively)
constexpr float kCentreInside = std::numeric_limits<float>::infinity();

struct InstanceGeometry {
  const Mesh* mesh = nullptr;
  int instance = 0;
  std::vector<vec3> world;  // world-space vertices, computed as RayTracer does
  mat3 linear{1.0f};        // object → world for directions (tangents)
  mat3 normal_matrix{1.0f};
};

// A light-mapped triangle in texel units (u·width, v·height).
struct UvTriangle {
  double x[3], y[3];
  double area2;  // signed doubled area
  int geometry;  // InstanceGeometry index
  int triangle;  // within the mesh
};

// Which triangle a texel takes so far: one containing its centre (score = kCentreInside)
// beats any other; otherwise the largest overlap area. Ties keep the earlier triangle
// (instance order, then triangle order), so the result does not depend on scheduling.
struct Candidate {
  int32_t triangle = -1;  // UvTriangle index
  float score = 0.0f;
};

double cross2(double ax, double ay, double bx, double by) {
  return ax * by - ay * bx;
}

// Barycentrics (b1, b2) of point (px, py); false when the triangle is degenerate in uv.
bool barycentric(const UvTriangle& t, double px, double py, double* b1, double* b2) {
  if (t.area2 == 0.0) return false;
  const double ex1 = t.x[1] - t.x[0], ey1 = t.y[1] - t.y[0];
  const double ex2 = t.x[2] - t.x[0], ey2 = t.y[2] - t.y[0];
  const double dx = px - t.x[0], dy = py - t.y[0];
  *b1 = cross2(dx, dy, ex2, ey2) / t.area2;
  *b2 = cross2(ex1, ey1, dx, dy) / t.area2;
  return true;
}

bool contains(const UvTriangle& t, double px, double py, double* b1, double* b2) {
  return barycentric(t, px, py, b1, b2) && *b1 >= 0.0 && *b2 >= 0.0 && *b1 + *b2 <= 1.0;
}

// x-range of the triangle's part inside the strip y0 ≤ y ≤ y1 (empty: lo > hi).
void strip_span(const UvTriangle& t, double y0, double y1, double* lo, double* hi) {
  *lo = std::numeric_limits<double>::infinity();
  *hi = -std::numeric_limits<double>::infinity();
  auto extend = [&](double x) {
    *lo = std::min(*lo, x);
    *hi = std::max(*hi, x);
  };
  for (int i = 0; i < 3; ++i)
    if (t.y[i] >= y0 && t.y[i] <= y1) extend(t.x[i]);
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const double ya = t.y[i], yb = t.y[j];
    if (ya == yb) continue;
    for (const double yc : {y0, y1}) {
      if ((yc - ya) * (yc - yb) < 0.0) {
        const double s = (yc - ya) / (yb - ya);
        extend(t.x[i] + s * (t.x[j] - t.x[i]));
      }
    }
  }
}

// The point of the triangle's boundary nearest (px, py), as barycentrics (b1, b2). Used for
// texels whose centre lies outside: the nearest point of the triangle is then on an edge.
vec2 nearest_on_boundary(const UvTriangle& t, double px, double py) {
  double best = std::numeric_limits<double>::infinity();
  vec2 bary(0.0f);
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const double ex = t.x[j] - t.x[i], ey = t.y[j] - t.y[i];
    const double len2 = ex * ex + ey * ey;
    double s = len2 > 0.0 ? ((px - t.x[i]) * ex + (py - t.y[i]) * ey) / len2 : 0.0;
    s = std::clamp(s, 0.0, 1.0);
    const double dx = t.x[i] + s * ex - px, dy = t.y[i] + s * ey - py;
    const double d2 = dx * dx + dy * dy;
    if (d2 < best) {
      best = d2;
      // Weight 1 − s on vertex i and s on vertex j, written as (b1, b2).
      double w[3] = {0.0, 0.0, 0.0};
      w[i] = 1.0 - s;
      w[j] = s;
      bary = vec2(static_cast<float>(w[1]), static_cast<float>(w[2]));
    }
  }
  return bary;
}

std::string mesh_label(const Scene& scene, const Instance& inst) {
  const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
  return fmt::format("instance '{}' (mesh '{}')", inst.name, mesh.name);
}

std::vector<InstanceGeometry> light_mapped_instances(const Scene& scene) {
  std::vector<InstanceGeometry> out;
  std::vector<int> first_user(scene.meshes.size(), -1);
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    if (inst.mesh < 0 || static_cast<size_t>(inst.mesh) >= scene.meshes.size())
      throw Error(fmt::format("texel raster: instance '{}' refers to mesh {} of {}", inst.name,
                              inst.mesh, scene.meshes.size()));
    const Mesh& mesh = scene.meshes[static_cast<size_t>(inst.mesh)];
    if (mesh.uv1.empty()) continue;
    const std::string label = mesh_label(scene, inst);
    // Two instances of one mesh would share its texels although their lighting differs.
    int& first = first_user[static_cast<size_t>(inst.mesh)];
    if (first >= 0)
      throw Error(fmt::format(
          "texel raster: instances '{}' and '{}' share light-mapped mesh '{}'; give every "
          "instance its own mesh first (atlas::make_meshes_unique)",
          scene.instances[static_cast<size_t>(first)].name, inst.name, mesh.name));
    first = static_cast<int>(i);
    if (mesh.uv1.size() != mesh.positions.size())
      throw Error(fmt::format("texel raster: {} has {} uv1 for {} vertices", label, mesh.uv1.size(),
                              mesh.positions.size()));
    if (mesh.indices.size() % 3 != 0)
      throw Error(fmt::format("texel raster: {} has {} indices, not a multiple of 3", label,
                              mesh.indices.size()));
    for (const uint32_t index : mesh.indices)
      if (index >= mesh.positions.size())
        throw Error(fmt::format("texel raster: {} has vertex index {} of {}", label, index,
                                mesh.positions.size()));
    for (size_t v = 0; v < mesh.uv1.size(); ++v) {
      const vec2 uv = mesh.uv1[v];
      const auto inside = [](float c) {
        return std::isfinite(c) && c >= -kUvTolerance && c <= 1.0 + kUvTolerance;
      };
      if (!inside(uv.x) || !inside(uv.y))
        throw Error(fmt::format("texel raster: {} vertex {} has uv1 ({}, {}) outside [0,1]", label,
                                v, uv.x, uv.y));
    }
    InstanceGeometry g;
    g.mesh = &mesh;
    g.instance = static_cast<int>(i);
    g.linear = mat3(inst.transform);
    const float det = glm::determinant(g.linear);
    if (!(std::abs(det) > 0.0f) || !std::isfinite(det))
      throw Error(fmt::format("texel raster: {} has a singular or non-finite transform", label));
    g.normal_matrix = glm::transpose(glm::inverse(g.linear));
    g.world.reserve(mesh.positions.size());
    for (const vec3& position : mesh.positions)
      g.world.push_back(vec3(inst.transform * vec4(position, 1.0f)));
    out.push_back(std::move(g));
  }
  return out;
}

TexelSample make_sample(const InstanceGeometry& g, const UvTriangle& t, int x, int y) {
  TexelSample s;
  s.x = x;
  s.y = y;
  s.instance = g.instance;
  s.triangle = t.triangle;
  const double cx = x + 0.5, cy = y + 0.5;
  double b1 = 0.0, b2 = 0.0;
  if (contains(t, cx, cy, &b1, &b2)) {
    s.barycentric = vec2(static_cast<float>(b1), static_cast<float>(b2));
    s.centre_inside = true;
  } else {
    s.barycentric = nearest_on_boundary(t, cx, cy);
    s.centre_inside = false;
  }
  const Mesh& mesh = *g.mesh;
  const size_t tri = static_cast<size_t>(t.triangle);
  const uint32_t i0 = mesh.indices[3 * tri], i1 = mesh.indices[3 * tri + 1],
                 i2 = mesh.indices[3 * tri + 2];
  const float w1 = s.barycentric.x, w2 = s.barycentric.y, w0 = 1.0f - w1 - w2;
  const vec3 &p0 = g.world[i0], &p1 = g.world[i1], &p2 = g.world[i2];
  s.position = w0 * p0 + w1 * p1 + w2 * p2;  // as RayTracer::interaction
  s.geometric_normal = glm::normalize(glm::cross(p1 - p0, p2 - p0));

  // The shaders' frame (forward.vert, lighting.glsl load_surface): the normal carried by
  // the inverse transpose, the tangent by the model matrix, then Gram–Schmidt against the
  // normal, bitangent = cross(n, t) · w. The normal is put on the winding's side, as the
  // ray tracer does, so "front" means the same to the baker and the renderers.
  vec3 n = s.geometric_normal;
  if (mesh.normals.size() == mesh.positions.size()) {
    const vec3 m =
        g.normal_matrix * (w0 * mesh.normals[i0] + w1 * mesh.normals[i1] + w2 * mesh.normals[i2]);
    const float len = glm::length(m);
    if (len > 0.0f && std::isfinite(len)) n = m / len;
  }
  if (glm::dot(n, s.geometric_normal) < 0.0f) n = -n;
  s.normal = n;
  bool has_tangent = false;
  if (mesh.tangents.size() == mesh.positions.size()) {
    const vec4 t4 = w0 * mesh.tangents[i0] + w1 * mesh.tangents[i1] + w2 * mesh.tangents[i2];
    vec3 tangent = g.linear * vec3(t4);
    tangent -= n * glm::dot(n, tangent);
    const float len = glm::length(tangent);
    if (len > 1e-6f * glm::length(vec3(t4)) && std::isfinite(len)) {
      s.tangent = tangent / len;
      s.tangent_sign = t4.w < 0.0f ? -1.0f : 1.0f;
      has_tangent = true;
    }
  }
  if (!has_tangent) {
    s.tangent = Frame::from_normal(n).t;
    s.tangent_sign = 1.0f;
  }
  return s;
}

}  // namespace

void check_texel_raster(const Scene& scene, const TexelRaster& raster, const char* who) {
  if (raster.width < 1 || raster.height < 1 ||
      raster.sample_of.size() != static_cast<size_t>(raster.width) * raster.height)
    throw Error(fmt::format("{}: malformed texel raster ({}x{}, {} entries)", who, raster.width,
                            raster.height, raster.sample_of.size()));
  for (const TexelSample& s : raster.samples) {
    if (s.x < 0 || s.x >= raster.width || s.y < 0 || s.y >= raster.height)
      throw Error(fmt::format("{}: texel ({}, {}) lies outside the {}x{} raster", who, s.x, s.y,
                              raster.width, raster.height));
    const bool instance_ok =
        s.instance >= 0 && static_cast<size_t>(s.instance) < scene.instances.size();
    const int mesh = instance_ok ? scene.instances[static_cast<size_t>(s.instance)].mesh : -1;
    if (mesh < 0 || static_cast<size_t>(mesh) >= scene.meshes.size() || s.triangle < 0 ||
        static_cast<size_t>(s.triangle) >= scene.meshes[static_cast<size_t>(mesh)].triangle_count())
      throw Error(fmt::format(
          "{}: texel ({}, {}) refers to instance {} triangle {}, which scene '{}' does not have "
          "(raster made from another scene?)",
          who, s.x, s.y, s.instance, s.triangle, scene.name));
  }
}

double texel_overlap_area(const glm::dvec2 triangle[3], int x, int y) {
  // A triangle clipped by four half-planes keeps at most 7 corners.
  glm::dvec2 poly[8], next[8];
  int n = 3;
  std::copy(triangle, triangle + 3, poly);
  const double lo[2] = {double(x), double(y)}, hi[2] = {double(x) + 1.0, double(y) + 1.0};
  for (int side = 0; side < 4 && n > 0; ++side) {
    const int axis = side / 2;
    const bool upper = side % 2 == 1;
    const double bound = upper ? hi[axis] : lo[axis];
    const auto inside = [&](const glm::dvec2& p) {
      return upper ? p[axis] <= bound : p[axis] >= bound;
    };
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const glm::dvec2& a = poly[i];
      const glm::dvec2& b = poly[(i + 1) % n];
      const bool a_in = inside(a), b_in = inside(b);
      if (a_in) next[m++] = a;
      if (a_in != b_in) {
        const double t = (bound - a[axis]) / (b[axis] - a[axis]);
        next[m++] = a + t * (b - a);
      }
    }
    n = m;
    std::copy(next, next + m, poly);
  }
  double twice = 0.0;
  for (int i = 0; i < n; ++i) {
    const glm::dvec2& a = poly[i];
    const glm::dvec2& b = poly[(i + 1) % n];
    twice += a.x * b.y - b.x * a.y;
  }
  return 0.5 * std::abs(twice);
}

TexelRaster rasterize_texels(const Scene& scene, int width, int height) {
  if (width < 1 || height < 1 || width > kMaxSize || height > kMaxSize)
    throw Error(fmt::format("texel raster: size {}x{} must lie in [1, {}] on both sides", width,
                            height, kMaxSize));
  const std::vector<InstanceGeometry> geometry = light_mapped_instances(scene);

  std::vector<UvTriangle> triangles;
  const int bands = (height + kBandRows - 1) / kBandRows;
  std::vector<std::vector<int32_t>> band_triangles(static_cast<size_t>(bands));
  for (size_t gi = 0; gi < geometry.size(); ++gi) {
    const InstanceGeometry& g = geometry[gi];
    const Mesh& mesh = *g.mesh;
    for (size_t f = 0; f < mesh.triangle_count(); ++f) {
      const uint32_t* idx = &mesh.indices[3 * f];
      // Triangles of zero world area are invisible to rays (RayTracer drops them) and
      // have no normal: they stand for no surface.
      const glm::dvec3 a(g.world[idx[0]]), b(g.world[idx[1]]), c(g.world[idx[2]]);
      const glm::dvec3 cr = glm::cross(b - a, c - a);
      if (cr.x == 0.0 && cr.y == 0.0 && cr.z == 0.0) continue;
      UvTriangle t;
      for (int k = 0; k < 3; ++k) {
        const vec2 uv = glm::clamp(mesh.uv1[idx[k]], vec2(0.0f), vec2(1.0f));
        t.x[k] = static_cast<double>(uv.x) * width;
        t.y[k] = static_cast<double>(uv.y) * height;
      }
      t.area2 = cross2(t.x[1] - t.x[0], t.y[1] - t.y[0], t.x[2] - t.x[0], t.y[2] - t.y[0]);
      t.geometry = static_cast<int>(gi);
      t.triangle = static_cast<int>(f);
      const double ymin = std::min({t.y[0], t.y[1], t.y[2]});
      const double ymax = std::max({t.y[0], t.y[1], t.y[2]});
      // Rows r with ymin < r + 1 and ymax > r (positive overlap with the open row).
      const int r0 = std::max(0, static_cast<int>(std::floor(ymin)));
      const int r1 = std::min(height - 1, static_cast<int>(std::ceil(ymax)) - 1);
      if (r1 < r0) continue;
      const int32_t id = static_cast<int32_t>(triangles.size());
      triangles.push_back(t);
      for (int band = r0 / kBandRows; band <= r1 / kBandRows; ++band)
        band_triangles[static_cast<size_t>(band)].push_back(id);
    }
  }

  const size_t texel_count = static_cast<size_t>(width) * static_cast<size_t>(height);
  std::vector<Candidate> best(texel_count);
  parallel_for(
      bands,
      [&](int64_t band_begin, int64_t band_end) {
        for (int64_t band = band_begin; band < band_end; ++band) {
          const int row0 = static_cast<int>(band) * kBandRows;
          const int row1 = std::min(height, row0 + kBandRows);  // exclusive
          for (const int32_t id : band_triangles[static_cast<size_t>(band)]) {
            const UvTriangle& t = triangles[static_cast<size_t>(id)];
            const double ymin = std::min({t.y[0], t.y[1], t.y[2]});
            const double ymax = std::max({t.y[0], t.y[1], t.y[2]});
            const int r0 = std::max(row0, static_cast<int>(std::floor(ymin)));
            const int r1 = std::min(row1 - 1, static_cast<int>(std::ceil(ymax)) - 1);
            for (int y = r0; y <= r1; ++y) {
              double lo, hi;
              strip_span(t, y, y + 1, &lo, &hi);
              if (lo > hi) continue;
              // Texels x with lo < x + 1 and hi > x.
              const int x0 = std::max(0, static_cast<int>(std::floor(lo)));
              const int x1 = std::min(width - 1, static_cast<int>(std::ceil(hi)) - 1);
              for (int x = x0; x <= x1; ++x) {
                Candidate& c = best[static_cast<size_t>(y) * width + x];
                if (c.triangle >= 0 && c.score == kCentreInside) continue;
                double b1, b2;
                if (contains(t, x + 0.5, y + 0.5, &b1, &b2)) {
                  c = {id, kCentreInside};
                  continue;
                }
                const glm::dvec2 corners[3] = {
                    {t.x[0], t.y[0]}, {t.x[1], t.y[1]}, {t.x[2], t.y[2]}};
                const float area = static_cast<float>(texel_overlap_area(corners, x, y));
                if (c.triangle < 0 || area > c.score) c = {id, area};
              }
            }
          }
        }
      },
      1);

  // Samples in row-major order: count per row, prefix sums, then fill rows in parallel.
  TexelRaster raster;
  raster.width = width;
  raster.height = height;
  raster.sample_of.assign(texel_count, -1);
  std::vector<int64_t> row_start(static_cast<size_t>(height) + 1, 0);
  parallel_for(
      height,
      [&](int64_t y0, int64_t y1) {
        for (int64_t y = y0; y < y1; ++y) {
          int64_t n = 0;
          for (int x = 0; x < width; ++x)
            n += best[static_cast<size_t>(y) * width + x].triangle >= 0 ? 1 : 0;
          row_start[static_cast<size_t>(y) + 1] = n;
        }
      },
      16);
  for (int y = 0; y < height; ++y) row_start[y + 1] += row_start[y];
  const int64_t covered = row_start[static_cast<size_t>(height)];
  ILLUM_CHECK(covered <= std::numeric_limits<int32_t>::max(), "{} covered texels", covered);
  raster.samples.resize(static_cast<size_t>(covered));
  parallel_for(
      height,
      [&](int64_t y0, int64_t y1) {
        for (int64_t y = y0; y < y1; ++y) {
          int64_t next = row_start[static_cast<size_t>(y)];
          for (int x = 0; x < width; ++x) {
            const size_t texel = static_cast<size_t>(y) * width + x;
            const Candidate& c = best[texel];
            if (c.triangle < 0) continue;
            const UvTriangle& t = triangles[static_cast<size_t>(c.triangle)];
            raster.samples[static_cast<size_t>(next)] =
                make_sample(geometry[static_cast<size_t>(t.geometry)], t, x, static_cast<int>(y));
            raster.sample_of[texel] = static_cast<int32_t>(next);
            ++next;
          }
        }
      },
      4);
  return raster;
}

void dilate(Image& image, const TexelRaster& raster, int iterations) {
  if (iterations < 0)
    throw Error(fmt::format("dilate: iterations must be ≥ 0, not {}", iterations));
  if (image.width() != raster.width || image.height() != raster.height)
    throw Error(fmt::format("dilate: image is {}x{} but the texel raster {}x{}", image.width(),
                            image.height(), raster.width, raster.height));
  const int width = raster.width, height = raster.height, channels = image.channels();
  ILLUM_CHECK(raster.sample_of.size() == static_cast<size_t>(width) * height,
              "texel raster has {} entries for {}x{}", raster.sample_of.size(), width, height);
  if (iterations == 0 || image.empty()) return;
  std::vector<uint8_t> filled(raster.sample_of.size());
  for (size_t i = 0; i < filled.size(); ++i) filled[i] = raster.sample_of[i] >= 0 ? 1 : 0;
  std::vector<uint8_t> filled_now(filled.size());
  for (int it = 0; it < iterations; ++it) {
    // Each pass reads only texels filled before it, so the result does not depend on the
    // order texels are visited in.
    std::fill(filled_now.begin(), filled_now.end(), 0);
    parallel_for(
        height,
        [&](int64_t y0, int64_t y1) {
          std::vector<double> sum(static_cast<size_t>(channels));
          for (int64_t y = y0; y < y1; ++y) {
            for (int x = 0; x < width; ++x) {
              const size_t texel = static_cast<size_t>(y) * width + x;
              if (filled[texel]) continue;
              std::fill(sum.begin(), sum.end(), 0.0);
              int n = 0;
              for (int dy = -1; dy <= 1; ++dy) {
                const int64_t ny = y + dy;
                if (ny < 0 || ny >= height) continue;
                for (int dx = -1; dx <= 1; ++dx) {
                  const int nx = x + dx;
                  if (nx < 0 || nx >= width || (dx == 0 && dy == 0)) continue;
                  if (!filled[static_cast<size_t>(ny) * width + nx]) continue;
                  const float* v = image.pixel(nx, static_cast<int>(ny));
                  for (int c = 0; c < channels; ++c) sum[static_cast<size_t>(c)] += v[c];
                  ++n;
                }
              }
              if (n == 0) continue;
              filled_now[texel] = 1;
              // Written in place: this texel was unfilled, so no other texel reads it in
              // this pass.
              float* out = image.pixel(x, static_cast<int>(y));
              for (int c = 0; c < channels; ++c)
                out[c] = static_cast<float>(sum[static_cast<size_t>(c)] / n);
            }
          }
        },
        16);
    bool any = false;
    for (size_t i = 0; i < filled.size(); ++i) {
      if (filled_now[i]) {
        filled[i] = 1;
        any = true;
      }
    }
    if (!any) break;
  }
}

}  // namespace illum::atlas
