#!/bin/bash
# The depth-only cascades take ≈ 0.09 ms more in the visibility frame than in the deferred
# and forward ones: the same pass under other add-ons and pipelines, and a build with the
# cascades' vertex shader doing the two transforms again (.device/exp/illum-twomul, not
# committed) beside the committed one (.device/bin/illum). Sibenik 1080p, maps every frame.
#   bash bench/results/h200-2026-12-02-depth-cascades/anomaly.sh
source bench/results/h200-2026-12-02-vertex/device_setup.sh >/dev/null 2>&1
gunzip -f .device/exp/*.gz 2>/dev/null; chmod +x .device/exp/* 2>/dev/null
f() {
  local b=$1; shift
  echo "== $b $* ${ILLUM_SERIALIZE_PASSES:+(serialized)}"
  $b frame sibenik --width 1920 --height 1080 --frames 200 --warmup 20 -p shadow_update_period=1 \
    "$@" 2>&1 | grep -E "^  +(cascades|shadow_maps|depth_prepass|visibility|gbuffer|frame) "
}
for b in .device/bin/illum .device/exp/illum-twomul; do
  f $b --technique visibility
  f $b --technique deferred
done
f .device/bin/illum --technique visibility --enable ssao
f .device/bin/illum --technique visibility --enable bloom
f .device/bin/illum --technique deferred -p deferred.lighting=volumes
f .device/bin/illum --technique forward --enable ssao
# .device/exp/illum-serial: a build (not committed) whose timer puts an execution barrier
# (all commands → all commands) before each pass's first timestamp when
# ILLUM_SERIALIZE_PASSES is set: no pass starts before the one before it has finished.
for t in visibility deferred forward; do
  f .device/exp/illum-serial --technique $t
  ILLUM_SERIALIZE_PASSES=1 f .device/exp/illum-serial --technique $t
done
