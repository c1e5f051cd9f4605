#!/bin/sh
# ab2.sh REPS SCENE ARGS... -- BIN1 BIN2 ...: alternates the binaries, prints CPU seconds
reps=$1 scene=$2; shift 2
args=""; while [ "$1" != "--" ]; do args="$args $1"; shift; done; shift
for r in $(seq $reps); do
  for b in "$@"; do
    /usr/bin/time -f "%U %S %e" -o /tmp/speed-ab/t.txt $b render $scene $args -o /tmp/speed-ab/out.exr --no-preview >/dev/null 2>&1
    echo "$(basename $b) $(awk '{printf "cpu %.2f wall %.2f", $1+$2, $3}' /tmp/speed-ab/t.txt) load $(cut -d' ' -f1 /proc/loadavg)"
  done
done
