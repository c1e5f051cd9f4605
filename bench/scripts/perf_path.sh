#!/bin/sh
# Where illum's path tracer spends its time: `perf record -g` (Debian's linux-perf) over one
# `illum render`, then the self time grouped: Embree, sampler, texture lookups, hit-point
# reconstruction, BSDF, light selection and sampling, path loop (bench/results/path-tracer.md,
# "Profile").
#   bench/scripts/perf_path.sh ILLUM OUTDIR SCENE [illum render options]
#   bench/scripts/perf_path.sh build/ci/bin/illum "" cornell --width 256 --height 256 --spp 32
#   bench/scripts/perf_path.sh build/ci/bin/illum "" sibenik --width 192 --height 128 --spp 64
# Build first: `cmake --build build/ci --target illum`; needs `perf` (Debian: linux-perf).
# OUTDIR "" means ${TMPDIR:-/tmp}/illum-bench/perf. Writes OUTDIR/SCENE.{data,txt,exr} and
# prints the per-symbol table and the grouped totals. The groups are by symbol name (self
# time, no children): Embree's symbols are stripped, so its share is its whole library.
# Exit 2 on bad arguments.
set -eu
if [ $# -lt 3 ]; then
  echo "usage: $0 ILLUM OUTDIR SCENE [illum render options]" >&2
  exit 2
fi
illum=$1 out=${2:-${TMPDIR:-/tmp}/illum-bench/perf} scene=$3
shift 3
[ -x "$illum" ] || { echo "$0: $illum is not an executable" >&2; exit 2; }
command -v perf >/dev/null || { echo "$0: perf is not installed (Debian: linux-perf)" >&2; exit 2; }
mkdir -p "$out"
perf record -g -F 499 -o "$out/$scene.data" "$illum" render "$scene" "$@" -o "$out/$scene.exr" --no-preview
perf report -i "$out/$scene.data" --no-children --sort dso,symbol --stdio -g none 2>/dev/null |
  grep '%' > "$out/$scene.txt"
head -25 "$out/$scene.txt" | cut -c1-120
awk '
{ p = $1; sub("%", "", p); c = "other"
  if ($0 ~ /libembree/) c = "Embree (BVH traversal, all rays)"
  else if ($0 ~ /SobolSampler|hash_mix/) c = "sampler (Sobol + scrambling hashes)"
  else if ($0 ~ /Image::rgb|sample_bilinear|fmodf|texture_color|material_albedo/) c = "texture lookups"
  else if ($0 ~ /RayTracer::interaction/) c = "hit-point reconstruction (RayTracer::interaction)"
  else if ($0 ~ /Bsdf|cosine_hemisphere|concentric_disk|sincos/) c = "BSDF construction and sampling"
  else if ($0 ~ /LightSampler|Distribution1D|sample_uniform_triangle|shadow_ray|sample_direct/) c = "light selection and sampling"
  else if ($0 ~ /PathRadiance|render_tiles|generate_ray|RayTracer::intersect|RayTracer::occluded/) c = "path loop, camera, trace wrappers"
  else if ($0 ~ /tinyobj|strtod|tokens_of|memchr|obj_loader|kernel|libz|ld-linux|libtbb/) c = "scene loading, kernel, I/O"
  s[c] += p }
END { for (k in s) printf "%6.2f%%  %s\n", s[k], k }' "$out/$scene.txt" | sort -rn
