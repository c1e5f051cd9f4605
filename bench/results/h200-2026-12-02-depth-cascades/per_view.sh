#!/bin/bash
# The cascades timed view by view (a build with a timer scope around each cascade, not
# committed: .device/exp/illum = this change, .device/exp/illum-base = main before it),
# Sibenik 1080p, visibility and deferred frames, every map each frame.
#   bash bench/results/h200-2026-12-02-depth-cascades/per_view.sh
source bench/results/h200-2026-12-02-vertex/device_setup.sh >/dev/null 2>&1
gunzip -f .device/exp/*.gz; chmod +x .device/exp/*
for b in illum illum-base; do
  for t in visibility deferred forward; do
    echo "== $b $t"
    .device/exp/$b frame sibenik --width 1920 --height 1080 --frames 200 --warmup 20 \
      -p shadow_update_period=1 --technique $t 2>&1 | grep -E "^  +(cascade|shadow_maps|frame)"
  done
done
