#!/bin/bash
# Real-time frame timings: `illum frame` over the technique/shadow combinations of the
# real-time renderer, one JSON per combination (per-pass GPU ms from timestamp queries,
# median over FRAMES after WARMUP), then a summary table. Meant for a GPU machine; on
# lavapipe use small FRAMES and sizes (ctest illum_bench.realtime_frames_smoke runs every row
# at 32×32 with validation on).
#
#   bench/scripts/realtime_frames.sh ILLUM [OUTDIR [SCENE]] [-- extra illum frame options]
#   FRAMES=200 WARMUP=20 WIDTH=1920 HEIGHT=1080 LIGHTMAP=folder   (environment, defaults shown)
#
# Build first: `cmake --build build/ci --target illum`. OUTDIR defaults to
# ${TMPDIR:-/tmp}/illum-bench/realtime-frames, SCENE to sibenik. LIGHTMAP names an `illum
# bake` folder (e.g. `illum bake sibenik -o sib-lm --resolution 1024 --spp 2 --content
# indirect`, made here and bundled). On the GPU machine (bundle: device-setup.sh), from the
# repository root:
#   source bench/scripts/device-setup.sh
#   bench/scripts/realtime_frames.sh .device/bin/illum "$OUT/frames"
#
# Rows: forward/deferred × map/vsm/volume, volume with CPU silhouettes, deferred with cached
# shadow maps and with light volumes, and (when LIGHTMAP names an `illum bake` folder)
# deferred + map over that light-map. Exit 2 on bad arguments.
set -euo pipefail
positional=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do positional+=("$1"); shift; done
[ "${1:-}" = "--" ] && shift
if [ ${#positional[@]} -lt 1 ] || [ ${#positional[@]} -gt 3 ]; then
  echo "usage: $0 ILLUM [OUTDIR [SCENE]] [-- illum frame options]" >&2
  exit 2
fi
illum=${positional[0]} out=${positional[1]:-${TMPDIR:-/tmp}/illum-bench/realtime-frames}
scene=${positional[2]:-sibenik}
[ -x "$illum" ] || { echo "$0: $illum is not an executable" >&2; exit 2; }
mkdir -p "$out"
size=(--width "${WIDTH:-1920}" --height "${HEIGHT:-1080}" --frames "${FRAMES:-200}" --warmup "${WARMUP:-20}")

run() {
  local name=$1
  shift
  "$illum" frame "$scene" "${size[@]}" "$@" --json "$out/$name.json" "${extra[@]}" > "$out/$name.txt"
}
extra=("$@")
run forward-map --technique forward --shadows map
run forward-vsm --technique forward --shadows vsm
run forward-volume --technique forward --shadows volume
run forward-volume-cpu --technique forward --shadows volume -p silhouettes=cpu
run deferred-map --technique deferred --shadows map
run deferred-vsm --technique deferred --shadows vsm
run deferred-volume --technique deferred --shadows volume
run deferred-map-cached --technique deferred --shadows map -p shadow_update_period=0
run deferred-map-light-volumes --technique deferred --shadows map -p deferred_lighting=volumes
if [ -n "${LIGHTMAP:-}" ]; then
  run deferred-map-lightmap --technique deferred --shadows map --baked "$LIGHTMAP"
fi

printf '%-28s %12s %12s  %s\n' run "GPU ms" "wall ms" "passes (median GPU ms)"
for f in "$out"/*.json; do
  python3 - "$f" <<'PY'
import json, os, sys
d = json.load(open(sys.argv[1]))
passes = ", ".join(f"{p['name']} {p['median_ms']:.3f}" for p in d["passes"])
name = os.path.basename(sys.argv[1])[:-5]
print(f"{name:<28} {d['frame_gpu_median_ms']:12.3f} {d['frame_wall_median_ms']:12.3f}  {passes}"
      f"  [{d['device']}, {d['validation_messages']} validation messages]")
PY
done
