// Light-map atlas (ALGORITHMS.md item 5): every light-mapped triangle gets a place in one
// shared square texture. Triangles are grouped into charts (connected, nearly coplanar
// pieces of a mesh), each chart is flattened to 2-D at a uniform world-space texel density,
// and the charts are packed with at least `padding` empty texels between them so bilinear
// filtering never mixes two charts (S002 §3.3.6).
//
// UV convention (shared with the texel raster, the bakers and the shaders): uv1 ∈ [0,1]²;
// texel (x, y) covers [x/W, (x+1)/W] × [y/H, (y+1)/H]; y = 0 is the image's first row (the
// first row uploaded to the GPU), so no flip anywhere.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "illum/core/math.h"
#include "illum/core/params.h"
#include "illum/scene/scene.h"

namespace illum::atlas {

// The atlas side's range: below 16 texels no chart fits its padding; 16384 is the image
// limit of every other output (render/integrator.h kMaxImageSide).
inline constexpr int kMinResolution = 16;
inline constexpr int kMaxResolution = 16384;

struct AtlasOptions {
  int resolution = 512;           // atlas width = height, in texels, in [kMin, kMaxResolution]
  float texel_size = 0.0f;        // world metres per texel; 0 = the finest that fits
  int padding = 2;                // empty texels between charts (≥ 1)
  float max_chart_angle = 45.0f;  // degrees: a chart's normals stay within this of its axis
  // A mesh that brings its own light-map UVs (Mesh::uv1, glTF TEXCOORD_1) keeps them when
  // they pass check_mesh_uv1 (uv1_check.h): they become that mesh's chart, scaled to the
  // nominal density on average. false: every mesh is charted anew.
  bool reuse_uv1 = true;

  // Keys: resolution, texel_size, padding, max_chart_angle, reuse_uv1. Throws Error on values out
  // of range (resolution 16..16384, texel_size ≥ 0 and finite, padding 1..16, angle (0, 89]).
  static AtlasOptions from_params(const Params& params);
};

// Atlas::charts index of a triangle whose mesh no instance uses (it takes no atlas space;
// its uv1 is (0, 0)).
inline constexpr uint32_t kNoChart = 0xffffffffu;

// Where one chart lies: every texel its triangles touch (conservatively) is inside the
// texel rectangle [x, x + width) × [y, y + height), which is at least `padding` texels inside
// the atlas border. Texels touched by two different charts are more than `padding` apart
// (at least `padding` empty texels between them). Two rectangles are either that far apart
// or nested: a small chart may be placed in the empty part of a large chart's rectangle.
struct AtlasChart {
  int mesh = 0;  // Scene::meshes index
  int x = 0, y = 0, width = 0, height = 0;
};

// One mesh's light-map layout. Vertices on chart seams are split, so the mesh gets a new
// vertex list: new vertex i copies every attribute of source vertex source_vertex[i] and
// has light-map coordinate uv1[i]. Triangle t keeps its number (indices[3t..3t+2] are the
// new vertices of old triangle t), so hit records stay valid.
struct MeshLayout {
  std::vector<uint32_t> source_vertex;
  std::vector<vec2> uv1;
  std::vector<uint32_t> indices;
  // Checked against the mesh by apply_atlas (a layout baked for another scene is refused).
  uint32_t source_vertex_count = 0;
  // Atlas::charts index of each triangle (kNoChart: mesh without instance); may be empty
  // in an atlas made by hand.
  std::vector<uint32_t> triangle_chart;
  // The mesh's own UV1 was kept (AtlasOptions::reuse_uv1); not stored in the atlas file.
  bool reused_uv1 = false;
};

struct Atlas {
  int width = 0;
  int height = 0;
  float texel_size = 0.0f;  // world metres per texel actually used
  int chart_count = 0;
  std::vector<MeshLayout> meshes;  // one per Scene::meshes entry, same order
  std::vector<AtlasChart> charts;  // chart_count entries (may be empty in an atlas made by hand)
};

// Light-maps need one chart set per instance: gives every instance after the first that
// shares a mesh its own copy of the mesh (Instance::mesh updated). Idempotent.
void make_meshes_unique(Scene& scene);

// Builds the atlas for every mesh of `scene` (which must have unique meshes: throws Error
// otherwise). Throws Error when the charts cannot fit `resolution` at `texel_size`, naming
// both numbers. Deterministic: the same scene and options give the same atlas.
Atlas build_atlas(const Scene& scene, const AtlasOptions& options);

// Rewrites the scene's meshes with the atlas layout (splits seam vertices, fills uv1).
// Throws Error if the atlas does not match the scene (mesh count, vertex or triangle counts).
void apply_atlas(Scene& scene, const Atlas& atlas);

// The charting every baker does first: make_meshes_unique, build_atlas, apply_atlas. The
// scene's meshes then carry the atlas's uv1; the atlas is returned for the light-map folder
// and the texel raster.
Atlas chart_scene(Scene& scene, const AtlasOptions& options);

// Binary file (little-endian, magic "ILLUMATL", version 1). load_atlas throws Error on a
// missing, truncated or malformed file; save_atlas writes a temporary file and renames it.
void save_atlas(const Atlas& atlas, const std::filesystem::path& path);
Atlas load_atlas(const std::filesystem::path& path);

}  // namespace illum::atlas
