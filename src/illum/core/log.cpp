#include "illum/core/log.h"

#include <spdlog/sinks/stdout_color_sinks.h>

namespace illum::log {

spdlog::logger& logger() {
  static const std::shared_ptr<spdlog::logger> instance = [] {
    auto created = spdlog::stderr_color_mt("illum");
    created->set_pattern("illum: [%^%l%$] %v");
    spdlog::set_default_logger(created);  // direct spdlog calls print the same way
    return created;
  }();
  return *instance;
}

void set_level(Level level) {
  switch (level) {
    case Level::kDebug:
      logger().set_level(spdlog::level::debug);
      break;
    case Level::kInfo:
      logger().set_level(spdlog::level::info);
      break;
    case Level::kWarn:
      logger().set_level(spdlog::level::warn);
      break;
    case Level::kError:
      logger().set_level(spdlog::level::err);
      break;
    case Level::kOff:
      logger().set_level(spdlog::level::off);
      break;
  }
}

}  // namespace illum::log
