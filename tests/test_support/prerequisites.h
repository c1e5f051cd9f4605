// What a test needs from outside the checkout: the shared scenes (ILLUM_SHARED_SCENES,
// ../shared/scenes beside the checkout) and programs on PATH (xvfb-run, xdotool). Outside CI
// a missing prerequisite skips the test and says what is missing; under CI (environment
// CI=true, which .ci/run sets) it fails the test, so CI never passes by skipping.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace illum::test {

// CI=true (or 1), as .ci/run and the common CI services set it.
inline bool in_ci() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && (std::string(ci) == "true" || std::string(ci) == "1");
}

// `relative` inside the shared scenes folder, e.g. "sibenik/sibenik.obj".
inline std::string shared_scene(const std::string& relative) {
  // Appended in place: GCC 12 at -O1 warns (-Warray-bounds, a false positive in libstdc++'s
  // inlined copy) on the `string + "/" + relative` chain once the headers come precompiled.
  std::string path = ILLUM_SHARED_SCENES;
  path += '/';
  path += relative;
  return path;
}

inline bool on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  std::error_code ec;
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (!dir.empty() && std::filesystem::exists(std::filesystem::path(dir) / program, ec))
      return true;
  return false;
}

}  // namespace illum::test

// Skips (outside CI) or fails (CI=true) the running test unless `condition` holds; `what`
// names the prerequisite. Use it in a TEST body or a fixture's SetUp(): it returns from there.
#define ILLUM_REQUIRE(condition, what)                                              \
  do {                                                                              \
    if (!(condition)) {                                                             \
      if (::illum::test::in_ci()) {                                                 \
        FAIL() << "CI=true but " << (what) << " is missing; CI must provide it";    \
      } else {                                                                      \
        GTEST_SKIP() << (what) << " is missing; skipped (with CI=true this fails)"; \
      }                                                                             \
    }                                                                               \
  } while (0)

// A file of the shared scenes, e.g. ILLUM_REQUIRE_SHARED_SCENE("sibenik/sibenik.obj").
#define ILLUM_REQUIRE_SHARED_SCENE(relative)                                             \
  ILLUM_REQUIRE(std::filesystem::is_regular_file(::illum::test::shared_scene(relative)), \
                "shared scene file " + ::illum::test::shared_scene(relative))

// A program on PATH that scripts/install-deps.sh installs, e.g. ILLUM_REQUIRE_PROGRAM("xdotool").
#define ILLUM_REQUIRE_PROGRAM(name)           \
  ILLUM_REQUIRE(::illum::test::on_path(name), \
                std::string("program '") + (name) + "' on PATH (scripts/install-deps.sh)")
