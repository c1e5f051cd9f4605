#include "illum/core/log.h"

#include <spdlog/sinks/stdout_color_sinks.h>

namespace illum::log {
namespace {
// Installed once before main: every illum log line goes to stderr as "illum: [level] msg".
const bool kInstalled = [] {
  auto logger = spdlog::stderr_color_mt("illum");
  logger->set_pattern("illum: [%^%l%$] %v");
  spdlog::set_default_logger(logger);
  return true;
}();
}  // namespace

void set_level(Level level) {
  (void)kInstalled;
  switch (level) {
    case Level::kDebug:
      spdlog::set_level(spdlog::level::debug);
      break;
    case Level::kInfo:
      spdlog::set_level(spdlog::level::info);
      break;
    case Level::kWarn:
      spdlog::set_level(spdlog::level::warn);
      break;
    case Level::kError:
      spdlog::set_level(spdlog::level::err);
      break;
    case Level::kOff:
      spdlog::set_level(spdlog::level::off);
      break;
  }
}

}  // namespace illum::log
