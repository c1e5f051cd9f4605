// Each subcommand of `illum` lives in its own cmd_*.cpp and registers itself on the CLI11
// app through one of these functions (explicit list in main.cpp, no static registration).
// Handlers throw illum::Error for bad input; main() turns that into one line and exit 2.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "illum/scene/load.h"

namespace illum::cli {

// The `illum` app with every subcommand and the app-level options (--log into *log_level,
// --version); accepted before or after the subcommand. main() adds what needs the MPI job.
std::unique_ptr<CLI::App> build_app(std::string* log_level);
// After CLI11 refused `argument` as not expected (ExtrasError): "unknown option --resoluton
// of illum bake; did you mean --resolution?" (the nearest option of the parsed subcommand
// and the app), or "" for an argument that is not an option.
std::string unknown_option_message(const CLI::App& app, const std::string& argument);

void add_info_command(CLI::App& app);
void add_render_command(CLI::App& app);
void add_bake_command(CLI::App& app);
void add_relight_command(CLI::App& app);  // cmd_relight.cpp
void add_export_command(CLI::App& app);   // cmd_export.cpp

// `illum bake --kind prt` (cmd_bake_prt.cpp): the options it shares with the light-map bake.
struct PrtBakeRequest {
  std::string scene, output, mode;
  int resolution = 512, spp = 256, bands = 4, threads = 0;
  int vq = 0;  // representatives of the VQ-compressed SHL-map, 0: none
  float texel_size = 0.0f;
  uint64_t seed = 0;
  std::vector<std::string> params;
  LoadOptions load;
  bool regenerate_uv1 = false;  // chart every mesh anew, even one with a valid UV1
};
void run_prt_bake(const PrtBakeRequest& request);
#ifdef ILLUM_HAVE_FRAME_COMMAND
void add_frame_command(CLI::App& app);
#endif
#ifdef ILLUM_HAVE_VIEW_COMMAND
void add_view_command(CLI::App& app);
#endif

// Turns repeated `--param key=value` strings into a JSON object: true/false, integers,
// floats and JSON arrays ("[1,2,3]") keep their type, anything else stays a string.
// Throws Error for an item without '=', with nothing after it, with a key given before, a
// number a double cannot hold (1e400) and a value starting with '[' that is not a JSON array
// (nesting bounded as in core/json_input.h).
nlohmann::json key_values_to_json(const std::vector<std::string>& items);

// Refuses an output path whose extension is not one of the image formats, whose folder
// does not exist or is not writable, or whose name is too long, before any long work starts.
void check_output_path(const std::string& path);

// --sun X,Y,Z[,E] and --sky R,G,B|V|FILE, the same on every command that lights a scene
// (scene/lighting_overrides.h says what each adds).
struct LightingArgs {
  std::string sun, sky;
};
void add_lighting_options(CLI::App* cmd, LightingArgs* args);
// What a command does with a scene that has no light: warn (its result is black) or refuse
// (a solver with no power to spread: radiosity, probes).
enum class Unlit { kWarn, kRefuse };
// Adds the sun and the sky to `scene` (add_sun_and_sky alone: render, whose integrators
// warn per integrator), then warns (held until log::release) or refuses when the scene has
// no light at all; `realtime` also warns that an environment is not shown there.
void apply_lighting_options(Scene& scene, const LightingArgs& args, const std::string& command,
                            Unlit unlit = Unlit::kWarn, bool realtime = false);
void add_sun_and_sky(Scene& scene, const LightingArgs& args);

// The scene-loading flags every subcommand that loads a scene takes (--allow-missing-textures).
void add_load_options(CLI::App* cmd, LoadOptions* options);

}  // namespace illum::cli
