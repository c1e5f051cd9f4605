#!/usr/bin/env bash
# Quick start: installs the Debian packages, builds the `illum` program (Release) and
# path-traces the built-in Cornell box to cornell.png in the current folder.
# Only the `illum` target and the libraries it links are built; the configured tree is the
# full release tree, so `cmake --build build/release` later adds illum-bench and the tests
# (then `ctest --preset slow`).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/install-deps.sh"
cmake --preset release -S "$root" >/dev/null
cmake --build "$root/build/release" --target illum -j"$(nproc)"
"$root/build/release/bin/illum" render cornell --integrator path --spp 64 -o cornell.png
echo "quickstart: wrote $(pwd)/cornell.png"
echo "quickstart: cmake --install build/release --prefix ~/.local puts illum on PATH (~/.local/bin)"
