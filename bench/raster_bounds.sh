#!/bin/bash
# Issue 9 (3a) on a GPU: `illum frame --json` over scenes × sizes × frame pipelines × shadow
# schedules (shadow maps re-rendered every frame, and cached: `shadow_update_period=0`, the
# cascades still every frame), then `illum-bench raster` over all of them: each pass beside
# the raster or memory bound measured on the same device.
#
#   bench/raster_bounds.sh ILLUM ILLUM_BENCH OUTDIR
#   SCENES="cornell sibenik" SIZES="960x540 1920x1080 3840x2160" PIPELINES="forward deferred"
#   FRAMES=200 WARMUP=20 REPEATS=50   (environment, defaults shown)
#   PARAMS="-p occlusion_culling=true"  (environment: more `illum frame` arguments, e.g. the
#   occlusion culling switched on; default none)
#
# Writes OUTDIR/SCENE-WxH-PIPELINE-{every,cached}.{json,txt}, OUTDIR/raster.{json,txt}.
# Exit 2 on bad arguments.
set -euo pipefail
if [ $# -ne 3 ]; then
  echo "usage: $0 ILLUM ILLUM_BENCH OUTDIR" >&2
  exit 2
fi
illum=$1 bench=$2 out=$3
[ -x "$illum" ] || { echo "$0: $illum is not an executable" >&2; exit 2; }
[ -x "$bench" ] || { echo "$0: $bench is not an executable" >&2; exit 2; }
mkdir -p "$out"
for scene in ${SCENES:-cornell sibenik}; do
  for size in ${SIZES:-960x540 1920x1080 3840x2160}; do
    w=${size%x*} h=${size#*x}
    for pipeline in ${PIPELINES:-forward deferred}; do
      for schedule in every cached; do
        # "every": every shadow map re-rendered each frame; "cached": spot and point maps
        # rendered once (the cascades still every frame).
        extra=(-p shadow_update_period=1)
        [ "$schedule" = cached ] && extra=(-p shadow_update_period=0)
        name="$scene-$size-$pipeline-$schedule"
        # shellcheck disable=SC2086  # PARAMS splits into arguments
        "$illum" frame "$scene" --width "$w" --height "$h" --technique "$pipeline" --shadows map \
          --frames "${FRAMES:-200}" --warmup "${WARMUP:-20}" "${extra[@]}" ${PARAMS:-} \
          --json "$out/$name.json" > "$out/$name.txt"
        echo "$name: $(grep -E '^  frame ' "$out/$name.txt")"
      done
    done
  done
done
"$bench" raster "$out"/*-every.json "$out"/*-cached.json --repeats "${REPEATS:-50}" \
  --json "$out/raster.json" | tee "$out/raster.txt"
