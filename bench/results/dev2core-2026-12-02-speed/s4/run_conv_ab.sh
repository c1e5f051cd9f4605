#!/bin/bash
# base (main beb090b) and this branch alternately, illum only, 2 threads, the quiet run's sizes and references
cd /work/wt/speed
for rep in 1 2; do
  for b in base final; do
    for sc in cornell sibenik; do
      if [ $sc = cornell ]; then sz="--width 256 --height 256 --reference-spp 1024"; else sz="--width 192 --height 128 --reference-spp 2048"; fi
      echo "=== $b $sc rep $rep $(date -u +%T) load: $(cut -d' ' -f1-3 /proc/loadavg)"
      /tmp/speed/bin/illum-bench-$b converge $sc $sz --spp 16,64,256 --peer none --out /tmp/speed/ab2 --json /tmp/speed/ab2/$sc-$b-$rep.json 2>&1 | grep -E "^ +[0-9]+ "
    done
  done
done
echo done
