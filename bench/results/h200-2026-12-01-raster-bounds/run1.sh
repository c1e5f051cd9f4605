#!/bin/bash
# Issue 9 (3a): raster bounds and the pass table on the device; before (main 8f15deb) and
# after (rt-speed dd36fb5) binaries, same matrix, same run.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
gunzip -f .device/lib/libembree3.so.3.gz .device/scenes/sibenik/sibenik.obj.gz
source .device/env.sh
export ILLUM_DATA_DIR=$PWD/data
mkdir -p ../shared/scenes && ln -sfn "$PWD/.device/scenes/sibenik" ../shared/scenes/sibenik
R=/tmp/r; mkdir -p $R/after $R/before
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee $R/gpu.txt
illum frame sibenik --width 64 --height 64 --frames 2 2>&1 | tail -3
start=$(date +%s)
FRAMES=200 WARMUP=20 REPEATS=50 bash .device/raster_bounds.sh .device/bin/illum .device/bin/illum-bench $R/after > $R/after.log 2>&1
echo "after matrix: $(( $(date +%s) - start )) s, rc $?"; tail -5 $R/after.log
for scene in cornell sibenik; do for size in 960x540 1920x1080 3840x2160; do w=${size%x*} h=${size#*x}
  for p in forward deferred; do for s in every cached; do
    per=1; [ $s = cached ] && per=0
    n=$scene-$size-$p-$s
    illum-main frame $scene --width $w --height $h --technique $p --shadows map --frames 200 --warmup 20 -p shadow_update_period=$per --json $R/before/$n.json > $R/before/$n.txt 2>&1
    echo "before $n: $(grep -E '^  frame ' $R/before/$n.txt)"
  done; done; done; done
illum-bench raster $R/before/*.json --repeats 50 --json $R/before/raster.json > $R/before/raster.txt 2>&1; echo "before bench rc $?"
illum frame sibenik --width 1920 --height 1080 --technique deferred --shadows volume --frames 50 --warmup 5 --json $R/after/vol.json > $R/after/vol.txt 2>&1
illum-bench raster $R/after/vol.json --repeats 50 --json $R/after/raster-vol.json > $R/after/raster-vol.txt 2>&1; echo "vol rc $?"
echo "total $(( $(date +%s) - start )) s"
tar czf $OUT/results.tgz -C $R .
cp $R/after/raster.txt $OUT/after-raster.txt 2>/dev/null; cp $R/before/raster.txt $OUT/before-raster.txt 2>/dev/null
