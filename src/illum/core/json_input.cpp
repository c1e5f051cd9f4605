#include "illum/core/json_input.h"

#include <fstream>

#include "illum/core/error.h"

namespace illum {

namespace {

struct TextPosition {
  size_t line = 1, column = 1;
};

TextPosition position_of(std::string_view text, size_t offset) {
  TextPosition p;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++p.line;
      p.column = 1;
    } else {
      ++p.column;
    }
  }
  return p;
}

// A SAX consumer that builds nothing and remembers where the parser gave up: run only after
// a parse failed, to place errors whose messages carry no position (number overflow).
class ErrorLocator : public nlohmann::json_sax<nlohmann::json> {
 public:
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override { return true; }
  bool key(string_t&) override { return true; }
  bool end_object() override { return true; }
  bool start_array(std::size_t) override { return true; }
  bool end_array() override { return true; }
  bool parse_error(std::size_t position, const std::string& token,
                   const nlohmann::detail::exception&) override {
    position_ = position;
    token_ = token;
    return false;
  }
  size_t position() const { return position_; }
  const std::string& token() const { return token_; }

 private:
  size_t position_ = 0;
  std::string token_;
};

// nlohmann's messages start with "[json.exception.parse_error.101] "; the user needs the rest.
std::string without_exception_tag(const std::string& what) {
  const auto pos = what.find("] ");
  return pos == std::string::npos ? what : what.substr(pos + 2);
}

}  // namespace

void check_json_nesting(std::string_view text, const std::string& origin, int max_depth) {
  int depth = 0;
  const size_t n = text.size();
  for (size_t i = 0; i < n; ++i) {
    const char c = text[i];
    if (c == '"') {
      for (++i; i < n && text[i] != '"'; ++i) {
        if (text[i] == '\\') ++i;  // the escaped character cannot end the string
      }
    } else if (c == '/' && i + 1 < n && text[i + 1] == '/') {
      while (i < n && text[i] != '\n') ++i;
    } else if (c == '/' && i + 1 < n && text[i + 1] == '*') {
      const size_t end = text.find("*/", i + 2);
      i = end == std::string_view::npos ? n : end + 1;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) {
        const TextPosition p = position_of(text, i);
        throw Error(fmt::format("{}: JSON nested deeper than {} levels (line {}, column {})",
                                origin, max_depth, p.line, p.column));
      }
    } else if (c == ']' || c == '}') {
      --depth;  // unbalanced closers are the parser's to report
    }
  }
}

nlohmann::json parse_json(std::string_view text, const std::string& origin, bool allow_comments) {
  check_json_nesting(text, origin);
  try {
    return nlohmann::json::parse(text.begin(), text.end(), nullptr, /*allow_exceptions=*/true,
                                 allow_comments);
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(fmt::format("{}: malformed JSON: {}", origin, without_exception_tag(e.what())));
  } catch (const nlohmann::json::exception& e) {
    // Out-of-range numbers (out_of_range.406) and anything else: the message has no position,
    // so a second, building-nothing pass finds where the parser stopped.
    ErrorLocator locator;
    nlohmann::json::sax_parse(text.begin(), text.end(), &locator,
                              nlohmann::json::input_format_t::json,
                              /*strict=*/true, allow_comments);
    if (e.id == 406) {
      // The parser stops right after the number: its start is the token's length back.
      const size_t end = locator.position();
      const size_t size = locator.token().size();
      const TextPosition p = position_of(text, end >= size ? end - size : 0);
      throw Error(fmt::format("{}: number {} is out of range (line {}, column {})", origin,
                              locator.token(), p.line, p.column));
    }
    const TextPosition p = position_of(text, locator.position());
    throw Error(fmt::format("{}: malformed JSON at line {}, column {}: {}", origin, p.line,
                            p.column, without_exception_tag(e.what())));
  }
}

std::string read_file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw Error(fmt::format("{}: cannot open file", path));
  const std::streamoff size = in.tellg();
  if (size < 0) throw Error(fmt::format("{}: cannot read file", path));
  std::string bytes(static_cast<size_t>(size), '\0');
  in.seekg(0);
  if (!in.read(bytes.data(), size)) throw Error(fmt::format("{}: cannot read file", path));
  return bytes;
}

nlohmann::json read_json_file(const std::string& path, bool allow_comments) {
  return parse_json(read_file_bytes(path), path, allow_comments);
}

}  // namespace illum
