// build_app(): the whole `illum` command line as one CLI11 app, so that main() and the
// option tests (tests/cli/cli_app_options_test.cpp) read the same definitions.
#include <algorithm>
#include <string>
#include <vector>

#include "commands.h"
#include "illum/core/error.h"
#include "illum/core/file_write.h"
#include "illum/core/image.h"
#include "illum/core/json_input.h"
#include "illum/core/params.h"
#include "job_role.h"
#include "option_checks.h"

namespace illum::cli {

namespace {
// `item` is the whole "key=value" for messages. A value that starts like a number but does
// not fit a double (1e400) or a '[' that is not a JSON array is an error, not a string: the
// reader would only say "must be a number" without the reason.
nlohmann::json parse_value(const std::string& text, const std::string& item) {
  if (text == "true") return true;
  if (text == "false") return false;
  if (!text.empty() && text.front() == '[')
    return parse_json(text, fmt::format("--param '{}'", item));
  size_t used = 0;
  try {
    const long long i = std::stoll(text, &used);
    if (used == text.size()) return i;
  } catch (const std::logic_error&) {
    // not an integer, or too long for one: may still be a double
  }
  try {
    const double d = std::stod(text, &used);
    if (used == text.size()) return d;
  } catch (const std::invalid_argument&) {
  } catch (const std::out_of_range&) {
    throw Error(fmt::format("--param '{}': {} is out of range for a number", item, text));
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
    if (eq + 1 == kv.size()) throw Error(fmt::format("--param '{}' has no value after '='", kv));
    if (j.contains(kv.substr(0, eq)))
      throw Error(fmt::format("--param '{}' is given more than once", kv.substr(0, eq)));
    j[kv.substr(0, eq)] = parse_value(kv.substr(eq + 1), kv);
  }
  return j;
}

void check_output_path(const std::string& path) {
  image_format_from_path(path);  // throws for an unknown extension
  check_writable_output(path);
}

void add_load_options(CLI::App* cmd, LoadOptions* options) {
  cmd->add_flag("--allow-missing-textures", options->allow_missing_textures,
                "a missing or unreadable texture, .mtl or environment map is one warning, and "
                "the scene renders without it (default: an error)");
}

std::unique_ptr<CLI::App> build_app(std::string* log_level) {
  auto app = std::make_unique<CLI::App>(
      "illum: global illumination for glTF/OBJ scenes — reference renderers, bakers, real-time");
  app->require_subcommand(1);
  app->set_version_flag("--version", "illum 0.1.0");
  app->add_option("--log", *log_level, "log level (also after the subcommand)")
      ->check(CLI::IsMember({"debug", "info", "warn", "error", "off"}));
  // Options a subcommand does not know are looked up on the app: `illum render ... --log
  // info` as well as `illum --log info render ...`. (Inherited by every subcommand.)
  app->fallthrough();

  add_info_command(*app);
  add_render_command(*app);
  add_bake_command(*app);
  add_relight_command(*app);
  add_export_command(*app);
#ifdef ILLUM_HAVE_FRAME_COMMAND
  add_frame_command(*app);
#endif
#ifdef ILLUM_HAVE_VIEW_COMMAND
  add_view_command(*app);
#endif
  refuse_empty_values(*app);
  // Only render and bake split their work across MPI ranks; the others would each write
  // the same files at once.
  for (CLI::App* command : app->get_subcommands({}))
    if (command->get_name() != "render" && command->get_name() != "bake" &&
        command->get_name() != "info")
      command->preparse_callback([name = command->get_name()](size_t) {
        refuse_with_several_ranks(true, "illum " + name,
                                  "only render and bake are split across ranks");
      });
  return app;
}

std::string unknown_option_message(const CLI::App& app, const std::string& argument) {
  if (argument.empty() || argument[0] != '-') return "";
  const std::string name = argument.substr(0, argument.find('='));
  std::vector<std::string> known;
  auto add = [&](const CLI::App& owner) {
    for (const CLI::Option* option : owner.get_options()) {
      for (const std::string& l : option->get_lnames()) known.push_back("--" + l);
      for (const std::string& s : option->get_snames()) known.push_back("-" + s);
    }
  };
  add(app);
  std::string where = "";
  const std::vector<CLI::App*> parsed = app.get_subcommands();
  if (!parsed.empty()) {
    add(*parsed.front());
    where = " of illum " + parsed.front()->get_name();
  }
  const std::string near = nearest_name(name, known);
  return fmt::format("unknown option {}{}{}", name, where,
                     near.empty()
                         ? fmt::format(" (see 'illum {}--help')",
                                       parsed.empty() ? "" : parsed.front()->get_name() + " ")
                         : fmt::format("; did you mean {}?", near));
}

}  // namespace illum::cli
