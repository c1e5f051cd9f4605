#!/bin/bash
# Cascade diagnostics (not committed code): env switches of a diagnostic build.
source bench/results/h200-2026-12-02-vertex/device_setup.sh >/dev/null 2>&1
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
i=0
for v in "X=1" "ILLUM_DIAG_D16=1" "ILLUM_DIAG_CULL=b" "ILLUM_DIAG_CULL=f" "ILLUM_DIAG_D16=1 ILLUM_DIAG_CULL=f" "ILLUM_DIAG_D16=1 ILLUM_DIAG_CULL=b" "X=2"; do
  i=$((i+1))
  env $v .device/bin/illum frame sibenik --width 1920 --height 1080 --technique visibility --shadows map --frames 200 --warmup 20 -p shadow_update_period=1 --json $R/v$i.json > $R/v$i.txt 2>&1
  echo "$v: $(grep -E '^  (cascades|frame) ' $R/v$i.txt | tr -s ' ' | tr '\n' ' ')"
done
.device/bin/illum-bench raster $R/v*.json --repeats 30 --json $R/raster.json > $R/raster.txt 2>&1; echo "bench rc $?"
grep -E "^/tmp|^  cascades " $R/raster.txt
cp $R/*.txt $R/*.json $OUT/
