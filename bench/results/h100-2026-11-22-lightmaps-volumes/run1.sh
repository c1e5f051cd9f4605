#!/bin/bash
# Device run 1: Sibenik 1080p frame timings (new stencil/light-map modes), images, and a
# 16-core Sibenik bake. Run from the repository root on the device machine with
# .device/payload.tar.xz (a device-bundle of build/release/bin/illum plus the Sibenik files
# and a 1024², 2-spp indirect light-map folder `sib-timing` made by
# `illum bake sibenik -o sib-timing --resolution 1024 --spp 2 --content indirect`, used only
# for timing) and .gl (the GL/EGL loader packages the bundle's Vulkan loader needs).
for f in .gl/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p /tmp/b && tar xJf .device/payload.tar.xz -C /tmp/b
source /tmp/b/bundle/env.sh
export ILLUM_DATA_DIR=$PWD/data
mkdir -p ../shared/scenes/sibenik && cp /tmp/b/bundle/sibenik/* ../shared/scenes/sibenik/
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
nproc
J=/tmp/j; mkdir -p $J
R="--width 1920 --height 1080 --frames 200 --warmup 20"
run() { name=$1; shift; illum frame "$@" --json $J/$name.json > $J/$name.txt 2>&1; echo "== $name"; grep -E "stencil|silhou|volume_l|gbuffer|lighting|forward |frame|wall" $J/$name.txt; }
run fwd-map sibenik $R --technique forward --shadows map
run def-map sibenik $R --technique deferred --shadows map
run fwd-vol-gpu sibenik $R --technique forward --shadows volume
run fwd-vol-cpu sibenik $R --technique forward --shadows volume -p silhouettes=cpu
run def-vol-gpu sibenik $R --technique deferred --shadows volume
run def-vol-cpu sibenik $R --technique deferred --shadows volume -p silhouettes=cpu
run def-vol-gpu-cached sibenik $R --technique deferred --shadows volume -p shadow_update_period=0
run def-map-lm sibenik $R --technique deferred --shadows map --lightmap /tmp/b/bundle/sib-timing
run fwd-map-lm sibenik $R --technique forward --shadows map --lightmap /tmp/b/bundle/sib-timing
run cornell-def-vol cornell $R --technique deferred --shadows volume
illum frame sibenik --technique deferred --shadows volume -o $OUT/rt-sibenik-deferred-volume.png > /dev/null 2>&1
tar czf $OUT/frames.tgz -C /tmp j
echo "== bake"
( time timeout 330 illum bake sibenik -o /tmp/sib-lm --resolution 2048 --spp 64 --content indirect --seed 1 ) 2>&1 | tail -5
cp /tmp/sib-lm/lightmap.json /tmp/sib-lm/preview.png $OUT/ 2>/dev/null
illum frame sibenik --technique deferred --shadows map --lightmap /tmp/sib-lm -o $OUT/rt-sibenik-lightmap.png 2>&1 | tail -1
illum frame sibenik --technique deferred --shadows map --lightmap /tmp/sib-lm -o $OUT/rt-sibenik-lightmap.exr > /dev/null 2>&1
ls -la $OUT
