#!/bin/bash
# Clustered draws on the H200: `illum frame` over Sibenik and Cornell × SIZES × {visibility,
# deferred} × {maps every frame, cached} through bench/raster_bounds.sh (each pass beside its
# bound), then Sibenik 1080p with SSAO. Run from the repository root with the bundle in
# .device as `bash bench/results/h200-2026-12-02-clusters/run.sh NAME "SIZES"`; the runs of
# this folder (README) were raster6 "1920x1080", raster7, raster9 and raster10
# "960x540 1920x1080 3840x2160", each on the commit its README line names.
set -u
name=$1 sizes=$2
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
gunzip -f .device/lib/libembree3.so.3.gz .device/scenes/sibenik/sibenik.obj.gz
source .device/env.sh
export ILLUM_DATA_DIR=$PWD/data
mkdir -p ../shared/scenes && ln -sfn "$PWD/.device/scenes/sibenik" ../shared/scenes/sibenik
R=/tmp/r; mkdir -p $R/$name $R/ssao
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee $R/gpu.txt
FRAMES=200 WARMUP=20 REPEATS=30 SCENES="sibenik cornell" SIZES="$sizes" PIPELINES="visibility deferred" \
  bash bench/raster_bounds.sh .device/bin/illum .device/bin/illum-bench $R/$name > $R/$name.log 2>&1; echo "rc $?"
for t in visibility deferred; do
  illum frame sibenik --width 1920 --height 1080 --technique $t --shadows map -p shadow_update_period=1 \
    --enable ssao -p ssao.radius=0.5 --frames 200 --warmup 20 --json $R/ssao/sibenik-$t-ssao.json > $R/ssao/sibenik-$t-ssao.txt 2>&1
  echo "ssao $t: $(grep -E '^  (frame|ssao)' $R/ssao/sibenik-$t-ssao.txt | tr -s ' ' | tr '\n' ';')"
done
tar czf $OUT/$name.tgz -C $R .
grep -E "^/tmp.*frame" $R/$name/raster.txt
