// illum-bench: end-to-end benchmarks. `illum-bench SUITE [options]`; see bench/README.md.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "illum/core/error.h"
#include "illum/core/log.h"
#include "suites.h"

namespace {

void print_usage(std::FILE* out) {
  std::fputs(
      "usage: illum-bench SUITE [options]   (illum-bench SUITE --help for its options)\n"
      "suites:\n",
      out);
  for (const illum::bench::Suite& s : illum::bench::suites())
    std::fprintf(out, "  %-10s %s\n", s.name, s.summary);
}

}  // namespace

int main(int argc, char** argv) {
  // Warnings and errors only, the illum program's default level.
  illum::log::set_level(illum::log::Level::kWarn);
  if (argc < 2) {
    std::fputs("illum-bench: missing suite name (illum-bench --help lists them)\n", stderr);
    return 2;
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    print_usage(stdout);
    return 0;
  }
  const std::vector<std::string> args(argv + 2, argv + argc);
  try {
    for (const illum::bench::Suite& s : illum::bench::suites())
      if (name == s.name) return s.run(args);
    std::string names;
    for (const illum::bench::Suite& s : illum::bench::suites())
      names += (names.empty() ? "" : ", ") + std::string(s.name);
    throw illum::Error(fmt::format("unknown suite '{}' (suites: {})", name, names));
  } catch (const illum::Error& e) {
    std::fprintf(stderr, "illum-bench: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "illum-bench: internal error: %s\n", e.what());
    return 1;
  }
}
