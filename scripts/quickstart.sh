#!/usr/bin/env bash
# Quick start: installs the Debian packages, builds illum (Release) and path-traces the
# built-in Cornell box to cornell.png in the current folder.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/install-deps.sh"
cmake --preset release -S "$root" >/dev/null
cmake --build "$root/build/release" -j"$(nproc)"
"$root/build/release/bin/illum" render cornell --integrator path --spp 64 -o cornell.png
echo "quickstart: wrote $(pwd)/cornell.png"
