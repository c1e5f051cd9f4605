#!/bin/bash
# Depth-like passes on the packed position stream, the pre-pass on a position-only vertex
# shader, and triangles ordered within each cluster (meshoptimizer: vertex reuse; the first
# runs also ordered for overdraw, dropped after experiments.sh) — against the bundle of main before them (.device/base, occlusion culling off as
# main's default; the unordered run was the new bundle with the within-cluster order switched
# off by an environment variable, removed since), on the H200: Sibenik and Cornell × SIZES × PIPELINES × {every, cached}.
#   bash bench/results/h200-2026-12-02-vertex/run.sh "SIZES" "PIPELINES"   (repository root;
#   .device holds the new bundle in bin/ and main's in base/, binaries gzipped)
set -u
sizes=$1 pipelines=$2
source bench/results/h200-2026-12-02-vertex/device_setup.sh
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee $R/gpu.txt
run() {  # NAME ILLUM (the bench is always the new one: the same bounds for both)
  local name=$1 illum=$2
  FRAMES=200 WARMUP=20 REPEATS=30 SCENES="sibenik cornell" SIZES="$sizes" PIPELINES="$pipelines" \
    PARAMS="-p occlusion_culling=false" \
    bash bench/raster_bounds.sh $illum .device/bin/illum-bench $R/$name > $R/$name.log 2>&1
  echo "$name rc $?"
}
run base .device/base/illum
run new .device/bin/illum
tar czf $OUT/final.tgz -C $R .
grep -E "patches|rate" $R/new/raster.txt | head -12
for n in base new; do
  echo "== $n"
  awk '/^\/tmp.*sibenik-(960x540|1920x1080)-(visibility|deferred)-every/{p=1; print substr($0, 1, 110); next} /^$/{p=0} p && /^  (shadow_maps|depth_prepass|visibility|gbuffer|cascades) /{print substr($0, 1, 62)}' $R/$n/raster.txt
done
