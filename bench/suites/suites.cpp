#include "suites.h"

#include <embree3/rtcore_config.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include "illum/core/error.h"
#include "illum/scene/scene.h"

namespace illum::bench {

std::span<const Suite> suites() {
  // Explicit list (no static registration): one line per suite.
  static const Suite kSuites[] = {
      {"rays", "closest-hit throughput of illum's RayTracer vs a raw Embree loop", &run_rays},
      {"photons", "photon-map build and k-NN/radius query times: kd-tree vs nanoflann",
       &run_photons},
      {"caustics", "caustic error at equal time: path vs photon vs SPPM (spot and sphere light)",
       &run_caustics},
      {"path", "path-tracing samples/s and rays/s on cornell and sibenik", &run_path},
      {"lightmap", "light-map baker rays/s vs the path tracer; denoiser error and cost",
       &run_lightmap},
      {"lightmap-extras", "baked AO vs the ao integrator; global-line vs per-texel obscurance",
       &run_lightmap_extras},
      {"radiosity", "radiosity light-maps: time to equal error against the path-traced baker",
       &run_radiosity},
      {"prt", "PRT transfer bake time, VQ ratio and error, texel relighting vs bandwidth",
       &run_prt},
      {"atlas", "light-map atlas: charts, utilisation, texel density and stretch; build time",
       &run_atlas},
      {"prt-vs-path", "PRT relit from one bake vs the path tracer (band-limited and true light)",
       &run_prt_vs_path},
      {"prt-point-check",
       "direct PRT transfer at its texels vs the integral at camera hits (where they part)",
       &run_prt_point_check},
      {"probes", "irradiance-probe bake time per 1000 probes on cornell and sibenik", &run_probes},
      {"photon-defaults", "photon integrator's defaults vs the path tracer at equal time",
       &run_photon_defaults},
      {"converge", "equal-noise efficiency 1/(variance x time), illum vs Blender Cycles",
       &run_converge},
      {"gi-compare",
       "a real-time frame's indirect light vs the path tracer's first indirect bounce",
       &run_gi_compare},
#ifdef ILLUM_BENCH_HAVE_GPU
      {"raster", "real-time passes (illum frame --json) beside this GPU's raster and memory bounds",
       &run_raster},
      {"probes-dynamic",
       "a dynamic object lit by the probe volume (per pixel, per instance) vs "
       "the path tracer",
       &run_probes_dynamic},
#endif
  };
  return kSuites;
}

bool parse_args(CLI::App& app, SuiteArgs args) {
  std::vector<const char*> argv;
  argv.push_back(app.get_name().c_str());
  for (const std::string& a : args) argv.push_back(a.c_str());
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::CallForHelp&) {
    std::fputs(app.help().c_str(), stdout);
    return false;
  } catch (const CLI::ParseError& e) {
    throw Error(fmt::format("{}: {}", app.get_name(), e.what()));
  }
  return true;
}

nlohmann::json machine_info() {
  std::string cpu = "unknown";
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("model name", 0) == 0) {
      const size_t colon = line.find(':');
      if (colon != std::string::npos) cpu = line.substr(line.find_first_not_of(' ', colon + 1));
      break;
    }
  }
  return {{"cpu", cpu},
          {"hardware_threads", std::thread::hardware_concurrency()},
          {"embree", RTC_VERSION_STRING}};
}

void write_json(const std::string& path, const nlohmann::json& value) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw Error(fmt::format("{}: cannot write (missing folder?)", path));
    out << value.dump(2) << '\n';
    if (!out.flush()) throw Error(fmt::format("{}: write failed", path));
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw Error(fmt::format("{}: cannot write: {}", path, ec.message()));
  }
}

void check_output_folder(const std::string& path) {
  if (path.empty()) return;
  const std::filesystem::path parent = std::filesystem::absolute(path).parent_path();
  if (!std::filesystem::is_directory(parent))
    throw Error(fmt::format("{}: folder {} does not exist", path, parent.string()));
}

bool add_sky_if_unlit(Scene& scene) {
  if (!scene.lights.empty() || scene.environment) return false;
  Environment sky;
  sky.constant = Color(1.0f);
  scene.environment = sky;
  return true;
}

double median(std::vector<double> values) {
  const size_t n = values.size();
  std::sort(values.begin(), values.end());
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace illum::bench
