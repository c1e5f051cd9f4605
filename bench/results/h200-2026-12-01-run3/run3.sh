#!/bin/bash
# Issue 9: request 3 of rt-speed (ee1c455), SSAO cost on main 8858c14.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
gunzip -f .device/lib/libembree3.so.3.gz .device/scenes/sibenik/sibenik.obj.gz
source .device/env.sh
export ILLUM_DATA_DIR=$PWD/data
mkdir -p ../shared/scenes && ln -sfn "$PWD/.device/scenes/sibenik" ../shared/scenes/sibenik
R=/tmp/r; mkdir -p $R/raster3 $R/raster3v $R/raster3b $R/ssao
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee $R/gpu.txt
ILLUM=.device/bin/illum ILLUM_BENCH=.device/bin/illum-bench
s=$(date +%s)
FRAMES=200 WARMUP=20 REPEATS=50 SCENES="sibenik cornell" SIZES="1920x1080" PIPELINES="visibility deferred forward" bash .device/raster_bounds.sh $ILLUM $ILLUM_BENCH $R/raster3 > $R/raster3.log 2>&1; echo "1: rc $? $(( $(date +%s) - s )) s"
$ILLUM frame sibenik --width 1920 --height 1080 --technique deferred --shadows volume --frames 50 --warmup 5 --json $R/raster3v/vol.json > $R/raster3v/vol.txt 2>&1
$ILLUM_BENCH raster $R/raster3v/vol.json --repeats 50 --json $R/raster3v/raster-vol.json > $R/raster3v/raster-vol.txt 2>&1; echo "2: rc $?"
FRAMES=200 WARMUP=20 REPEATS=50 SCENES="sibenik cornell" SIZES="960x540 3840x2160" PIPELINES="visibility deferred" bash .device/raster_bounds.sh $ILLUM $ILLUM_BENCH $R/raster3b > $R/raster3b.log 2>&1; echo "3: rc $? $(( $(date +%s) - s )) s"
for p in deferred forward; do for a in off on; do
  en=(); [ $a = on ] && en=(--enable ssao -p ssao.radius=0.5)
  illum-main-ssao frame sibenik --width 1920 --height 1080 --technique $p --shadows map -p shadow_update_period=1 "${en[@]}" --frames 200 --warmup 20 --json $R/ssao/sibenik-$p-ssao-$a.json > $R/ssao/sibenik-$p-ssao-$a.txt 2>&1
  echo "ssao $p $a: $(grep -E '^  (frame|ssao)' $R/ssao/sibenik-$p-ssao-$a.txt | tr -s ' ' | tr '\n' ';')"
done; done
tar czf $OUT/results3.tgz -C $R .
grep -A9 "sibenik 1920x1080, visibility" $R/raster3/raster.txt | head -24
