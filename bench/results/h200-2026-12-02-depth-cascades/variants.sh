#!/bin/bash
# Sibenik 1080p, the cascades and spot maps (every frame) of the new bundle under frame
# pipelines and shadow settings, and two runs of main's (.device/base) — to find what the
# cascades' time depends on. Run from the repository root on the device:
#   bash bench/results/h200-2026-12-02-depth-cascades/variants.sh
source bench/results/h200-2026-12-02-vertex/device_setup.sh >/dev/null 2>&1
f() { echo "== $*"; .device/bin/illum frame sibenik --width 1920 --height 1080 --frames 200 --warmup 20 -p shadow_update_period=1 "$@" 2>&1 | grep -E "^  (cascades|shadow_maps|depth_prepass|visibility|gbuffer|frame) "; }
f --technique visibility --json $R/visibility.json
python3 -c "import json; print('gpu_memory', json.load(open('$R/visibility.json'))['gpu_memory'])"
f --technique deferred
f --technique forward
f --technique visibility -p map.resolution=1024
f --technique deferred -p map.resolution=1024
f --technique visibility --shadows vsm
f --technique deferred --shadows vsm
g() { echo "== base $*"; .device/base/illum frame sibenik --width 1920 --height 1080 --frames 200 --warmup 20 -p shadow_update_period=1 "$@" 2>&1 | grep -E "^  (cascades|shadow_maps|depth_prepass|visibility|gbuffer|frame) "; }
g --technique visibility
g --technique deferred
