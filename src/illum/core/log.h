// Logging through spdlog. Messages go to stderr as "illum: [level] message" so stdout stays
// clean for data (JSON).
#pragma once

#include <utility>

#include <spdlog/spdlog.h>

namespace illum::log {

enum class Level { kDebug, kInfo, kWarn, kError, kOff };
void set_level(Level level);

// While the log is held, messages wait in order instead of reaching stderr; release() prints
// them and lets later ones through, discard() drops them (returning how many). The CLI holds
// the log while it checks its input, so a run refused for bad input prints exactly its one
// error line even when loading the scene warned first.
void hold();
void release();
size_t discard();

// illum's logger, created on first use. (A static initializer in log.cpp would be dropped
// from programs that reference nothing else in it, which then printed spdlog's default
// format.)
spdlog::logger& logger();

template <typename... Args>
void debug(spdlog::format_string_t<Args...> format, Args&&... args) {
  logger().debug(format, std::forward<Args>(args)...);
}
template <typename... Args>
void info(spdlog::format_string_t<Args...> format, Args&&... args) {
  logger().info(format, std::forward<Args>(args)...);
}
template <typename... Args>
void warn(spdlog::format_string_t<Args...> format, Args&&... args) {
  logger().warn(format, std::forward<Args>(args)...);
}
template <typename... Args>
void error(spdlog::format_string_t<Args...> format, Args&&... args) {
  logger().error(format, std::forward<Args>(args)...);
}

}  // namespace illum::log
