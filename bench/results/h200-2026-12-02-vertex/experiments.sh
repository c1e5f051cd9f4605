#!/bin/bash
# Experiments after run.sh (commands in README.md): the new bundle with environment switches
# that existed only in that build — ILLUM_EXP_UNSORTED=cascades|all (shadow views drawn in
# cluster order, so runs of clusters merge into few draws) and ILLUM_EXP_NO_OVERDRAW (clusters
# ordered for vertex reuse only) — and the vertex-invocation counts now in the counting frame.
set -u
source bench/results/h200-2026-12-02-vertex/device_setup.sh
run() {  # NAME [env]
  local name=$1; shift
  env "$@" FRAMES=200 WARMUP=20 REPEATS=30 SCENES="sibenik" SIZES="960x540 1920x1080" \
    PIPELINES="visibility deferred" PARAMS="-p occlusion_culling=false" \
    bash bench/raster_bounds.sh .device/bin/illum .device/bin/illum-bench $R/$name > $R/$name.log 2>&1
  echo "$name rc $?"
}
run new
run unsorted-cascades ILLUM_EXP_UNSORTED=cascades
run unsorted-all ILLUM_EXP_UNSORTED=all
run no-overdraw ILLUM_EXP_NO_OVERDRAW=1
tar czf $OUT/exp.tgz -C $R .
for n in new unsorted-cascades unsorted-all no-overdraw; do
  echo "== $n"
  awk '/^\/tmp.*sibenik-(960x540|1920x1080)-(visibility|deferred)-every/{p=1; print substr($0, 40, 70); next} /^$/{p=0} p && /^  (shadow_maps|depth_prepass|visibility|gbuffer|cascades) /{v=$0; sub(/.* triangles \(/, "", v); print substr($0, 1, 62), "|", v}' $R/$n/raster.txt
done
