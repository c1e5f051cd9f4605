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

int main(int argc, char** argv) {
  std::string log_level = "warn";
  const std::unique_ptr<CLI::App> app_owner = illum::cli::build_app(&log_level);
  CLI::App& app = *app_owner;
  std::unique_ptr<illum::distributed::MpiJob> job;  // under mpirun only
  bool other_rank = false;  // a rank other than 0 of an MPI job: rank 0 says the warnings
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
  } catch (const CLI::ExtrasError& e) {
    illum::log::discard();
    code = 2;
    const std::vector<std::string> extras = app.remaining();
    const std::string unknown =
        extras.empty() ? "" : illum::cli::unknown_option_message(app, extras.front());
    message = unknown.empty() ? fmt::format("illum: error: {} (see 'illum --help')", e.what())
                              : "illum: error: " + unknown;
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
