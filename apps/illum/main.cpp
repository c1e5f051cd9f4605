// illum: global illumination for games and real-time 3D — command-line entry point.
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "commands.h"
#include "illum/core/error.h"
#include "illum/core/image.h"
#include "illum/core/interrupt.h"
#include "illum/core/log.h"

namespace illum::cli {

namespace {
nlohmann::json parse_value(const std::string& text) {
  if (text == "true") return true;
  if (text == "false") return false;
  try {
    size_t used = 0;
    const long long i = std::stoll(text, &used);
    if (used == text.size()) return i;
    const double d = std::stod(text, &used);
    if (used == text.size()) return d;
  } catch (const std::exception&) {
  }
  if (!text.empty() && text.front() == '[') {
    try {
      return nlohmann::json::parse(text);
    } catch (const std::exception&) {
    }
  }
  return text;
}
}  // namespace

nlohmann::json key_values_to_json(const std::vector<std::string>& items) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& kv : items) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0)
      throw Error(fmt::format("--param '{}' must look like key=value", kv));
    j[kv.substr(0, eq)] = parse_value(kv.substr(eq + 1));
  }
  return j;
}

void check_output_path(const std::string& path) {
  image_format_from_path(path);  // throws for an unknown extension
  const auto parent = std::filesystem::path(path).parent_path();
  if (!parent.empty() && !std::filesystem::is_directory(parent))
    throw Error(fmt::format("{}: output folder '{}' does not exist", path, parent.string()));
}

void add_load_options(CLI::App* cmd, LoadOptions* options) {
  cmd->add_flag("--allow-missing-textures", options->allow_missing_textures,
                "a missing or unreadable texture, .mtl or environment map is one warning, and "
                "the scene renders without it (default: an error)");
}

}  // namespace illum::cli

int main(int argc, char** argv) {
  CLI::App app{
      "illum: global illumination for glTF/OBJ scenes — reference renderers, bakers, real-time"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "illum 0.1.0");
  std::string log_level = "warn";
  app.add_option("--log", log_level, "log level")
      ->check(CLI::IsMember({"debug", "info", "warn", "error", "off"}));
  app.parse_complete_callback([&] {
    using illum::log::Level;
    const Level level = log_level == "debug"   ? Level::kDebug
                        : log_level == "info"  ? Level::kInfo
                        : log_level == "warn"  ? Level::kWarn
                        : log_level == "error" ? Level::kError
                                               : Level::kOff;
    illum::log::set_level(level);
  });

  illum::cli::add_info_command(app);
  illum::cli::add_render_command(app);
  illum::cli::add_bake_command(app);
#ifdef ILLUM_HAVE_FRAME_COMMAND
  illum::cli::add_frame_command(app);
#endif
#ifdef ILLUM_HAVE_VIEW_COMMAND
  illum::cli::add_view_command(app);
#endif

  illum::install_interrupt_handler();
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const illum::Interrupted&) {
    std::fprintf(stderr, "illum: interrupted; nothing was written\n");
    return 130;
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "illum: error: %s (see 'illum --help')\n", e.what());
    return 2;
  } catch (const illum::Error& e) {
    std::fprintf(stderr, "illum: error: %s\n", e.what());
    return 2;
  } catch (const illum::InternalError& e) {
    std::fprintf(stderr, "illum: %s — please report this bug\n", e.what());
    return 3;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "illum: error: out of memory\n");
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "illum: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
