#!/bin/bash
# The visibility frame's cascades are 0.09 ms slower than the deferred frame's unless SSAO
# (whose apply pass renders into the HDR target) is on: a build (not committed,
# .device/exp/illum-hdrca) whose visibility technique creates its HDR target with colour-
# attachment usage as well, never rendering into it. Sibenik 1080p, maps every frame.
#   bash bench/results/h200-2026-12-02-depth-cascades/hdr_usage.sh
source bench/results/h200-2026-12-02-vertex/device_setup.sh >/dev/null 2>&1
gunzip -f .device/exp/*.gz 2>/dev/null; chmod +x .device/exp/* 2>/dev/null
for b in .device/exp/illum-hdrca .device/bin/illum; do
  for t in visibility deferred; do
    echo "== $b $t"
    $b frame sibenik --width 1920 --height 1080 --frames 200 --warmup 20 \
      -p shadow_update_period=1 --technique $t 2>&1 | grep -E "^  +(cascades|visibility|frame) "
  done
done
