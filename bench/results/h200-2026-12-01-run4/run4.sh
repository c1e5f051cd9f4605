#!/bin/bash
# Issue 9: request 4 of rt-speed (ecdc066): 1080p, visibility and deferred, lower-bound model.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
gunzip -f .device/lib/libembree3.so.3.gz .device/scenes/sibenik/sibenik.obj.gz
source .device/env.sh
export ILLUM_DATA_DIR=$PWD/data
mkdir -p ../shared/scenes && ln -sfn "$PWD/.device/scenes/sibenik" ../shared/scenes/sibenik
R=/tmp/r; mkdir -p $R/raster4
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee $R/gpu.txt
s=$(date +%s)
FRAMES=100 WARMUP=20 REPEATS=30 SCENES="sibenik cornell" SIZES="1920x1080" PIPELINES="visibility deferred" bash .device/raster_bounds.sh .device/bin/illum .device/bin/illum-bench $R/raster4 > $R/raster4.log 2>&1; echo "rc $? $(( $(date +%s) - s )) s"
tar czf $OUT/results4.tgz -C $R .
cat $R/raster4/raster.txt | head -60
