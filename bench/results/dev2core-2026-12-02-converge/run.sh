#!/bin/sh
B=/work/wt/converge/build/ci/bin/illum-bench
cd /work/wt/converge
for rep in 1 2; do
  echo "=== run $rep cornell $(date -u) load: $(cat /proc/loadavg)"
  $B converge cornell --width 256 --height 256 --spp 16,64,256 --reference-spp 1024 --out /tmp/converge-runs/out --json /tmp/converge-runs/cornell-$rep.json
  echo "=== run $rep sibenik $(date -u) load: $(cat /proc/loadavg)"
  $B converge sibenik --width 192 --height 128 --spp 16,64,256 --reference-spp 2048 --out /tmp/converge-runs/out --json /tmp/converge-runs/sibenik-$rep.json
done
echo "=== done $(date -u) load: $(cat /proc/loadavg)"
