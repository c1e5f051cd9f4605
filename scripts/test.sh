#!/usr/bin/env bash
# Builds illum with warnings as errors and runs the test suite (everything but `slow`).
# This is the README's second command and what CI runs.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/install-deps.sh"
cd "$root"
cmake --preset ci >/dev/null
cmake --build --preset ci -j"$(nproc)"
ctest --preset ci
