#!/bin/bash
# PCF cascades rendered depth-only (the depth array is the map: no r32f target, no fragment
# shader) against the bundle of main before the change (.device/base), on the H200:
# Sibenik and Cornell × SIZES × PIPELINES × {every, cached}, occlusion culling off (default).
#   bash bench/results/h200-2026-12-02-depth-cascades/run.sh "SIZES" "PIPELINES"
#   (repository root; .device holds the new bundle in bin/ and main's illum in base/, gzipped)
set -u
sizes=$1 pipelines=$2
source bench/results/h200-2026-12-02-vertex/device_setup.sh
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee $R/gpu.txt
run() {  # NAME ILLUM (the bench is always the new one: the same bounds for both)
  local name=$1 illum=$2
  FRAMES=200 WARMUP=20 REPEATS=30 SCENES="sibenik cornell" SIZES="$sizes" PIPELINES="$pipelines" \
    bash bench/raster_bounds.sh $illum .device/bin/illum-bench $R/$name > $R/$name.log 2>&1
  echo "$name rc $?"
}
run base .device/base/illum
run new .device/bin/illum
tar czf $OUT/run.tgz -C $R .
for n in base new; do
  echo "== $n"
  awk '/^\/tmp.*sibenik-(960x540|1920x1080)-(visibility|deferred)-(every|cached)/{p=1; print substr($0, 1, 110); next} /^$/{p=0} p && /^  (shadow_maps|depth_prepass|visibility|gbuffer|cascades) /{print substr($0, 1, 62)}' $R/$n/raster.txt
done
grep -A3 "cascades" $R/new/raster.txt | grep -m2 "cascades"
