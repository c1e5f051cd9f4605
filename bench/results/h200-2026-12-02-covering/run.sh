#!/bin/bash
# The covering rate and the cascades at three map resolutions, on the H200 (repository root;
# .device holds the gzipped bundle of main d8e9fc7's `illum` and `illum-bench`, Sibenik staged;
# .device/frame1080.json is ../h200-2026-12-02-depth-cascades/run4-caster-culling.tgz's
# new/sibenik-1920x1080-visibility-every.json):
#   bash bench/results/h200-2026-12-02-covering/run.sh      (writes $OUT/cover.* and res.tgz)
set -u
source bench/results/h200-2026-12-02-vertex/device_setup.sh
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
# cover.txt / cover.json: the bench alone over that frame (same bounds, plus the covering rate).
.device/bin/illum-bench raster .device/frame1080.json --repeats 30 --json $OUT/cover.json |
  tee $OUT/cover.txt
# res.tgz: Sibenik 1080p visibility frames (every / cached) with every map at 512², 1024², 2048².
for res in 512 1024 2048; do
  FRAMES=200 WARMUP=20 REPEATS=30 SCENES=sibenik SIZES=1920x1080 PIPELINES=visibility \
    PARAMS="-p map.resolution=$res" bash bench/raster_bounds.sh .device/bin/illum \
    .device/bin/illum-bench $R/res$res > $R/res$res.log 2>&1
  echo "res $res rc $?"
  grep -E "covering|^  (cascades|shadow_maps) " $R/res$res/raster.txt | cut -c1-200
done
tar czf $OUT/res.tgz -C $R .
