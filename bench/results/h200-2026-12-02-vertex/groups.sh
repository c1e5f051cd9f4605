#!/bin/bash
# Experiment: shadow views culling and sorting clusters in groups of siblings (one draw a
# group), through environment switches that existed only in that build (ILLUM_EXP_CASCADE_GROUP,
# ILLUM_EXP_SPOT_GROUP); Sibenik 1920×1080, visibility pipeline, maps every frame.
set -u
source bench/results/h200-2026-12-02-vertex/device_setup.sh
for g in "c1" "c2 ILLUM_EXP_CASCADE_GROUP=2" "c4 ILLUM_EXP_CASCADE_GROUP=4" "c8 ILLUM_EXP_CASCADE_GROUP=8" "s4 ILLUM_EXP_SPOT_GROUP=4 ILLUM_EXP_CASCADE_GROUP=4"; do
  set -- $g; name=$1; shift
  env "$@" FRAMES=200 WARMUP=20 REPEATS=20 SCENES="sibenik" SIZES="1920x1080" PIPELINES="visibility" \
    PARAMS="-p occlusion_culling=false" bash bench/raster_bounds.sh .device/bin/illum .device/bin/illum-bench $R/$name > $R/$name.log 2>&1
  echo "== $name rc $?"
  awk '/^\/tmp.*every/{p=1; print substr($0, 60, 60); next} /^$/{p=0} p && /^  (shadow_maps|visibility|cascades) /{print substr($0, 1, 62)}' $R/$name/raster.txt
done
tar czf $OUT/groups.tgz -C $R .
