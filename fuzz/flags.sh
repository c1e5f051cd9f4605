# Sourced by fuzz/run_ctest.sh (CI) and scripts/fuzz.sh (long runs): the flags every fuzz run
# uses. Inputs are at most 64 KiB; one input running past 10 s (a hang), the process passing
# 2 GiB resident, or a single allocation above 1 GiB (memory out of proportion to the input)
# is a finding, like a crash or a sanitizer report.
illum_fuzz_flags=(-timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 -max_len=65536)
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
# Symbolized stacks in reports (llvm-16 matches the clang-16 that builds the asan tree).
export ASAN_SYMBOLIZER_PATH=${ASAN_SYMBOLIZER_PATH:-/usr/lib/llvm-16/bin/llvm-symbolizer}
