#!/usr/bin/env bash
# The ctest `EngineCheck.ThreeJsShowsTheExportedLightmap` (label `engine`, outside the presets:
# it needs Chromium and the npm registry). Bakes and exports the Cornell box, then run.sh must
# pass with illum's plugin and fail without it (three.js alone does not show the light-map).
#
#   scripts/engine-check/ctest.sh ILLUM
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
illum=${1:?usage: ctest.sh ILLUM}
work=$(mktemp -d "${TMPDIR:-/tmp}/illum-engine-ctest.XXXXXX")
trap 'rm -rf "$work"' EXIT
"$illum" bake cornell --resolution 64 --spp 16 --seed 1 -o "$work/lm" > /dev/null
"$illum" export cornell --baked "$work/lm" -o "$work/cornell.glb" > /dev/null
mkdir "$work/with" "$work/without"
ILLUM=$illum "$here/run.sh" "$work/cornell.glb" "$work/with" 128 128
if ILLUM=$illum LIGHTMAP=off "$here/run.sh" "$work/cornell.glb" "$work/without" 128 128 > /dev/null; then
  echo "ctest.sh: three.js without the plugin passed the check: the check cannot fail" >&2
  exit 1
fi
echo "ctest.sh: with the plugin within the bound, without it outside"
