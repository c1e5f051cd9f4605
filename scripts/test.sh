#!/usr/bin/env bash
# Builds illum and runs the test suite twice: the `ci` preset (release, warnings as errors,
# everything but `slow`), then the `asan` preset (clang, AddressSanitizer + UBSan, GPU layers
# and benchmarks off, with the fuzz harnesses) running everything but `gpu` and `slow`,
# including the fuzz targets' corpus replays and short sessions (label fuzz). The benchmarks'
# smoke tests run in the `ci` pass only: building illum-bench a second time under the
# sanitizers cost about a third of that build, minutes of CI on 2 cores. This is the README's second command
# and what CI runs (.ci/run, with CI=true). It does not set CI itself: run locally without
# ../shared/scenes, the tests that need them skip and say so.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/install-deps.sh"
cd "$root"
jobs=$(nproc)
echo "== ci: release build, warnings are errors"
cmake --preset ci >/dev/null
cmake --build --preset ci -j"$jobs"
ctest --preset ci
echo "== asan: AddressSanitizer + UBSan build (no GPU layers), tests but gpu and slow, fuzz targets"
cmake --preset asan >/dev/null
cmake --build --preset asan -j"$jobs"
ctest --preset asan
