#!/bin/bash
# The light-map figures of bench/results/lightmaps.md: the path baker on Sibenik at 1M texels,
# radiosity with and without receiver clusters, the atlas, and the bake's memory.
#
#   bench/scripts/lightmaps.sh ILLUM ILLUM_BENCH [OUTDIR [PART...]]
#
# Build first: `cmake --build build/ci --target illum illum-bench`; run from the repository
# root (Sibenik and the bunny are in ../shared/scenes). OUTDIR ("" or absent:
# ${TMPDIR:-/tmp}/illum-bench/lightmaps) gets NAME.log (command, load before and after,
# `/usr/bin/time -v`) and NAME.json per run. PARTs (default: bake radiosity atlas memory):
#   bake              `illum bake sibenik` at 1200² (1.01M texels, 16 spp, 3 bounces,
#                     denoised) and `illum-bench lightmap` on the same atlas (texel loop,
#                     denoiser, error against a 128-spp bake)
#   radiosity         Cornell 64² and 128² (τ = 0.001) and Sibenik 384² and 768² (τ = 0.01),
#                     unclustered (--cluster-ratio 0) and clustered (0.1, the default)
#   radiosity-large   for a many-core machine (THREADS=16): Sibenik 512² at τ = 0.001 with the
#                     atlas-space images of docs/lightmaps.md, both ways, and 768² both ways
#                     (unclustered > 7 min on 16 cores; capped at 40 min)
#   atlas             `illum-bench atlas`: Sibenik and the bunny at 1024², a synthetic scene of
#                     1M triangles at 4096²
#   memory            peak RSS and wall of `illum bake` at several sizes and options
# THREADS (default 2: the "on 2 cores" figures) sets --threads; PIN=2,3 runs each job under
# `taskset -c 2,3` (two pinned cores of an otherwise idle machine). Exit 2 on bad arguments.
#
# On the GPU machine's CPU (bundle: device-setup.sh with illum, illum-bench and Sibenik), from
# the repository root:
#   source bench/scripts/device-setup.sh
#   PIN=2,3 bench/scripts/lightmaps.sh .device/bin/illum .device/bin/illum-bench "$OUT/lm" bake
#   THREADS=16 bench/scripts/lightmaps.sh .device/bin/illum .device/bin/illum-bench "$OUT/lm" radiosity-large
set -euo pipefail
if [ $# -lt 2 ]; then
  echo "usage: $0 ILLUM ILLUM_BENCH [OUTDIR [PART...]]" >&2
  exit 2
fi
illum=$1 bench=$2 out=${3:-}
[ -n "$out" ] || out=${TMPDIR:-/tmp}/illum-bench/lightmaps
shift $(($# < 3 ? $# : 3))
parts=("$@")
[ ${#parts[@]} -gt 0 ] || parts=(bake radiosity atlas memory)
for x in "$illum" "$bench"; do
  [ -x "$x" ] || { echo "$0: $x is not an executable" >&2; exit 2; }
done
for p in "${parts[@]}"; do
  case $p in
    bake|radiosity|radiosity-large|atlas|memory) ;;
    *) echo "$0: unknown part '$p' (bake radiosity radiosity-large atlas memory)" >&2; exit 2 ;;
  esac
done
threads=${THREADS:-2}
pin=()
[ -n "${PIN:-}" ] && pin=(taskset -c "$PIN")
mkdir -p "$out"

run() {  # NAME PROGRAM ARGS...: one timed run, its log and its lines of interest
  local name=$1
  shift
  { date -u; nproc; uptime; echo "+ $*"; } > "$out/$name.log"
  /usr/bin/time -v timeout 2400 "${pin[@]}" "$@" >> "$out/$name.log" 2>&1 || echo "exit $?" >> "$out/$name.log"
  uptime >> "$out/$name.log"
  echo "== $name"
  grep -E "texels|radiosity|path|seconds|Elapsed|Maximum resident" "$out/$name.log" | head -20 || true
}

for p in "${parts[@]}"; do
  case $p in
    bake)
      run bake-sibenik-1200 "$illum" bake sibenik --resolution 1200 --spp 16 --bounces 3 \
        --threads "$threads" -o "$out/sibenik-1200"
      cp "$out/sibenik-1200/lightmap.json" "$out/bake-sibenik-1200.json" 2>/dev/null || true
      run lightmap-sibenik "$bench" lightmap --scene sibenik --resolution 1200 --spp 16 \
        --reference-spp 128 --max-bounces 3 --repeats 1 --seed 1 --threads "$threads" \
        --json "$out/lightmap-sibenik.json" ;;
    radiosity)
      for r in 64 128; do
        run cornell-$r "$bench" radiosity --scene cornell --resolution $r --threshold 0.001 \
          --threads "$threads" --cluster-ratio 0,0.1 --json "$out/cornell-$r.json"
      done
      run sibenik-384 "$bench" radiosity --scene sibenik --resolution 384 --reference-spp 64 \
        --threshold 0.01 --max-spp 0 --threads "$threads" --cluster-ratio 0,0.1,0.2 \
        --json "$out/sibenik-384.json"
      run sibenik-768 "$bench" radiosity --scene sibenik --resolution 768 --reference-spp 64 \
        --threshold 0.01 --max-spp 0 --threads "$threads" --cluster-ratio 0.1 \
        --json "$out/sibenik-768.json" ;;
    radiosity-large)
      run sibenik-512 "$bench" radiosity --scene sibenik --resolution 512 --reference-spp 512 \
        --max-spp 512 --threshold 0.001 --cluster-ratio 0,0.1 --threads "$threads" \
        --images "$out" --json "$out/sibenik-512.json"
      run sibenik-768-clustered "$bench" radiosity --scene sibenik --resolution 768 \
        --reference-spp 256 --max-spp 256 --threshold 0.01 --cluster-ratio 0.1 \
        --threads "$threads" --json "$out/sibenik-768-clustered.json"
      run sibenik-768-unclustered "$bench" radiosity --scene sibenik --resolution 768 \
        --reference-spp 256 --max-spp 0 --threshold 0.01 --cluster-ratio 0 \
        --threads "$threads" --json "$out/sibenik-768-unclustered.json" ;;
    atlas)
      run atlas-scenes-1024 "$bench" atlas --scene sibenik --scene ../shared/scenes/bunny/bunny.obj \
        --resolution 1024 --threads "$threads" --json "$out/atlas-scenes-1024.json"
      run atlas-synthetic-1M "$bench" atlas --synthetic 1000000 --resolution 4096 \
        --threads "$threads" --repeats 3 --json "$out/atlas-synthetic-1M.json" ;;
    memory)
      for args in "--resolution 256 --spp 1" "--resolution 512 --spp 1" "--resolution 1024 --spp 1" \
          "--resolution 2048 --spp 1" "--resolution 1024 --spp 1 --basis sh" \
          "--resolution 1024 --spp 1 --extras ao,obscurance,bent_normal --extras-rays 4" \
          "--resolution 1024 --spp 1 -p denoise=false"; do
        # shellcheck disable=SC2086  # args splits into arguments
        /usr/bin/time -f "cornell $args :: RSS_KB %M WALL %e" "${pin[@]}" "$illum" bake cornell $args \
          --threads "$threads" -o "$out/memory-bake" > /dev/null 2>> "$out/memory.log" || true
        tail -1 "$out/memory.log"
      done
      for r in 600 1200; do
        /usr/bin/time -f "sibenik --resolution $r --spp 1 -p denoise=false :: RSS_KB %M WALL %e" \
          "${pin[@]}" "$illum" bake sibenik --resolution $r --spp 1 -p denoise=false \
          --threads "$threads" -o "$out/memory-bake" > /dev/null 2>> "$out/memory.log" || true
        tail -1 "$out/memory.log"
      done
      rm -rf "$out/memory-bake" ;;
  esac
done
