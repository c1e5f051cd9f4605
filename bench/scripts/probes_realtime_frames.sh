#!/bin/bash
# Real-time timings of the probe volume on dynamic objects (bench/results/probes.md): one
# probe bake of SCENE (default: data/scenes/cornell-dynamic, a ball marked dynamic), then `illum frame`
# in each frame pipeline with the per-pixel lookup (baked.probe_lookup=pixel), with the
# per-instance ambient cube (=instance) and without the probes; per-pass GPU ms as JSON per
# row and the median frame time per row. Meant for the GPU machine; on lavapipe use small
# FRAMES and sizes (ctest illum_bench.probes_realtime_frames_smoke runs every row at 32×32
# with validation on).
#
#   bench/scripts/probes_realtime_frames.sh ILLUM [OUTDIR [SCENE]]
#   FRAMES=200 WARMUP=20 WIDTH=1920 HEIGHT=1080 SPACING=0.05 SPP=64
#
# Build first: `cmake --build build/ci --target illum`. OUTDIR defaults to
# ${TMPDIR:-/tmp}/illum-bench/probes-frames. On the GPU machine (bundle: device-setup.sh), from
# the repository root:
#   source bench/scripts/device-setup.sh
#   bench/scripts/probes_realtime_frames.sh .device/bin/illum "$OUT/probes-frames"
#
# The ball covers about a tenth of a 16:9 frame of cornell-dynamic; the difference between
# the pixel and instance rows is the per-pixel lookup's cost on those pixels (8 probes of 28
# floats each, weights, SH-L2 evaluation), in the pass that writes the ambient term (forward,
# G-buffer, visibility resolve).
set -euo pipefail
if [ $# -lt 1 ] || [ $# -gt 3 ]; then
  echo "usage: $0 ILLUM [OUTDIR [SCENE]]" >&2
  exit 2
fi
illum=$1 out=${2:-${TMPDIR:-/tmp}/illum-bench/probes-frames}
here=$(cd "$(dirname "$0")/../.." && pwd)
scene=${3:-$here/data/scenes/cornell-dynamic/cornell-dynamic.illum.json}
[ -x "$illum" ] || { echo "$0: $illum is not an executable" >&2; exit 2; }
mkdir -p "$out"
size=(--width "${WIDTH:-1920}" --height "${HEIGHT:-1080}" --frames "${FRAMES:-200}" --warmup "${WARMUP:-20}")
probes=$out/probes
if [ ! -f "$probes/probes.json" ]; then
  "$illum" bake "$scene" --kind probes --spacing "${SPACING:-0.05}" --spp "${SPP:-64}" --seed 1 \
    -o "$probes" 2> "$out/bake.txt"
fi
for pipeline in forward deferred visibility; do
  "$illum" frame "$scene" "${size[@]}" -t "$pipeline" --shadows none \
    --json "$out/$pipeline-none.json" > "$out/$pipeline-none.txt"
  for lookup in pixel instance; do
    "$illum" frame "$scene" "${size[@]}" -t "$pipeline" --shadows none --baked "$probes" \
      -p baked.probe_lookup="$lookup" --json "$out/$pipeline-$lookup.json" > "$out/$pipeline-$lookup.txt"
  done
done
for f in "$out"/*.json; do
  printf '%-28s %s\n' "$(basename "$f" .json)" \
    "$(grep -o '"frame_gpu_median_ms": [0-9.e+-]*' "$f" | cut -d' ' -f2) ms (GPU, median)"
done
