// --sun and --sky: one definition for every command that lights a scene (render, bake,
// frame, view; relight reads the same two for its PRT light).
#include "commands.h"
#include "illum/core/error.h"
#include "illum/core/log.h"
#include "illum/scene/lighting_overrides.h"

namespace illum::cli {

void add_lighting_options(CLI::App* cmd, LightingArgs* args) {
  cmd->add_option("--sun", args->sun,
                  "add a sun: X,Y,Z the direction its light travels (as in scene files), "
                  "optionally ,E its irradiance in W/m² (default π)");
  cmd->add_option("--sky", args->sky,
                  "add a sky (replacing the scene's environment): R,G,B or V a uniform "
                  "radiance, or an equirectangular .hdr/.exr file");
}

void add_sun_and_sky(Scene& scene, const LightingArgs& args) {
  if (!args.sun.empty()) add_sun(scene, args.sun);
  if (!args.sky.empty()) set_sky(scene, args.sky);
}

void apply_lighting_options(Scene& scene, const LightingArgs& args, const std::string& command,
                            Unlit unlit, bool realtime) {
  add_sun_and_sky(scene, args);
  if (!has_any_light(scene)) {
    if (unlit == Unlit::kRefuse)
      throw Error(unlit_scene_message(scene, command, "nothing to bake"));
    log::warn("{}", unlit_scene_message(scene, command));
  }
  if (realtime && scene.environment)
    log::warn(
        "{}: the real-time renderer does not light with an environment yet: the {} is "
        "not shown (the offline renderers and bakers use it)",
        command, args.sky.empty() ? "scene's environment" : "--sky");
}

}  // namespace illum::cli
