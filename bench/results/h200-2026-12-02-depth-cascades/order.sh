source bench/results/h200-2026-12-02-vertex/device_setup.sh >/dev/null 2>&1
gunzip -f .device/exp/*.gz; chmod +x .device/exp/*
for b in ${BINS:-illum-order illum}; do
  for t in visibility deferred; do
    echo "== $b $t"
    .device/exp/$b frame sibenik --width 1920 --height 1080 --frames 200 --warmup 20 \
      -p shadow_update_period=1 --technique $t 2>&1 | grep -E "^  +(cascade|shadow_maps|visibility |depth_prepass|frame)"
  done
done
