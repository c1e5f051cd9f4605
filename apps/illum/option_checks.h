// Strict checks of the values given to `illum`'s options.
//
// CLI11 (2.1) reads integers with strtoull/strtoll in base 0 and floats with strtold, and
// turns an empty value into 0: `--seed -1` wraps to 2^64 − 1 on an unsigned option,
// `--width 010` is octal 8, `--seed ""` is 0, `--exposure nan` and `--exposure inf` pass,
// and `--exposure 1e99` becomes inf in a float. Every numeric option is therefore
// registered with `->transform(number<T>(lo, hi))`, which refuses each of these with a
// message naming the option (CLI11 prefixes it) and hands CLI11 the value in plain decimal;
// `refuse_empty_values` adds the empty-value check to every option that takes a value.
// tests/cli/cli_options_test.cpp tries every numeric option listed by `illum SUB --help`.
#pragma once

#include <cfloat>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "illum/core/error.h"

namespace illum::cli {

// A decimal number of type T in [lo, hi]: not empty, no sign on an unsigned type, nothing
// after the number, finite, not overflowing T. (A Validator subclass, as CLI::Range is.)
template <typename T>
class Number : public CLI::Validator {
 public:
  static_assert(std::is_arithmetic_v<T>);
  Number(T lo, T hi) : CLI::Validator(range_text(lo, hi)) {
    name_ = "number";
    func_ = [lo, hi](std::string& text) -> std::string {
      if (text.empty()) return "needs a value";
      const char* kind = std::is_floating_point_v<T> ? "a number"
                         : std::is_signed_v<T>       ? "an integer"
                                                     : "a non-negative integer";
      T value{};
      const char* last = text.data() + text.size();
      std::from_chars_result r;
      if constexpr (std::is_floating_point_v<T>)
        r = std::from_chars(text.data(), last, value, std::chars_format::general);
      else
        r = std::from_chars(text.data(), last, value, 10);
      if (r.ec == std::errc::result_out_of_range && r.ptr == last)
        return fmt::format("'{}' is out of range ({})", text, range_text(lo, hi));
      if (r.ec != std::errc() || r.ptr != last) return fmt::format("'{}' is not {}", text, kind);
      if constexpr (std::is_floating_point_v<T>) {
        if (!std::isfinite(value)) return fmt::format("'{}' is not a finite number", text);
      }
      if (value < lo || value > hi) return fmt::format("{} is not {}", text, range_text(lo, hi));
      // What CLI11 converts next: plain decimal, so a leading 0 is not read as octal.
      if constexpr (std::is_integral_v<T>) text = std::to_string(value);
      return {};
    };
  }

 private:
  // "in [lo, hi]", or "at least lo" when hi is the type's largest value or a guard past any
  // real value (one printed as 1e+30); a float bound of the smallest normal number reads
  // "positive" (help shows no internal limits).
  static std::string range_text(T lo, T hi) {
    const bool positive = std::is_floating_point_v<T> && lo == std::numeric_limits<T>::min();
    const std::string low = positive ? "positive" : fmt::format("at least {}", lo);
    if (hi == std::numeric_limits<T>::max() || fmt::format("{}", hi).find('e') != std::string::npos)
      return low;
    return positive ? fmt::format("positive, at most {}", hi) : fmt::format("in [{}, {}]", lo, hi);
  }
};

template <typename T>
Number<T> number(T lo, T hi) {
  return Number<T>(lo, hi);
}

// Every option that takes a value, of `app` and of each of its subcommands, refuses an
// empty one (`--baked ""` would otherwise mean "none", `--seed ""` 0).
inline void refuse_empty_values(CLI::App& app) {
  const CLI::Validator non_empty(
      [](std::string& text) { return text.empty() ? std::string("needs a value") : ""; }, "",
      "non-empty");
  for (CLI::Option* option : app.get_options())
    if (option->get_expected_min() > 0) option->check(non_empty);
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
    refuse_empty_values(*sub);
}

// A --param key that a dedicated option sets would be overwritten by it without a word:
// refused, naming the option to use. `keys` pairs each such key with its option.
inline void refuse_params_of_options(
    const nlohmann::json& params, std::initializer_list<std::pair<const char*, const char*>> keys) {
  for (const auto& [key, option] : keys)
    if (params.contains(key))
      throw Error(fmt::format("--param {}: set it with {} instead", key, option));
}

}  // namespace illum::cli
