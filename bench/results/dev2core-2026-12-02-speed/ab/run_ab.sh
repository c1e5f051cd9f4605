#!/bin/sh
# A/B of main's illum-bench (/tmp/speed-base) and this branch's (/tmp/speed-ab/bench-new),
# interleaved, illum only (--peer none), same arguments as the converge run.sh.
for rep in 1 2; do
  for v in base new; do
    if [ $v = base ]; then B=/tmp/speed-base/illum-bench; else B=/tmp/speed-ab/bench-new; fi
    echo "=== rep $rep $v cornell $(date -u) load: $(cat /proc/loadavg)"
    $B converge cornell --width 256 --height 256 --spp 16,64,256 --reference-spp 1024 --peer none --out /tmp/speed-runs/ab-$v --json /tmp/speed-runs/ab/cornell-$v-$rep.json
  done
  for v in base new; do
    if [ $v = base ]; then B=/tmp/speed-base/illum-bench; else B=/tmp/speed-ab/bench-new; fi
    echo "=== rep $rep $v sibenik $(date -u) load: $(cat /proc/loadavg)"
    $B converge sibenik --width 192 --height 128 --spp 16,64,256 --reference-spp 2048 --peer none --out /tmp/speed-runs/ab-$v --json /tmp/speed-runs/ab/sibenik-$v-$rep.json
  done
done
echo "=== done $(date -u) load: $(cat /proc/loadavg)"
