// The options `illum frame` and `illum view` share to set up the real-time renderer, all
// read from the technique declarations (realtime/technique_registry.h): --technique (frame
// pipeline), --shadows (shadow method), --enable/--disable (add-ons), --tonemap,
// --exposure, --fixed-exposure and -p NAME.key=value (or a short alias key).
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "illum/realtime/render_settings.h"
#include "illum/scene/scene.h"

namespace illum::cli {

struct RealtimeArgs {
  std::string technique = "forward";
  std::string shadows = "map";
  std::string tonemap = "aces";
  float exposure = 1.0f;
  bool fixed_exposure = false;
  std::vector<std::string> enable, disable;
  std::vector<std::string> params;
};

void add_realtime_options(CLI::App* cmd, RealtimeArgs* args);
// --baked DIR (repeatable): bake folders to show (baked_display.h).
void add_baked_option(CLI::App* cmd, std::vector<std::string>* folders);
// A shown PRT folder is relit by the `baked` add-on's sun, not by scene lights: `--sun
// X,Y,Z[,E]` sets that sun (baked.sun_azimuth/elevation/irradiance, which `-p` refuses).
void show_sun_on_prt(realtime::RenderSettings* settings, const std::string& sun);

// The settings the options describe, for `scene` (lighting.ambient defaults to its
// settings.ambient). With `timing` (illum frame --frames N > 1) the shadow methods
// re-render every frame unless -p says otherwise. Throws Error with one line naming the
// option, technique, parameter or value that is wrong.
realtime::RenderSettings realtime_settings(const RealtimeArgs& args, const Scene& scene,
                                           bool timing);

}  // namespace illum::cli
