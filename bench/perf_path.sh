#!/bin/sh
# Where illum's path tracer spends its time: `perf record -g` (Debian's linux-perf) over one
# `illum render`, then the self time grouped into the costs issue 10 asks about.
#   bench/perf_path.sh build/ci/bin/illum OUTDIR cornell --width 256 --height 256 --spp 32
#   bench/perf_path.sh build/ci/bin/illum OUTDIR sibenik --width 192 --height 128 --spp 64
# Writes OUTDIR/SCENE.data and prints the per-symbol table and the grouped totals. The
# groups are by symbol name (self time, no children): Embree's symbols are stripped, so its
# share is its whole library.
set -eu
illum=$1 out=$2 scene=$3
shift 3
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
