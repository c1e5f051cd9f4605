#!/bin/bash
# Same setup as run1.sh (payload without the timing light-map).
# Device run 2: denoised Sibenik bake (docs image) and a 16-spp one for comparison.
for f in .gl/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
mkdir -p /tmp/b && tar xJf .device/payload.tar.xz -C /tmp/b
source /tmp/b/bundle/env.sh
export ILLUM_DATA_DIR=$PWD/data
mkdir -p ../shared/scenes/sibenik && cp /tmp/b/bundle/sibenik/* ../shared/scenes/sibenik/
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
illum bake sibenik -o /tmp/sib-lm --resolution 2048 --spp 64 --content indirect --seed 1 2>&1 | tail -1
illum frame sibenik --technique deferred --shadows map --lightmap /tmp/sib-lm -o $OUT/rt-sibenik-lightmap.png 2>&1 | tail -1
cp /tmp/sib-lm/lightmap.json $OUT/bake-sibenik-2048-64spp.json
illum bake sibenik -o /tmp/sib-16 --resolution 2048 --spp 16 --content indirect --seed 1 2>&1 | tail -1
illum frame sibenik --technique deferred --shadows map --lightmap /tmp/sib-16 -o $OUT/sibenik-lightmap-16spp.png 2>&1 | tail -1
illum bake sibenik -o /tmp/sib-16raw --resolution 2048 --spp 16 --content indirect --seed 1 -p denoise=false 2>&1 | tail -1
illum frame sibenik --technique deferred --shadows map --lightmap /tmp/sib-16raw -o $OUT/sibenik-lightmap-16spp-raw.png 2>&1 | tail -1
cp /tmp/sib-16/lightmap.json $OUT/bake-sibenik-2048-16spp.json
