// JSON that users hand to illum (scene files, glTF, --param values). Two dangers are closed
// here, before and around the parser: nesting depth is checked on the raw text (a value
// nested a million levels deep would exhaust the stack in any code that walks or copies the
// tree recursively: nlohmann's copy and dump, tinygltf's extension reader), and every parser
// exception (a syntax error, a number beyond the range of a double) becomes an illum::Error
// naming the origin, so no raw library message or exit code reaches the user.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace illum {

// Deepest nesting of arrays and objects illum accepts in any JSON it reads. Real files stay
// far below it: a glTF needs about 8 levels (a few more inside "extras"), a scene file 5.
inline constexpr int kMaxJsonDepth = 128;

// Throws Error "<origin>: JSON nested deeper than 128 levels (line L, column C)" at the first
// bracket past `max_depth`. Brackets inside strings and comments do not count; everything
// else about the syntax is left to the parser.
void check_json_nesting(std::string_view text, const std::string& origin,
                        int max_depth = kMaxJsonDepth);

// check_json_nesting, then parse. A syntax error throws Error "<origin>: malformed JSON: parse
// error at line L, column C: ..."; a number a double cannot hold (1e400) throws "<origin>:
// number 1e400 is out of range (line L, column C)". `allow_comments` accepts // and /* */.
nlohmann::json parse_json(std::string_view text, const std::string& origin,
                          bool allow_comments = false);

// The whole file as bytes; Error "<path>: cannot open file" / "cannot read file".
std::string read_file_bytes(const std::string& path);

// Reads the whole file (read_file_bytes) and parses it with parse_json.
nlohmann::json read_json_file(const std::string& path, bool allow_comments = false);

}  // namespace illum
