#!/bin/bash
# Real-time indirect light against the path tracer's first indirect bounce (docs/realtime-lpv.md,
# "Validation"): for each scene, `illum frame` with and without the technique (linear EXR, the
# constant ambient off, so their difference is the technique's indirect radiance), `illum
# render -i path --bounce-mode indirect1` at two seeds (light that bounced off exactly one
# surface before reaching the camera; two seeds give the reference's noise) and `-i normals`
# (the regions); same camera, lights and size. `illum-bench gi-compare` prints the figures
# and draws the panels. CPU and lavapipe suffice: the frames are a GPU's up to float rounding.
#
#   bench/scripts/gi_vs_path.sh ILLUM ILLUM_BENCH OUTDIR [SCENE ...] [-- FRAME OPTIONS]
#
# SCENE: cornell-spot, sibenik (both by default) or any scene with a camera. FRAME OPTIONS
# switch the technique on and set its parameters (default: --enable lpv), e.g.
#   bench/scripts/gi_vs_path.sh build/ci/bin/illum build/ci/bin/illum-bench "$TMPDIR/gi"
#   NAME=vpl256 bench/scripts/gi_vs_path.sh build/ci/bin/illum build/ci/bin/illum-bench \
#     "$TMPDIR/gi" cornell-spot -- --enable vpl -p vpl.count=256
# NAME (default lpv) names the outputs: OUTDIR/rt-gi-SCENE-NAME.png (no GI | with it | its
# indirect term | the path tracer's | signed error), SCENE-NAME.json and .txt (the figures),
# and a markdown row per scene appended to OUTDIR/rows.md. The path-traced images are kept
# (SCENE-WxH-SPPspp-seedN.exr) and reused by later runs of the same size and spp.
# Sizes: cornell-spot 256×256 and sibenik 320×200 by default (WIDTH and HEIGHT override
# both), SPP path samples per pixel per seed (1024). Time on the 2-core machine, loaded by
# other builds: about 2 min for cornell-spot, 13 min for sibenik, almost all of it the path
# tracer (bench/results/gi.md).
set -euo pipefail
if [ $# -lt 3 ]; then
  echo "usage: $0 ILLUM ILLUM_BENCH OUTDIR [SCENE ...] [-- FRAME OPTIONS]" >&2
  exit 2
fi
illum=$1 bench=$2 out=$3
shift 3
scenes=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do scenes+=("$1"); shift; done
[ "${1:-}" = "--" ] && shift
technique=("$@")
[ ${#technique[@]} -gt 0 ] || technique=(--enable lpv)
[ ${#scenes[@]} -gt 0 ] || scenes=(cornell-spot sibenik)
for x in "$illum" "$bench"; do [ -x "$x" ] || { echo "$0: $x is not an executable" >&2; exit 2; }; done
mkdir -p "$out" || exit 2
name=${NAME:-lpv}
start=$(date +%s)
for scene in "${scenes[@]}"; do
  case $scene in
    cornell-spot) w=${WIDTH:-256} h=${HEIGHT:-256} spp=${SPP:-1024} ;;
    sibenik) w=${WIDTH:-320} h=${HEIGHT:-200} spp=${SPP:-1024} ;;
    *) w=${WIDTH:-256} h=${HEIGHT:-256} spp=${SPP:-1024} ;;
  esac
  size=(--width "$w" --height "$h")
  frame=("$illum" frame "$scene" "${size[@]}" -p 'ambient=[0,0,0]')
  nice -n 10 "${frame[@]}" -o "$out/$scene-nogi.exr" > /dev/null
  nice -n 10 "${frame[@]}" "${technique[@]}" -o "$out/$scene-$name.exr" > /dev/null
  refs=()
  for seed in 1 2; do
    ref=$out/$scene-${w}x$h-${spp}spp-seed$seed.exr
    [ -f "$ref" ] || nice -n 10 "$illum" render "$scene" -i path --bounce-mode indirect1 \
      "${size[@]}" --spp "$spp" --seed "$seed" -o "$ref" > /dev/null
    refs+=(--reference "$ref")
  done
  normals=$out/$scene-${w}x$h-normals.exr
  [ -f "$normals" ] || nice -n 10 "$illum" render "$scene" -i normals "${size[@]}" --spp 1 \
    -o "$normals" > /dev/null
  "$bench" gi-compare --label "$scene, $name" --no-gi "$out/$scene-nogi.exr" \
    --gi "$out/$scene-$name.exr" "${refs[@]}" --normals "$normals" \
    --image "$out/rt-gi-$scene-$name.png" --json "$out/$scene-$name.json" |
    tee "$out/$scene-$name.txt"
  grep '^row ' "$out/$scene-$name.txt" | sed 's/^row //' >> "$out/rows.md"
  echo "frame options: ${technique[*]}; path tracer: ${w}x$h, $spp spp × 2 seeds" |
    tee -a "$out/$scene-$name.txt"
done
echo "wall $(( $(date +%s) - start )) s on $(nproc) cores"
