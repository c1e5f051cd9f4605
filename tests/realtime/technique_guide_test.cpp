// docs/realtime-techniques.md shows the worked example's code as excerpts: each fenced block
// after a line `<!-- excerpt: PATH -->` must appear, verbatim, in PATH (relative to the
// source tree), so the guide cannot drift from the code it teaches.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

namespace {

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(TechniqueGuide, ExcerptsAreTheSourceFiles) {
  const std::string root = ILLUM_SOURCE_DIR;
  const std::string guide = read(root + "/docs/realtime-techniques.md");
  ASSERT_FALSE(guide.empty()) << "docs/realtime-techniques.md not found";
  const std::string marker = "<!-- excerpt: ";
  int excerpts = 0;
  for (size_t at = guide.find(marker); at != std::string::npos; at = guide.find(marker, at + 1)) {
    const size_t path_end = guide.find(" -->", at);
    ASSERT_NE(path_end, std::string::npos);
    const std::string path = guide.substr(at + marker.size(), path_end - at - marker.size());
    const size_t open = guide.find("```", path_end);
    const size_t body = guide.find('\n', open) + 1;
    const size_t close = guide.find("\n```", body);
    ASSERT_NE(close, std::string::npos) << path << ": unclosed block";
    const std::string block = guide.substr(body, close + 1 - body);
    const std::string source = read(root + "/" + path);
    ASSERT_FALSE(source.empty()) << path << " not found";
    EXPECT_NE(source.find(block), std::string::npos)
        << "the excerpt of " << path << " is not in the file:\n"
        << block;
    ++excerpts;
  }
  EXPECT_GE(excerpts, 4);
}

}  // namespace
