// `illum-bench prt`: the figures of bench/results/prt.md on one scene (default: the Cornell box):
//  1. transfer bake time per 100k covered texels at --bands, shadowed and interreflected
//     (texels only, `--spp` rays a texel);
//  2. VQ compression of the interreflected SHL-map at each --representatives K: time,
//     iterations, compression against the fp32 map (N·3n²·4 bytes against N·2 + K·3n²·4), the
//     vector error, and what matters to a viewer — the relit texels' error under a sun and
//     under a uniform sky, RMS and largest, relative to the RMS of the exact relit values;
//  3. relighting --relight-texels texels (the covered texels' vectors repeated) under a new
//     sun in each repetition, in the three storage forms of bake/prt_texel_relight.h, beside
//     the bound of the bytes each form reads and writes at this machine's copy bandwidth
//     (a parallel memcpy of 256 MiB measured in the same run, bytes read + written / s).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "illum/atlas/atlas.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/prt_baker.h"
#include "illum/bake/prt_relight.h"
#include "illum/bake/prt_texel_relight.h"
#include "illum/bake/prt_vq.h"
#include "illum/core/error.h"
#include "illum/core/parallel.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"
#include "suites.h"

namespace illum::bench {

namespace {

struct PrtArgs {
  std::string scene = "cornell";
  int resolution = 256;
  int bands = 4;
  int spp = 64;
  int relight_texels = 1000000;
  std::vector<int> representatives = {4096, 16384};
  int repeats = 20;
  int threads = 0;
  uint64_t seed = 1;
  std::string json_path;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The covered texels' transfer vectors, packed (the map also holds dilated and empty texels).
std::vector<float> covered_vectors(const bake::TransferMap& map, const atlas::TexelRaster& raster) {
  std::vector<float> v;
  v.reserve(raster.covered() * size_t(map.channels));
  for (const atlas::TexelSample& s : raster.samples) {
    const float* p = map.pixel(s.x, s.y);
    v.insert(v.end(), p, p + map.channels);
  }
  return v;
}

// A sun for repetition k: directions spread over the upper hemisphere so no two repetitions
// relight with the same light.
bake::ShLight sun_for(int bands, int k) {
  const float phi = 2.399963f * float(k), z = 0.3f + 0.6f * float((k * 7) % 10) / 10.0f;
  const float r = std::sqrt(1.0f - z * z);
  return bake::sun_light(bands, -vec3(r * std::cos(phi), z, r * std::sin(phi)), Color(1.0f));
}

// Bytes read + written per second by a parallel memcpy between two buffers of `bytes`.
double copy_bytes_per_s(size_t bytes, int repeats) {
  std::vector<char> a(bytes, 1), b(bytes, 0);
  const int64_t chunks = 256;
  std::vector<double> runs;
  for (int r = 0; r < repeats + 1; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    char* dst = r % 2 ? a.data() : b.data();
    const char* src = r % 2 ? b.data() : a.data();
    parallel_for(
        chunks,
        [&](int64_t begin, int64_t end) {
          const size_t lo = bytes * size_t(begin) / size_t(chunks);
          const size_t hi = bytes * size_t(end) / size_t(chunks);
          std::memcpy(dst + lo, src + lo, hi - lo);
        },
        1);
    if (r > 0) runs.push_back(seconds_since(t0));
  }
  return 2.0 * double(bytes) / median(runs);
}

template <typename Fn>
std::vector<double> time_runs(int repeats, Fn&& fn) {
  std::vector<double> runs;
  for (int r = 0; r < repeats + 1; ++r) {  // the first warms caches and pages
    const auto t0 = std::chrono::steady_clock::now();
    fn(r);
    if (r > 0) runs.push_back(seconds_since(t0));
  }
  return runs;
}

}  // namespace

int run_prt(SuiteArgs args) {
  CLI::App app("PRT: transfer bake time, VQ compression and error, texel relighting throughput",
               "illum-bench prt");
  PrtArgs a;
  app.add_option("--scene", a.scene, "built-in scene name or scene file (default: cornell)");
  app.add_option("--resolution", a.resolution, "atlas side in texels")->check(CLI::Range(16, 4096));
  app.add_option("--bands", a.bands, "SH bands")
      ->check(CLI::Range(bake::kMinPrtBands, bake::kMaxPrtBands));
  app.add_option("--spp", a.spp, "visibility and shooting rays a texel")
      ->check(CLI::Range(1, 1 << 16));
  app.add_option("--relight-texels", a.relight_texels, "texels relit in part 3")
      ->check(CLI::Range(1, 1 << 26));
  app.add_option("--representatives", a.representatives, "VQ codebook sizes (part 2)")
      ->delimiter(',')
      ->check(CLI::Range(1, bake::kMaxVqRepresentatives));
  app.add_option("--repeats", a.repeats, "timed relighting repetitions (median)")
      ->check(CLI::Range(1, 10000));
  app.add_option("--threads", a.threads, "TBB threads (0 = all cores)")->check(CLI::Range(0, 4096));
  app.add_option("--seed", a.seed, "sampler and VQ seed");
  app.add_option("--json", a.json_path, "write the results here");
  if (!parse_args(app, args)) return 0;
  check_output_folder(a.json_path);
  ThreadLimit limit(a.threads);
  const int threads = a.threads > 0 ? a.threads : ThreadLimit::hardware_threads();

  Scene scene = load_scene(a.scene);
  const atlas::Atlas atl = atlas::chart_scene(scene, {.resolution = a.resolution});
  const RayTracer tracer(scene);
  const atlas::TexelRaster raster = atlas::rasterize_texels(scene, atl.width, atl.height);
  const size_t covered = raster.covered();
  if (covered == 0) throw Error(fmt::format("prt: scene '{}' has no light-mapped texel", a.scene));
  nlohmann::json j;
  j["suite"] = "prt";
  j["scene"] = scene.name;
  j["atlas"] = {atl.width, atl.height};
  j["covered_texels"] = covered;
  j["bands"] = a.bands;
  j["spp"] = a.spp;
  j["threads"] = threads;
  std::printf("prt: %s, atlas %dx%d, %zu covered texels, %d bands, %d rays a texel, %d threads\n",
              scene.name.c_str(), atl.width, atl.height, covered, a.bands, a.spp, threads);

  // 1. Bake time.
  bake::PrtBake interreflected;
  for (bake::PrtMode mode : {bake::PrtMode::kShadowed, bake::PrtMode::kInterreflected}) {
    bake::PrtBakeOptions o;
    o.bands = a.bands;
    o.mode = mode;
    o.spp = a.spp;
    o.seed = a.seed;
    o.vertices = false;
    o.progress = false;
    bake::PrtBake b = bake::bake_prt(scene, tracer, raster, o);
    const double per_100k = b.seconds * 1e5 / double(b.texels);
    std::printf("  bake %-15s %8.2f s, %.3g rays, %.2f s per 100k texels%s\n", to_string(mode),
                b.seconds, double(b.rays), per_100k,
                mode == bake::PrtMode::kInterreflected
                    ? fmt::format(" (shooting {:.2f} s, {} rounds, unshot {:.2g})", b.shoot_seconds,
                                  b.shoot_rounds, b.unshot_fraction)
                          .c_str()
                    : "");
    j["bake"][to_string(mode)] = {{"seconds", b.seconds},
                                  {"texels", b.texels},
                                  {"rays", b.rays},
                                  {"seconds_per_100k_texels", per_100k},
                                  {"shoot_seconds", b.shoot_seconds},
                                  {"shoot_rounds", b.shoot_rounds}};
    if (mode == bake::PrtMode::kInterreflected) interreflected = std::move(b);
  }
  const std::vector<float> vectors = covered_vectors(interreflected.texel_transfer, raster);
  const size_t dim = 3 * size_t(a.bands) * size_t(a.bands);

  // 2. VQ: compression and error, relit under a sun and under a uniform sky (radiance 1 from
  // every direction: only Y₀₀, c₀ = 2√π). A band-limited sun rings negative in places, so the
  // errors are relative to the RMS of the exact relit values, not to their mean.
  struct TestLight {
    const char* name;
    bake::ShLight light;
    std::vector<float> exact;
    double rms = 0.0;
  };
  bake::ShLight sky;
  sky.bands = a.bands;
  sky.coefficients.assign(size_t(a.bands) * size_t(a.bands), Color(0.0f));
  sky.coefficients[0] = Color(2.0f * std::sqrt(float(M_PI)));
  std::vector<TestLight> lights = {{"sun", sun_for(a.bands, 12345), {}, 0.0},
                                   {"sky", sky, {}, 0.0}};
  for (TestLight& l : lights) {
    l.exact.resize(3 * covered);
    bake::relight_texels(std::span<const float>(vectors), a.bands, l.light, l.exact);
    for (float v : l.exact) l.rms += double(v) * v;
    l.rms = std::sqrt(l.rms / double(l.exact.size()));
  }
  std::vector<float> approx(3 * covered);
  double vector_rms = 0.0;
  for (float v : vectors) vector_rms += double(v) * v;
  vector_rms = std::sqrt(vector_rms / double(covered));
  bake::VqCodebook first_codebook;
  std::printf("  %-6s %8s %6s %8s %10s %21s %21s\n", "VQ K", "seconds", "iters", "ratio", "vec rms",
              "sun: relit rms, max", "sky: relit rms, max");
  for (int k : a.representatives) {
    bake::VqOptions vo;
    vo.representatives = std::min<int>(k, int(covered));
    vo.seed = a.seed;
    const auto t0 = std::chrono::steady_clock::now();
    bake::VqCodebook cb = bake::vq_compress(vectors, int(dim), vo);
    const double seconds = seconds_since(t0);
    const double ratio =
        double(covered * dim * 4) / double(covered * 2 + size_t(cb.count()) * dim * 4);
    nlohmann::json jk = {{"representatives", cb.count()},
                         {"asked", k},
                         {"seconds", seconds},
                         {"iterations", cb.iterations},
                         {"ratio_vs_fp32", ratio},
                         {"vector_rms_relative", cb.rms_distance / vector_rms},
                         {"vector_max", cb.max_distance}};
    std::string errors;
    for (const TestLight& l : lights) {
      bake::relight_texels(cb, a.bands, l.light, approx);
      double se = 0.0, worst = 0.0;
      for (size_t i = 0; i < approx.size(); ++i) {
        const double d = std::abs(double(approx[i]) - l.exact[i]);
        se += d * d;
        worst = std::max(worst, d);
      }
      const double rms = std::sqrt(se / double(approx.size())) / l.rms, max = worst / l.rms;
      errors += fmt::format(" {:>10.4f} {:>10.4f}", rms, max);
      jk[fmt::format("{}_relit_rms_relative", l.name)] = rms;
      jk[fmt::format("{}_relit_max_relative", l.name)] = max;
    }
    std::printf("  %-6d %8.2f %6d %6.1f:1 %10.4f%s\n", cb.count(), seconds, cb.iterations, ratio,
                cb.rms_distance / vector_rms, errors.c_str());
    j["vq"].push_back(jk);
    if (first_codebook.count() == 0) first_codebook = std::move(cb);
  }

  // 3. Relighting N texels in each form.
  const size_t n = size_t(a.relight_texels);
  std::vector<float> big(n * dim);
  for (size_t t = 0; t < n; ++t)
    std::memcpy(&big[t * dim], &vectors[(t % covered) * dim], dim * sizeof(float));
  const std::vector<uint16_t> big_half = bake::to_half(big);
  bake::VqCodebook big_vq;
  if (first_codebook.count() > 0) {
    big_vq.dimension = first_codebook.dimension;
    big_vq.representatives = first_codebook.representatives;
    big_vq.indices.resize(n);
    for (size_t t = 0; t < n; ++t) big_vq.indices[t] = first_codebook.indices[t % covered];
  }
  std::vector<float> out(3 * n);
  const double copy = copy_bytes_per_s(size_t(256) << 20, a.repeats);
  std::printf("  copy bandwidth %.1f GB/s (parallel memcpy of 256 MiB, read + written)\n",
              copy * 1e-9);
  j["copy_gb_per_s"] = copy * 1e-9;
  struct Form {
    const char* name;
    double bytes;  // read + written per relight
    std::function<void(int)> run;
  };
  const double written = double(out.size() * sizeof(float));
  std::vector<Form> forms = {{"fp32", double(big.size() * 4) + written,
                              [&](int r) {
                                bake::relight_texels(std::span<const float>(big), a.bands,
                                                     sun_for(a.bands, r), out);
                              }},
                             {"fp16", double(big_half.size() * 2) + written, [&](int r) {
                                bake::relight_texels(std::span<const uint16_t>(big_half), a.bands,
                                                     sun_for(a.bands, r), out);
                              }}};
  if (big_vq.count() > 0)
    forms.push_back({"vq", double(n * 2 + big_vq.representatives.size() * 4) + written, [&](int r) {
                       bake::relight_texels(big_vq, a.bands, sun_for(a.bands, r), out);
                     }});
  std::printf("  relight %zu texels, %d bands, median of %d:\n  %-6s %10s %10s %8s %10s\n", n,
              a.bands, a.repeats, "form", "ms", "bound ms", "ratio", "MB moved");
  for (const Form& f : forms) {
    const std::vector<double> runs = time_runs(a.repeats, f.run);
    const double ms = median(runs) * 1e3, bound = f.bytes / copy * 1e3;
    std::printf("  %-6s %10.3f %10.3f %8.2f %10.1f\n", f.name, ms, bound, ms / bound,
                f.bytes * 1e-6);
    j["relight"].push_back({{"form", f.name},
                            {"texels", n},
                            {"median_ms", ms},
                            {"bound_ms", bound},
                            {"bytes", f.bytes},
                            {"runs_s", runs}});
  }
  j["machine"] = machine_info();
  if (!a.json_path.empty()) write_json(a.json_path, j);
  return 0;
}

}  // namespace illum::bench
