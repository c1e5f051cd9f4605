#!/usr/bin/env bash
# Loads an `illum export` .glb in three.js (headless Chromium) with illum's light-map plugin
# and compares the frame with `illum frame` of the same file. README.md beside this file.
#
#   scripts/engine-check/run.sh SCENE.glb OUTDIR [WIDTH HEIGHT]
#
# Writes OUTDIR/illum.exr, illum.png (illum frame), three.png (three.js) and metrics.json;
# prints the per-channel errors. Exit 0 when each channel's mean relative error is within
# BOUND (default 0.005), 1 when not or when a step fails, 2 on bad arguments.
# Environment: ILLUM (default build/ci/bin/illum), CHROMIUM (default /usr/bin/chromium),
# BOUND, LIGHTMAP=off (three.js without the plugin: the check must then fail).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
illum=${ILLUM:-$here/../../build/ci/bin/illum}
chromium=${CHROMIUM:-/usr/bin/chromium}
bound=${BOUND:-0.005}
if [[ $# -ne 2 && $# -ne 4 ]]; then
  echo "usage: $0 SCENE.glb OUTDIR [WIDTH HEIGHT]" >&2
  exit 2
fi
glb=$1 out=$2 width=${3:-128} height=${4:-128}
[[ -f $glb ]] || { echo "$0: $glb: no such file" >&2; exit 2; }
[[ -d $out ]] || { echo "$0: $out: no such folder" >&2; exit 2; }
[[ $width =~ ^[1-9][0-9]*$ && $height =~ ^[1-9][0-9]*$ ]] ||
  { echo "$0: WIDTH and HEIGHT must be positive integers" >&2; exit 2; }
[[ -x $illum ]] || { echo "$0: $illum is not an executable (set ILLUM)" >&2; exit 2; }
[[ -x $chromium ]] || { echo "$0: $chromium missing (scripts/install-deps.sh --engine-check)" >&2; exit 2; }
command -v npm > /dev/null || { echo "$0: npm missing (scripts/install-deps.sh --engine-check)" >&2; exit 2; }

work=$(mktemp -d "${TMPDIR:-/tmp}/illum-engine-check.XXXXXX")
trap 'rm -rf "$work"' EXIT
cp "$here"/package.json "$here"/package-lock.json "$here"/render.mjs "$here"/page.html \
  "$here"/illum-lightmap.js "$work"/
(cd "$work" && nice -n 10 npm ci --no-audit --no-fund --loglevel=error) >&2

"$illum" frame "$glb" --width "$width" --height "$height" -o "$out/illum.exr" > /dev/null
"$illum" frame "$glb" --width "$width" --height "$height" --tonemap clamp --fixed-exposure \
  -o "$out/illum.png" > /dev/null
status=0
nice -n 10 node "$work/render.mjs" --glb "$glb" --exr "$out/illum.exr" --out "$out" \
  --width "$width" --height "$height" --chromium "$chromium" --bound "$bound" \
  --lightmap "${LIGHTMAP:-on}" > "$out/metrics.json" || status=$?
cat "$out/metrics.json"
exit "$status"
