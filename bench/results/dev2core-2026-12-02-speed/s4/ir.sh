#!/bin/bash
# ir.sh BIN... : instructions executed (valgrind --tool=cachegrind, Ir) of a small fixed render of each scene, whole process
cd /work/wt/speed
for b in "$@"; do
  for sc in ${SCENES:-cornell sibenik}; do
    if [ $sc = cornell ]; then args="cornell --width 64 --height 64 --spp 16"; else args="sibenik --width 48 --height 32 --spp 32"; fi
    ir=$(valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=/dev/null $b render $args --threads 1 --seed 1 -o /tmp/speed/ir-$(basename $b)-$sc.exr --no-preview 2>&1 | grep "I *refs" | awk '{print $NF}')
    echo "$(basename $b) $sc Ir $ir"
  done
done
