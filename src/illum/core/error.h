// Errors: bad user input throws illum::Error (the CLI prints one line and exits 2);
// broken invariants use ILLUM_CHECK (always on) / ILLUM_DCHECK (debug builds only).
#pragma once

#include <source_location>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace illum {

class Error : public std::runtime_error {
 public:
  explicit Error(std::string message, std::source_location where = std::source_location::current());
  // Where in illum's source the error was raised (for logs and debugging; the CLI shows
  // only the message, which must name the user's file/option itself).
  const std::source_location& where() const { return where_; }

 private:
  std::source_location where_;
};

// A broken internal invariant: a bug in illum, not bad input.
class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

[[noreturn]] void check_failed(const char* expr, const std::string& message,
                               std::source_location where);

}  // namespace illum

#define ILLUM_CHECK(cond, ...)                                    \
  do {                                                            \
    if (!(cond)) [[unlikely]]                                     \
      ::illum::check_failed(#cond, ::fmt::format("" __VA_ARGS__), \
                            std::source_location::current());     \
  } while (0)

#ifdef NDEBUG
#define ILLUM_DCHECK(cond, ...) \
  do {                          \
  } while (0)
#else
#define ILLUM_DCHECK(cond, ...) ILLUM_CHECK(cond, __VA_ARGS__)
#endif
