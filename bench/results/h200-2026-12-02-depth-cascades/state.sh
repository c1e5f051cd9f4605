#!/bin/bash
# What the cascades inherit from the visibility raster (builds not committed):
# .device/exp/illum-emptyfs — the depth-only cascades with an empty fragment shader;
# .device/exp/illum-noprimid — the visibility raster's fragment shader without
# gl_PrimitiveID (wrong ids: a diagnostic only). Sibenik 1080p, spot maps cached (so the
# cascades follow the previous frame's last raster pass) and every frame.
#   bash bench/results/h200-2026-12-02-depth-cascades/state.sh
source bench/results/h200-2026-12-02-vertex/device_setup.sh >/dev/null 2>&1
gunzip -f .device/exp/*.gz 2>/dev/null; chmod +x .device/exp/* 2>/dev/null
for b in .device/exp/illum-emptyfs .device/exp/illum-noprimid .device/bin/illum; do
  for t in visibility deferred; do
    for period in 0 1; do
      echo "== $b $t shadow_update_period=$period"
      $b frame sibenik --width 1920 --height 1080 --frames 200 --warmup 20 \
        -p shadow_update_period=$period --technique $t 2>&1 |
        grep -E "^  +(cascades|shadow_maps|visibility|frame) "
    done
  done
done
