#!/bin/bash
# The PCF cascades in d16 (map.cascade_depth, main after 6f5a66a) against main 6f5a66a (d32), on
# the H200: the depth-cascades matrix (Sibenik and Cornell × SIZES × PIPELINES × every/cached,
# base in .device/base, new in .device/bin; bundle recipe in
# bench/results/h200-2026-12-02-depth-cascades/README.md), then the new build with d32 cascades
# (-p map.cascade_depth=d32: what else the change touched — the maps' transfer usage — costs
# nothing if it matches the base).
#   bash bench/results/h200-2026-12-03-d16-cascades/run.sh "SIZES" "PIPELINES"
set -u
bash bench/results/h200-2026-12-02-depth-cascades/run.sh "$1" "$2"
source .device/env.sh
export ILLUM_DATA_DIR=$PWD/data
for pipe in visibility deferred; do
  for depth in d32 d16; do
    .device/bin/illum frame sibenik --width 1920 --height 1080 --technique $pipe --shadows map \
      --frames 200 --warmup 20 -p shadow_update_period=1 -p map.cascade_depth=$depth \
      > /tmp/r/new-$pipe-$depth.txt 2>&1
    echo "new, cascade_depth=$depth, $pipe: $(grep -E '^  (cascades|frame) ' /tmp/r/new-$pipe-$depth.txt | tr -s ' ' | tr '\n' ' ')"
  done
done | tee $OUT/d32-check.txt
