#!/bin/bash
# The quad bound on the H200: Sibenik and Cornell × SIZES × {visibility, deferred, forward} ×
# {maps every frame, cached} through bench/raster_bounds.sh; `illum-bench raster` now adds the
# quad bound (the mixed pass with the passing layers made of the quads the pass shaded).
#   bash bench/results/h200-2026-12-02-quads/run.sh NAME "SIZES" "PIPELINES" (from the
#   repository root, the bundle in .device; this folder: quads1 "960x540 1920x1080 3840x2160"
#   "visibility deferred forward")
# PARAMS in the environment is passed on to bench/raster_bounds.sh (`illum frame` arguments,
# e.g. PARAMS="-p occlusion_culling=true"; culling is off by default).
set -u
name=$1 sizes=$2 pipelines=$3
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
gunzip -f .device/lib/libembree3.so.3.gz .device/scenes/sibenik/sibenik.obj.gz
source .device/env.sh
export ILLUM_DATA_DIR=$PWD/data
mkdir -p ../shared/scenes && ln -sfn "$PWD/.device/scenes/sibenik" ../shared/scenes/sibenik
R=/tmp/r; mkdir -p $R/$name
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee $R/gpu.txt
echo "PARAMS=${PARAMS:-}" | tee $R/$name/params.txt
FRAMES=200 WARMUP=20 REPEATS=30 SCENES="sibenik cornell" SIZES="$sizes" PIPELINES="$pipelines" \
  bash bench/raster_bounds.sh .device/bin/illum .device/bin/illum-bench $R/$name > $R/$name.log 2>&1; echo "rc $?"
tail -3 $R/$name.log
tar czf $OUT/$name.tgz -C $R .
grep -E "^/tmp.*frame|quads|  (shadow_maps|depth_prepass|visibility|gbuffer|forward|cascades)(\.occlusion)? " $R/$name/raster.txt | grep -E "1920x1080|^  " | head -80
