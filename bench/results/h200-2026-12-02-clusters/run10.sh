#!/bin/bash
# Clustered draws (frustum culling, front-to-back) on the H200: Sibenik and Cornell at 540p, 1080p and 2160p, G-buffer and id targets not cleared, visibility and deferred,
# shadow maps every frame and cached, then the visibility pipeline with SSAO. Run from the
# repository root as `bash bench/results/h200-2026-12-02-clusters/run10.sh` with the bundle in .device.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
gunzip -f .device/lib/libembree3.so.3.gz .device/scenes/sibenik/sibenik.obj.gz
source .device/env.sh
export ILLUM_DATA_DIR=$PWD/data
mkdir -p ../shared/scenes && ln -sfn "$PWD/.device/scenes/sibenik" ../shared/scenes/sibenik
R=/tmp/r; mkdir -p $R/raster10 $R/ssao
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee $R/gpu.txt
FRAMES=200 WARMUP=20 REPEATS=30 SCENES="sibenik cornell" SIZES="960x540 1920x1080 3840x2160" PIPELINES="visibility deferred" \
  bash bench/raster_bounds.sh .device/bin/illum .device/bin/illum-bench $R/raster10 > $R/raster10.log 2>&1; echo "rc $?"
for t in visibility deferred; do
  illum frame sibenik --width 1920 --height 1080 --technique $t --shadows map -p shadow_update_period=1 \
    --enable ssao -p ssao.radius=0.5 --frames 200 --warmup 20 --json $R/ssao/sibenik-$t-ssao.json > $R/ssao/sibenik-$t-ssao.txt 2>&1
  echo "ssao $t: $(grep -E '^  (frame|ssao)' $R/ssao/sibenik-$t-ssao.txt | tr -s ' ' | tr '\n' ';')"
done
tar czf $OUT/results10.tgz -C $R .
grep -E "^/tmp.*frame" $R/raster10/raster.txt
