#!/bin/bash
# Is it the graphics pass before the cascades? A build (not committed,
# .device/exp/illum-after-spots) that records the cascades after the spot maps instead of
# before them: with the spot maps rendered every frame the cascades then follow an r32f
# colour pass; with them cached, the previous frame's last raster pass (the visibility
# raster's r32ui ids, the G-buffer's float targets) as before. Sibenik 1080p.
#   bash bench/results/h200-2026-12-02-depth-cascades/after_spots.sh
source bench/results/h200-2026-12-02-vertex/device_setup.sh >/dev/null 2>&1
gunzip -f .device/exp/*.gz 2>/dev/null; chmod +x .device/exp/* 2>/dev/null
for b in .device/exp/illum-after-spots .device/bin/illum; do
  for t in visibility deferred; do
    for period in 1 0; do
      echo "== $b $t shadow_update_period=$period"
      $b frame sibenik --width 1920 --height 1080 --frames 200 --warmup 20 \
        -p shadow_update_period=$period --technique $t 2>&1 | grep -E "^  +(cascades|shadow_maps|frame) "
    done
  done
done
