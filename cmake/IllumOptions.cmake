# One INTERFACE target carries the project's warnings and compile options; every illum
# target links it PRIVATE so the flags never leak to consumers.
add_library(illum_options INTERFACE)
add_library(illum::options ALIAS illum_options)
target_compile_features(illum_options INTERFACE cxx_std_20)
target_compile_options(illum_options INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align -Woverloaded-virtual
  -Wnull-dereference -Wimplicit-fallthrough
  $<$<BOOL:${ILLUM_WERROR}>:-Werror>)
target_include_directories(illum_options INTERFACE ${PROJECT_SOURCE_DIR}/src)

# The fuzz harnesses (fuzz/) need libFuzzer, which only clang has. Their libraries get
# libFuzzer's coverage instrumentation (without its main) so the fuzzer sees illum's branches.
if(ILLUM_BUILD_FUZZ AND NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "ILLUM_BUILD_FUZZ needs clang (the asan preset uses it); "
                      "CMAKE_CXX_COMPILER is ${CMAKE_CXX_COMPILER_ID}")
endif()
# Options of every layer object beyond illum::options; the layers' shared precompiled header
# is built with them too, or it would not fit the objects that reuse it.
set(ILLUM_LAYER_COMPILE_OPTIONS "")
if(ILLUM_BUILD_FUZZ)
  list(APPEND ILLUM_LAYER_COMPILE_OPTIONS -fsanitize=fuzzer-no-link)
endif()

# Where the project's own data (built-in scenes) lives, for lookups without a path.
set(ILLUM_DATA_DIR "${PROJECT_SOURCE_DIR}/data" CACHE PATH "illum data folder")
# The shared test scenes beside the checkout (../shared/scenes), used by tests and benchmarks.
get_filename_component(_illum_shared "${PROJECT_SOURCE_DIR}/../shared/scenes" ABSOLUTE)
set(ILLUM_SHARED_SCENES "${_illum_shared}" CACHE PATH "shared test scenes folder")

# Headers nearly every object of a layer parses: the standard ones and those of core's public
# dependencies (illum/core/params.h alone brings in nlohmann/json). One precompiled header,
# built once (≈ 11 s) with the macros and options every layer shares, is reused by all layers,
# as the test programs share theirs (tests/CMakeLists.txt). A layer may add macros of its own
# (scene, distributed): clang refuses a header only for macros it has and the object lacks or
# defines differently. Parsing these headers was about a third of an object's compile.
set(ILLUM_LAYER_PCH_HEADERS
  <algorithm> <array> <atomic> <chrono> <cmath> <cstdint> <cstdio> <cstring> <filesystem>
  <fstream> <functional> <limits> <map> <memory> <optional> <set> <span> <string>
  <string_view> <unordered_map> <utility> <vector>
  <fmt/format.h> <glm/glm.hpp> <nlohmann/json.hpp> <spdlog/spdlog.h> <tbb/parallel_for.h>)

# illum_layer(NAME SOURCES... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Creates target illum_NAME with alias illum::NAME: one target per folder under src/illum.
function(illum_layer name)
  cmake_parse_arguments(L "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  if(NOT L_SOURCES)  # header-only layer
    add_library(illum_${name} INTERFACE)
    add_library(illum::${name} ALIAS illum_${name})
    target_include_directories(illum_${name} INTERFACE ${PROJECT_SOURCE_DIR}/src)
    target_link_libraries(illum_${name} INTERFACE ${L_PUBLIC_DEPS})
    return()
  endif()
  add_library(illum_${name} STATIC ${L_SOURCES})
  add_library(illum::${name} ALIAS illum_${name})
  target_include_directories(illum_${name} PUBLIC ${PROJECT_SOURCE_DIR}/src)
  target_link_libraries(illum_${name} PUBLIC ${L_PUBLIC_DEPS} PRIVATE illum::options ${L_PRIVATE_DEPS})
  set_target_properties(illum_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  if(NOT TARGET illum_layer_pch)
    add_library(illum_layer_pch OBJECT ${PROJECT_SOURCE_DIR}/cmake/layer_pch_anchor.cpp)
    target_link_libraries(illum_layer_pch PRIVATE illum::options glm::glm TBB::tbb spdlog::spdlog
                                                  fmt::fmt nlohmann_json::nlohmann_json)
    set_target_properties(illum_layer_pch PROPERTIES POSITION_INDEPENDENT_CODE ON)
    target_compile_options(illum_layer_pch PRIVATE ${ILLUM_LAYER_COMPILE_OPTIONS})
    target_precompile_headers(illum_layer_pch PRIVATE ${ILLUM_LAYER_PCH_HEADERS})
  endif()
  target_precompile_headers(illum_${name} REUSE_FROM illum_layer_pch)
  target_compile_options(illum_${name} PRIVATE ${ILLUM_LAYER_COMPILE_OPTIONS})
endfunction()
