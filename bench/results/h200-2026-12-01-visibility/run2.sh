#!/bin/bash
# Issue 9 (3b): the matrix with the visibility buffer (rt-speed 6cad98f), images.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
gunzip -f .device/lib/libembree3.so.3.gz .device/scenes/sibenik/sibenik.obj.gz
source .device/env.sh
export ILLUM_DATA_DIR=$PWD/data
mkdir -p ../shared/scenes && ln -sfn "$PWD/.device/scenes/sibenik" ../shared/scenes/sibenik
R=/tmp/r; mkdir -p $R/raster2
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee $R/gpu.txt
start=$(date +%s)
FRAMES=200 WARMUP=20 REPEATS=50 PIPELINES="forward deferred visibility" bash .device/raster_bounds.sh .device/bin/illum .device/bin/illum-bench $R/raster2 > $R/raster2.log 2>&1
echo "matrix rc $? $(( $(date +%s) - start )) s"; grep -E "visibility" $R/raster2.log | head -20
illum frame sibenik --technique visibility --width 1920 --height 1080 -o $R/rt-sibenik-visibility.png > $R/img1.txt 2>&1
illum frame sibenik --technique deferred --width 1920 --height 1080 -o $R/rt-sibenik-deferred.png > $R/img2.txt 2>&1
illum frame cornell --technique visibility --width 960 --height 540 -o $R/rt-cornell-visibility.png > $R/img3.txt 2>&1
tar czf $OUT/results2.tgz -C $R .
cp $R/raster2/raster.txt $OUT/raster2.txt 2>/dev/null; cp $R/rt-sibenik-visibility.png $OUT/ 2>/dev/null
