// The suites of `illum-bench`. A suite is a function that receives the arguments after its
// name and returns the process exit code; bad input throws illum::Error (illum-bench prints
// one line and exits 2). To add one: write bench/bench_NAME.cpp defining it, declare it
// here, and add one line to the list in suites.cpp.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace illum {
struct Scene;
}

namespace illum::bench {

using SuiteArgs = std::span<const std::string>;
using SuiteFn = int (*)(SuiteArgs args);

struct Suite {
  const char* name;
  const char* summary;  // one line for the usage text
  SuiteFn run;
};

// The registered suites, in the order the usage text lists them.
std::span<const Suite> suites();

// --- suites -----------------------------------------------------------------------------
int run_rays(SuiteArgs args);     // bench_rays.cpp: ray-query throughput, illum vs raw Embree
int run_photons(SuiteArgs args);  // bench_photons.cpp: photon-map build/query, kd-tree vs nanoflann
int run_caustics(SuiteArgs args);  // bench_caustics.cpp: caustics, path vs photon vs SPPM
int run_path(SuiteArgs args);      // bench_path.cpp: path-tracing samples/s and rays/s
int run_lightmap(SuiteArgs args);  // bench_lightmap.cpp: light-map baker vs path tracer, denoiser
int run_lightmap_extras(SuiteArgs args);  // bench_lightmap_extras.cpp: AO/obscurance maps
int run_radiosity(SuiteArgs args);  // bench_radiosity.cpp: radiosity vs path bake, equal error
int run_prt(SuiteArgs args);     // bench_prt.cpp: PRT bake time, VQ, texel relighting vs bandwidth
int run_probes(SuiteArgs args);  // bench_probes.cpp: probe bake time per 1000 probes
int run_atlas(SuiteArgs args);   // bench_atlas.cpp: atlas charts, utilisation, stretch, time
// bench_prt_vs_path.cpp: PRT relit from one bake vs the path tracer, image grid and errors
int run_prt_vs_path(SuiteArgs args);
// bench_prt_point_check.cpp: direct PRT transfer at its texels vs the integral at camera hits
int run_prt_point_check(SuiteArgs args);
// bench_photon_defaults.cpp: the photon integrator's defaults vs the path tracer
int run_photon_defaults(SuiteArgs args);
// bench_converge.cpp: equal-noise efficiency, illum vs Blender Cycles (peer)
int run_converge(SuiteArgs args);
// bench_gi_compare.cpp: a real-time frame's indirect light vs the path tracer's indirect1
int run_gi_compare(SuiteArgs args);
#ifdef ILLUM_BENCH_HAVE_GPU
int run_raster(SuiteArgs args);  // bench_raster.cpp: real-time passes beside the device's bounds
// bench_probes_dynamic.cpp: a dynamic object lit by the probe volume vs the path tracer
int run_probes_dynamic(SuiteArgs args);
#endif

// --- helpers shared by suites ---------------------------------------------------------------

// Parses `args` with `app` (named "illum-bench SUITE"). Returns false when --help was
// printed (exit 0); throws illum::Error with CLI11's one-line message on bad input.
bool parse_args(CLI::App& app, SuiteArgs args);

// What machine produced the numbers: CPU model, hardware threads, Embree version.
nlohmann::json machine_info();

// Writes `value` to `path` through a temporary file renamed on success; throws
// illum::Error naming the path on failure.
void write_json(const std::string& path, const nlohmann::json& value);

// Throws illum::Error naming `path` when the folder it would be written to does not exist
// (nothing for an empty path): call it before minutes of measuring, not after.
void check_output_folder(const std::string& path);

// Gives a scene with no light at all (Sibenik before it had a sun) a uniform white sky of
// radiance 1, so paths do the work a lit scene would; returns whether it did.
bool add_sky_if_unlit(Scene& scene);

// Median of a non-empty list (mean of the middle two for an even count).
double median(std::vector<double> values);

}  // namespace illum::bench
