# The corrected bench over the frames of run.tgz (no frame re-rendered: the bounds only).
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
gunzip -f .device/lib/*.gz .device/bin/*.gz; chmod +x .device/bin/*
source .device/env.sh
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
for n in base new; do
  .device/bin/illum-bench raster .device/json/$n/*-every.json .device/json/$n/*-cached.json --repeats 30 --json $OUT/raster-$n-rebound.json > $OUT/raster-$n-rebound.txt 2>&1
  echo "$n rc $?"
  grep -E "^  cascades " $OUT/raster-$n-rebound.txt | head -3
done
