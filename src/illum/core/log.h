// Logging through spdlog. Messages go to stderr so stdout stays clean for data (JSON).
#pragma once

#include <spdlog/spdlog.h>

namespace illum::log {

enum class Level { kDebug, kInfo, kWarn, kError, kOff };
void set_level(Level level);

using spdlog::debug;
using spdlog::error;
using spdlog::info;
using spdlog::warn;

}  // namespace illum::log
