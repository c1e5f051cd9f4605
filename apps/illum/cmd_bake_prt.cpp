// `illum bake SCENE --kind prt -o FOLDER` (the PRT kind of cmd_bake.cpp's bake command):
// bakes SH transfer (bake/prt_baker.h) into the folder of baked/prt_file.h, which
// `illum relight` (cmd_relight.cpp) renders.
#include <chrono>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "illum/atlas/atlas.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_seams.h"
#include "illum/bake/prt_baker.h"
#include "illum/bake/prt_vq.h"
#include "illum/baked/prt_file.h"
#include "illum/core/log.h"
#include "illum/core/parallel.h"
#include "illum/scene/geometry_hash.h"
#include "illum/scene/load.h"
#include "option_checks.h"

namespace illum::cli {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void run_prt_bake(const PrtBakeRequest& args) {
  baked::check_prt_output(args.output);
  nlohmann::json j = key_values_to_json(args.params);
  refuse_params_of_options(j, {{"resolution", "--resolution"},
                               {"texel_size", "--texel-size"},
                               {"spp", "--spp"},
                               {"bands", "--bands"},
                               {"mode", "--mode"},
                               {"seed", "--seed"},
                               {"reuse_uv1", "--regenerate-uv1"}});
  j["resolution"] = args.resolution;
  j["reuse_uv1"] = !args.regenerate_uv1;
  j["texel_size"] = args.texel_size;
  j["spp"] = args.spp;
  j["bands"] = args.bands;
  j["mode"] = args.mode;
  j["seed"] = args.seed;
  const Params params(j, "--param");
  const atlas::AtlasOptions atlas_options = atlas::AtlasOptions::from_params(params);
  bake::PrtBakeOptions options = bake::PrtBakeOptions::from_params(params);
  params.check_all_used();
  options.threads = args.threads;

  ThreadLimit limit(args.threads);
  Scene scene = load_scene(args.scene, args.load);
  baked::PrtSet set;
  set.scene_triangles = scene.triangle_count();
  auto t0 = std::chrono::steady_clock::now();
  set.atlas = atlas::chart_scene(scene, atlas_options);
  const double atlas_s = seconds_since(t0);
  const RayTracer tracer(scene);
  atlas::TexelRaster raster = atlas::rasterize_texels(scene, set.atlas.width, set.atlas.height);
  // As `illum bake` does: texel samples inside or behind geometry would leak light into the
  // transfer (bake/lightmap_seams.h).
  const bake::TexelPushOut pushed = bake::keep_texels_out_of_geometry(scene, tracer, raster);
  log::release();
  bake::PrtBake baked = bake::bake_prt(scene, tracer, raster, options);

  set.bands = baked.bands;
  set.mode = baked.mode;
  set.texel_transfer = std::move(baked.texel_transfer);
  set.vertex_transfer = std::move(baked.vertex_transfer);
  double vq_seconds = 0.0;
  if (args.vq > 0) {
    const auto tv = std::chrono::steady_clock::now();
    bake::VqOptions vq;
    vq.representatives = args.vq;
    vq.seed = args.seed;
    set.vq = bake::vq_compress(set.texel_transfer.data, set.texel_transfer.channels, vq);
    vq_seconds = seconds_since(tv);
  }
  set.scene = scene.name;
  set.scene_hash = geometry_hash_hex(scene);  // with the atlas applied, as apply_prt_set checks
  set.bake = {{"spp", options.spp},
              {"seed", options.seed},
              {"dilate", options.dilate},
              {"stitch", options.stitch},
              {"stitch_coplanar", options.stitch_coplanar},
              {"seam_edges", baked.seam_edges},
              {"coplanar_edges", baked.coplanar_edges},
              {"stitch_seconds", baked.stitch_seconds},
              {"shoot_tolerance", options.shoot_tolerance},
              {"shoot_relative_tolerance", options.shoot_relative_tolerance},
              {"max_rounds", options.max_rounds},
              {"normal_maps", options.normal_maps},
              {"normal_map_samples", options.normal_map_samples},
              {"texels", baked.texels},
              {"vertices", baked.vertices},
              {"rays", baked.rays},
              {"atlas_seconds", atlas_s},
              {"bake_seconds", baked.seconds},
              {"shoot_seconds", baked.shoot_seconds},
              {"texels_pushed_out", pushed.moved},
              {"texels_rejected", pushed.rejected}};
  set.bake.update(bake::shooting_record(baked));
  if (set.vq.count() > 0) {
    const double full = double(set.texel_transfer.data.size()) * 4.0;
    const double packed =
        double(set.vq.representatives.size()) * 4.0 + double(set.vq.indices.size()) * 2.0;
    set.bake["vq_seconds"] = vq_seconds;
    set.bake["vq_compression"] = full / packed;
    std::fprintf(stderr,
                 "illum: VQ %d representatives, %d iterations, max distance %.4g, rms %.4g, "
                 "%.1f:1 against the f32 map, %.2fs\n",
                 set.vq.count(), set.vq.iterations, set.vq.max_distance, set.vq.rms_distance,
                 full / packed, vq_seconds);
  }
  baked::save_prt_set(args.output, set);
  std::fprintf(stderr,
               "illum: bake %s, prt %d bands %s: atlas %dx%d, %zu texels, %zu vertices, %d spp "
               "in %.2fs (shooting %.2fs, %d rounds, unshot %.2g) -> %s\n",
               scene.name.c_str(), set.bands, bake::to_string(set.mode), set.atlas.width,
               set.atlas.height, baked.texels, baked.vertices, options.spp, baked.seconds,
               baked.shoot_seconds, baked.shoot_rounds, baked.unshot_fraction, args.output.c_str());
}

}  // namespace illum::cli
