#!/bin/bash
# ab.sh REPS BIN_A BIN_B ... : fixed-work single-thread renders, interleaved; prints bin scene user_s render_wall_s
reps=$1; shift
bins=("$@")
cd /work/wt/speed
for r in $(seq 1 $reps); do
  for b in "${bins[@]}"; do
    for sc in ${SCENES:-cornell sibenik}; do
      if [ $sc = cornell ]; then args="cornell --width 256 --height 256 --spp 32"; else args="sibenik --width 192 --height 128 --spp 64"; fi
      out=$( { /usr/bin/time -f "USER %U" $b render $args --threads 1 --seed 1 -o /tmp/speed/ab-$(basename $b)-$sc.exr --no-preview >/dev/null; } 2>&1 )
      u=$(echo "$out" | grep -o "USER [0-9.]*" | cut -d' ' -f2)
      rt=$(echo "$out" | grep -o "render [0-9.]*s" | head -1 | tr -d 'rendes ')
      echo "$(basename $b) $sc $u $rt"
    done
  done
done
