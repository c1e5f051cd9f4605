#include "illum/core/error.h"

namespace illum {

Error::Error(std::string message, std::source_location where)
    : std::runtime_error(std::move(message)), where_(where) {}

void check_failed(const char* expr, const std::string& message, std::source_location where) {
  throw InternalError(fmt::format("internal check failed: {} ({}) at {}:{}", expr, message,
                                  where.file_name(), where.line()));
}

}  // namespace illum
