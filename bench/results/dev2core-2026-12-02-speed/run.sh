#!/bin/sh
# Same arguments as bench/results/dev2core-2026-12-02-converge/run.sh, this branch's
# illum-bench (copied to /tmp/speed-ab/bench-final), Cycles as the peer.
B=/tmp/speed-ab/bench-final
O=/tmp/speed-runs/peer
for rep in 1 2; do
  echo "=== run $rep cornell $(date -u) load: $(cat /proc/loadavg)"
  $B converge cornell --width 256 --height 256 --spp 16,64,256 --reference-spp 1024 --out $O/out --json $O/cornell-$rep.json
  echo "=== run $rep sibenik $(date -u) load: $(cat /proc/loadavg)"
  $B converge sibenik --width 192 --height 128 --spp 16,64,256 --reference-spp 2048 --out $O/out --json $O/sibenik-$rep.json
done
echo "=== done $(date -u) load: $(cat /proc/loadavg)"
