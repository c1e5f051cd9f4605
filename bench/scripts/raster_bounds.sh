#!/bin/bash
# The real-time raster matrix on a GPU: `illum frame --json` over scenes × sizes × frame
# pipelines × shadow schedules (shadow maps re-rendered every frame, and cached:
# `shadow_update_period=0`, the cascades still every frame), then `illum-bench raster` over
# all of them: each pass beside the raster, geometry, mixed, quad, memory or shading bound
# measured on the same device (bench/README.md, `raster`). The tables of
# bench/results/raster.md ("H200 frames", "H200 passes and bounds") come from this script.
#
#   bench/scripts/raster_bounds.sh ILLUM ILLUM_BENCH [OUTDIR]
#
# Build first: `cmake --build build/ci --target illum illum-bench` (GPU layer on, the
# default). OUTDIR defaults to ${TMPDIR:-/tmp}/illum-bench/raster.
# Environment (defaults shown):
#   SCENES="sibenik cornell" SIZES="960x540 1920x1080 3840x2160"
#   PIPELINES="visibility deferred forward" FRAMES=200 WARMUP=20 REPEATS=30
#   PARAMS=""          more `illum frame` arguments, e.g. "-p occlusion_culling=true" or
#                      "-p map.resolution=1024"
#   BASE_ILLUM=PATH    a second `illum` (e.g. the build before a change): the matrix runs with
#                      both into OUTDIR/base and OUTDIR/new, bounded by the same illum-bench,
#                      and OUTDIR/tables.md shows base → new
# Writes OUTDIR/SCENE-WxH-PIPELINE-{every,cached}.{json,txt}, OUTDIR/raster.{json,txt} (the
# bench's JSON and table), OUTDIR/shading.txt (each forward pass beside its shading bound) and
# OUTDIR/tables.md (bench/scripts/raster_tables.py). Exit 2 on bad arguments.
#
# On the GPU machine (bundle: bench/scripts/device-setup.sh says how), from the repository root:
#   source bench/scripts/device-setup.sh
#   bench/scripts/raster_bounds.sh .device/bin/illum .device/bin/illum-bench "$OUT/raster"
# (the whole matrix: about 75 s of device time; with BASE_ILLUM about twice that).
set -euo pipefail
if [ $# -lt 2 ] || [ $# -gt 3 ]; then
  echo "usage: $0 ILLUM ILLUM_BENCH [OUTDIR]" >&2
  exit 2
fi
illum=$1 bench=$2 out=${3:-${TMPDIR:-/tmp}/illum-bench/raster}
here=$(cd "$(dirname "$0")" && pwd)
[ -x "$illum" ] || { echo "$0: $illum is not an executable" >&2; exit 2; }
[ -x "$bench" ] || { echo "$0: $bench is not an executable" >&2; exit 2; }
if [ -n "${BASE_ILLUM:-}" ] && [ ! -x "$BASE_ILLUM" ]; then
  echo "$0: BASE_ILLUM=$BASE_ILLUM is not an executable" >&2
  exit 2
fi

matrix() {  # ILLUM OUTDIR: the frames, then the bench over them
  local illum=$1 out=$2
  mkdir -p "$out"
  for scene in ${SCENES:-sibenik cornell}; do
    for size in ${SIZES:-960x540 1920x1080 3840x2160}; do
      local w=${size%x*} h=${size#*x}
      for pipeline in ${PIPELINES:-visibility deferred forward}; do
        for schedule in every cached; do
          # "every": every shadow map re-rendered each frame; "cached": spot and point maps
          # rendered once (the cascades still every frame).
          local extra=(-p shadow_update_period=1)
          [ "$schedule" = cached ] && extra=(-p shadow_update_period=0)
          local name="$scene-$size-$pipeline-$schedule"
          # shellcheck disable=SC2086  # PARAMS splits into arguments
          "$illum" frame "$scene" --width "$w" --height "$h" --technique "$pipeline" --shadows map \
            --frames "${FRAMES:-200}" --warmup "${WARMUP:-20}" "${extra[@]}" ${PARAMS:-} \
            --json "$out/$name.json" > "$out/$name.txt"
          echo "$name: $(grep -E '^  frame ' "$out/$name.txt")"
        done
      done
    done
  done
  "$bench" raster "$out"/*-every.json "$out"/*-cached.json --repeats "${REPEATS:-30}" \
    --json "$out/raster.json" | tee "$out/raster.txt"
  # Each forward pass beside its shading bound, in detail.
  python3 - "$out/raster.json" > "$out/shading.txt" <<'PY'
import json, os, sys
d = json.load(open(sys.argv[1]))
print(f"{d['device']}, driver {d['driver']}; copy {d['copy']['gb_per_s']:.0f} GB/s")
print("frame | forward ms | shading bound ms | ratio | binds | full-screen ms | pixels | lanes/pixel | fixed ms | G-buffer reads ms")
for f in d["frames"]:
    for p in f["passes"]:
        if "shading" in p:
            s = p["shading"]
            print(f"{os.path.basename(f['file'])} | {p['median_ms']:.3f} | {p['shading_bound_ms']:.3f} | "
                  f"{p['ratio']:.2f} | {p['bound']} | {s['full_screen_ms']:.3f} | {s['pixels']:.0f} | "
                  f"{s['lanes_per_pixel']:.3f} | {s['fixed_ms']:.3f} | {s['input_ms']:.4f}")
PY
}

if [ -n "${BASE_ILLUM:-}" ]; then
  matrix "$BASE_ILLUM" "$out/base"
  matrix "$illum" "$out/new"
  python3 "$here/raster_tables.py" "$out/new/raster.json" "$out/base/raster.json" > "$out/tables.md"
else
  matrix "$illum" "$out"
  python3 "$here/raster_tables.py" "$out/raster.json" > "$out/tables.md"
fi
echo "tables: $out/tables.md"
