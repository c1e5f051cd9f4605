// illum: global illumination for games and real-time 3D — command-line entry point.
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "illum/core/error.h"
#include "illum/core/file_write.h"
#include "illum/core/image.h"
#include "illum/core/interrupt.h"
#include "illum/core/json_input.h"
#include "illum/core/log.h"
#include "illum/distributed/mpi_job.h"
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

}  // namespace illum::cli

int main(int argc, char** argv) {
  CLI::App app{
      "illum: global illumination for glTF/OBJ scenes — reference renderers, bakers, real-time"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "illum 0.1.0");
  std::string log_level = "warn";
  std::unique_ptr<illum::distributed::MpiJob> job;  // under mpirun only
  bool other_rank = false;  // a rank other than 0 of an MPI job: rank 0 says the warnings
  app.add_option("--log", log_level, "log level")
      ->check(CLI::IsMember({"debug", "info", "warn", "error", "off"}));
  app.parse_complete_callback([&] {
    using illum::log::Level;
    const Level level = log_level == "debug"   ? Level::kDebug
                        : log_level == "info"  ? Level::kInfo
                        : log_level == "warn"  ? Level::kWarn
                        : log_level == "error" ? Level::kError
                                               : Level::kOff;
    illum::log::set_level(other_rank && level < Level::kError ? Level::kError : level);
    if (job && job->rank() == 0)
      illum::log::info("distributed: {} ranks, {} on this node, {} threads per rank by default",
                       job->ranks(), job->ranks_on_node(), job->threads_per_rank());
  });

  illum::cli::add_info_command(app);
  illum::cli::add_render_command(app);
  illum::cli::add_bake_command(app);
  illum::cli::add_relight_command(app);
  illum::cli::add_export_command(app);
#ifdef ILLUM_HAVE_FRAME_COMMAND
  illum::cli::add_frame_command(app);
#endif
#ifdef ILLUM_HAVE_VIEW_COMMAND
  illum::cli::add_view_command(app);
#endif
  illum::cli::refuse_empty_values(app);
  // Only render and bake split their work across MPI ranks; the others would each write
  // the same files at once.
  for (CLI::App* command : app.get_subcommands({}))
    if (command->get_name() != "render" && command->get_name() != "bake" &&
        command->get_name() != "info")
      command->preparse_callback([name = command->get_name()](size_t) {
        illum::cli::refuse_with_several_ranks(true, "illum " + name,
                                              "only render and bake are split across ranks");
      });

  illum::install_interrupt_handler();
  // Under mpirun (and only there: see distributed/README.md) the process is one rank of a
  // job; render and bake split their work across the ranks, and rank 0 writes the output.
  std::unique_ptr<illum::ScopedWorkSplit> installed;
  if (illum::distributed::launched_by_mpi_launcher()) {
    try {
      job = std::make_unique<illum::distributed::MpiJob>(&argc, &argv);
    } catch (const illum::Error& e) {
      std::fprintf(stderr, "illum: error: %s\n", e.what());
      return 2;
    }
    installed = std::make_unique<illum::ScopedWorkSplit>(job.get());
  }
  const bool root = !job || job->rank() == 0;
  other_rank = !root;
  // Warnings wait until a command has checked its input and starts its work
  // (log::release() there): a run refused for bad input prints only its one error line.
  illum::log::hold();
  int code = 0;
  std::string message;  // the one line for stderr, if any
  try {
    if (job) job->check_settings();
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    if (!root) return 0;
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    if (!root) return 0;
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    if (!root) return 0;
    return app.exit(e);
  } catch (const illum::Interrupted&) {
    illum::log::discard();
    code = 130;
    // Under mpirun a SIGTERM is the launcher ending the job: Ctrl-C given to mpirun, or
    // another rank that died (mpirun names it).
    if (root) {
      const int signal = illum::interrupt_signal();
      if (signal == SIGTERM && job)
        message =
            "illum: stopped by SIGTERM (under mpirun: Ctrl-C, or another rank failed); nothing "
            "was written";
      else if (signal == SIGTERM || signal == SIGHUP)
        message = fmt::format("illum: stopped by {}; nothing was written",
                              signal == SIGTERM ? "SIGTERM" : "SIGHUP");
      else
        message = "illum: interrupted; nothing was written";
    }
  } catch (const CLI::ParseError& e) {
    illum::log::discard();
    code = 2;
    message = fmt::format("illum: error: {} (see 'illum --help')", e.what());
  } catch (const illum::Error& e) {
    illum::log::discard();
    code = 2;
    message = fmt::format("illum: error: {}", e.what());
  } catch (const illum::InternalError& e) {
    illum::log::release();  // a bug: everything that led to it helps the report
    code = 3;
    message = fmt::format("illum: {} — please report this bug", e.what());
  } catch (const std::bad_alloc&) {
    illum::log::discard();
    code = 2;
    message = "illum: error: out of memory";
  } catch (const std::exception& e) {
    illum::log::release();
    code = 1;
    message = fmt::format("illum: error: {}", e.what());
  }
  // Several ranks end together (distributed/README.md "Failure"): they agree on the exit
  // code, and rank 0 alone prints the first failing rank's line.
  if (job && job->ranks() > 1) {
    if (code == 0) illum::log::release();
    return job->finish(code, message);
  }
  if (code != 0) {
    if (!message.empty()) std::fprintf(stderr, "%s\n", message.c_str());
    return code;
  }
  illum::log::release();
  return 0;
}
