// The explicit list of integrators (no static registration): add one include and one line
// in kIntegrators to register a new one.
#include "illum/render/integrator.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "illum/core/error.h"
#include "illum/render/ao_integrator.h"
#include "illum/render/debug_integrator.h"
#include "illum/render/path_integrator.h"
#include "illum/render/photon_integrator.h"
#include "illum/render/sppm.h"
#include "illum/render/whitted_integrator.h"

namespace illum {

namespace {

using Factory = std::unique_ptr<Integrator> (*)(const Params&);

struct Registration {
  const char* name;
  Factory create;
};

template <typename T>
std::unique_ptr<Integrator> make(const Params& params) {
  return std::make_unique<T>(params);
}

std::unique_ptr<Integrator> make_normals(const Params& p) {
  return std::make_unique<DebugIntegrator>(DebugIntegrator::Mode::kNormals, p);
}
std::unique_ptr<Integrator> make_albedo(const Params& p) {
  return std::make_unique<DebugIntegrator>(DebugIntegrator::Mode::kAlbedo, p);
}
std::unique_ptr<Integrator> make_depth(const Params& p) {
  return std::make_unique<DebugIntegrator>(DebugIntegrator::Mode::kDepth, p);
}

const Registration kIntegrators[] = {
    {"normals", make_normals},
    {"albedo", make_albedo},
    {"depth", make_depth},
    {"ao", make<AoIntegrator>},
    {"whitted", make<WhittedIntegrator>},
    {"path", make<PathIntegrator>},
    // Photon mapping and SPPM register below.
    {"photon", make<PhotonIntegrator>},
    {"sppm", make<SppmIntegrator>},
};

}  // namespace

std::vector<std::string> Integrator::names() {
  std::vector<std::string> out;
  for (const Registration& r : kIntegrators) out.emplace_back(r.name);
  return out;
}

std::unique_ptr<Integrator> Integrator::create(const std::string& name, const Params& params) {
  for (const Registration& r : kIntegrators) {
    if (name != r.name) continue;
    std::unique_ptr<Integrator> integrator = r.create(params);
    params.check_all_used();  // a misspelt --param is an error, not a silent default
    return integrator;
  }
  throw Error(fmt::format("unknown integrator '{}' (known: {})", name, fmt::join(names(), ", ")));
}

}  // namespace illum
