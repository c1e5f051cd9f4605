// Each subcommand of `illum` lives in its own cmd_*.cpp and registers itself on the CLI11
// app through one of these functions (explicit list in main.cpp, no static registration).
// Handlers throw illum::Error for bad input; main() turns that into one line and exit 2.
#pragma once

#include <CLI/CLI.hpp>

namespace illum::cli {

void add_info_command(CLI::App& app);
void add_render_command(CLI::App& app);
#ifdef ILLUM_HAVE_FRAME_COMMAND
void add_frame_command(CLI::App& app);
#endif
#ifdef ILLUM_HAVE_VIEW_COMMAND
void add_view_command(CLI::App& app);
#endif

// Refuses an output path whose folder does not exist or whose extension is not one of the
// image formats, before any long work starts.
void check_output_path(const std::string& path);

}  // namespace illum::cli
