#!/bin/bash
# PRT relit against the path tracer (bench/results/prt.md, "Against the path tracer"): one
# PRT bake relit under two suns and one environment map, beside the path tracer under the
# same band-limited light and under the true light, with the error figures and an image grid
# (`illum-bench prt-vs-path`, bench/README.md; docs/prt.md "Against the path tracer"). CPU only.
#
#   bench/scripts/prt_vs_path.sh ILLUM_BENCH [OUTDIR] [sibenik|small|cornell-opening]
#
# Build first: `cmake --build build/ci --target illum-bench`; run from the repository root
# (the environment map is ../shared/scenes/envmaps, as Sibenik's meshes). OUTDIR defaults to
# ${TMPDIR:-/tmp}/illum-bench/prt-vs-path.
#
# sibenik (default): Sibenik, 6 bands, interreflected, 8 path bounces. Writes
# prt_vs_path_sibenik.png (a row per light: relit, path tracer under the band-limited light,
# path tracer under the true light, |relit − path| × 4), sibenik.json (every figure),
# sibenik.txt (the printed summary), log.txt (with the wall time) and command.txt. THREADS
# (default: all cores) sets the worker count; RESOLUTION, BAKE_SPP, WIDTH, HEIGHT and
# PATH_SPP override the sizes (1024, 128, 192, 128, 1024; the table's run: RESOLUTION=768
# WIDTH=96 HEIGHT=64 THREADS=16, 489 s on 16 Xeon cores). Path-tracing time grows as
# WIDTH·HEIGHT·PATH_SPP (15 images: 5 a light), the bake as RESOLUTION²·BAKE_SPP (two bakes).
# MODE (interreflected) and MAX_BOUNCES (8) select the transfer and the path tracer's depth
# (direct light only: MODE=shadowed MAX_BOUNCES=1); STITCH (true) and PUSH_OUT (true) the
# bake's seam stitching and texel push-out, as the CLI's bake; SPREAD_SEEDS (16) the bakes of
# the seen texels' direct transfer that give the relit side's σ and the bias's standard
# error (0: the two-run σ only).
# small: the same lights at tiny sizes (a smoke test, about 2 minutes on two cores).
# cornell-opening: the Cornell box with a ceiling opening (data/scenes/cornell-opening), two
# suns and the map, 6 bands, 128² atlas, 128×128 pixels, 16 bounces (about 12 minutes on two
# cores); writes prt_vs_path_cornell_opening.png (docs/images), cornell_opening.{json,txt}.
#
# The Sibenik suns: Sibenik is closed but for its windows and door, and the scene's own sun
# (0.354,−0.866,−0.354) lights 0.4 % of the camera's view directly. A scan of 144 directions
# (bench/scripts/sibenik_sun_scan.py: elevation 15–85°, every 20° of azimuth; direct light
# only, 96×64 from the scene camera) found these two the best at 3.8 % and 3.3 %: A, 45° high,
# from +z across the nave through that wall's windows; B, 15° high, from +x along the nave
# through the entrance front. Both travel along −y (down).
#
# On the GPU machine's 16 cores (CPU only; bundle: device-setup.sh with illum-bench and the
# environment map), from the repository root:
#   source bench/scripts/device-setup.sh
#   RESOLUTION=768 WIDTH=96 HEIGHT=64 THREADS=16 bench/scripts/prt_vs_path.sh .device/bin/illum-bench "$OUT/prt-vs-path"
set -euo pipefail
if [ $# -lt 1 ] || [ $# -gt 3 ]; then
  echo "usage: $0 ILLUM_BENCH [OUTDIR] [sibenik|small|cornell-opening]" >&2
  exit 2
fi
bench=$1 out=${2:-${TMPDIR:-/tmp}/illum-bench/prt-vs-path} size=${3:-sibenik}
[ -x "$bench" ] || { echo "$0: $bench is not an executable" >&2; exit 2; }
env_map=../shared/scenes/envmaps/venice_sunset_1k.hdr
[ -f "$env_map" ] || { echo "$0: $env_map not found (run from the repository root)" >&2; exit 2; }
if [ "$size" = cornell-opening ]; then
  mkdir -p "$out"
  start=$(date +%s)
  "$bench" prt-vs-path --scene data/scenes/cornell-opening/cornell-opening.illum.json \
    --sun 0.25,-1,0.3,8 --sun=-0.4,-0.5,1,6 --env "$env_map" \
    --bands 6 --resolution 128 --bake-spp 256 --width 128 --height 128 --path-spp 512 \
    --max-bounces 16 --threads "${THREADS:-0}" --seed 1 \
    --image "$out/prt_vs_path_cornell_opening.png" --json "$out/cornell_opening.json" |
    tee "$out/cornell_opening.txt"
  echo "wall $(( $(date +%s) - start )) s, threads ${THREADS:-all} of $(nproc)"
  exit 0
fi
case $size in
  sibenik)
    sizes=(--resolution "${RESOLUTION:-1024}" --bake-spp "${BAKE_SPP:-128}"
      --width "${WIDTH:-192}" --height "${HEIGHT:-128}" --path-spp "${PATH_SPP:-1024}") ;;
  small)
    sizes=(--resolution 512 --bake-spp 8 --width 48 --height 32 --path-spp 32) ;;
  *) echo "$0: '$size' is none of sibenik, small, cornell-opening" >&2; exit 2 ;;
esac
mkdir -p "$out"
cmd=("$bench" prt-vs-path --scene sibenik
  --sun=-0.123,-0.707,-0.696,10 --sun=-0.908,-0.259,0.330,10 --env "$env_map"
  --bands 6 --mode "${MODE:-interreflected}" "${sizes[@]}" --max-bounces "${MAX_BOUNCES:-8}"
  --stitch "${STITCH:-true}" --push-out "${PUSH_OUT:-true}" --spread-seeds "${SPREAD_SEEDS:-16}"
  --threads "${THREADS:-0}" --seed 1
  --image "$out/prt_vs_path_sibenik.png" --json "$out/sibenik.json")
printf '%q ' "${cmd[@]}" > "$out/command.txt"
echo >> "$out/command.txt"
start=$(date +%s)
"${cmd[@]}" 2> >(tee "$out/log.txt" >&2) | tee "$out/sibenik.txt"
echo "wall $(( $(date +%s) - start )) s, threads ${THREADS:-all} of $(nproc)" | tee -a "$out/log.txt"
