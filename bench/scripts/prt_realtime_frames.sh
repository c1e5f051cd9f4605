#!/bin/bash
# Real-time PRT display timings (bench/results/prt.md, "Real-time display"): one PRT bake of
# SCENE, then `illum frame --baked` in each frame pipeline and each lookup, per-pass GPU ms
# (median over FRAMES after WARMUP) as JSON per row and a summary line per row. Meant for the
# GPU machine; on lavapipe use small FRAMES, sizes and RESOLUTION:
#   FRAMES=2 WARMUP=1 WIDTH=64 HEIGHT=64 RESOLUTION=32 SPP=4 VQ=16 bench/scripts/prt_realtime_frames.sh build/ci/bin/illum "" cornell
#
#   bench/scripts/prt_realtime_frames.sh ILLUM [OUTDIR [SCENE]]
#   FRAMES=200 WARMUP=20 WIDTH=1920 HEIGHT=1080 BANDS=4 RESOLUTION=512 SPP=64 VQ=1024
#
# Build first: `cmake --build build/ci --target illum`. OUTDIR defaults to
# ${TMPDIR:-/tmp}/illum-bench/prt-frames, SCENE to sibenik. The bake runs on the CPU (on the
# GPU machine its 16 cores). There (bundle: device-setup.sh), from the repository root:
#   source bench/scripts/device-setup.sh
#   bench/scripts/prt_realtime_frames.sh .device/bin/illum "$OUT/prt-frames"
#
# Rows: forward/deferred/visibility × texels/vertices/vq, and each pipeline without the bake
# (the scene's own lights, shadows none) for reference. The bake runs on the CPU first.
set -euo pipefail
if [ $# -lt 1 ] || [ $# -gt 3 ]; then
  echo "usage: $0 ILLUM [OUTDIR [SCENE]]" >&2
  exit 2
fi
illum=$1 out=${2:-${TMPDIR:-/tmp}/illum-bench/prt-frames} scene=${3:-sibenik}
[ -x "$illum" ] || { echo "$0: $illum is not an executable" >&2; exit 2; }
mkdir -p "$out"
size=(--width "${WIDTH:-1920}" --height "${HEIGHT:-1080}" --frames "${FRAMES:-200}" --warmup "${WARMUP:-20}")
prt=$out/prt
if [ ! -f "$prt/prt.json" ]; then
  "$illum" bake "$scene" --kind prt --bands "${BANDS:-4}" --resolution "${RESOLUTION:-512}" \
    --spp "${SPP:-64}" --vq "${VQ:-1024}" --seed 1 -o "$prt" 2> "$out/bake.txt"
fi
for pipeline in forward deferred visibility; do
  "$illum" frame "$scene" "${size[@]}" -t "$pipeline" --shadows none \
    --json "$out/$pipeline-none.json" > "$out/$pipeline-none.txt"
  for lookup in texels vertices vq; do
    "$illum" frame "$scene" "${size[@]}" -t "$pipeline" --shadows none --baked "$prt" \
      -p baked.prt_lookup="$lookup" --sun -0.25,-0.866,-0.433 \
      --json "$out/$pipeline-$lookup.json" > "$out/$pipeline-$lookup.txt"
  done
done
for f in "$out"/*.json; do
  printf '%-28s %s\n' "$(basename "$f" .json)" \
    "$(grep -o '"frame_gpu_median_ms": [0-9.e+-]*' "$f" | cut -d' ' -f2) ms (GPU, median)"
done
