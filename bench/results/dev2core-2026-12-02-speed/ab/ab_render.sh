#!/bin/sh
# ab.sh NEWBIN REPS SCENE ARGS... : alternates base and new `illum render`, prints CPU seconds
new=$1 reps=$2 scene=$3; shift 3
for r in $(seq $reps); do
  for b in /tmp/speed-base/illum $new; do
    /usr/bin/time -f "%U %S %e" -o /tmp/speed-ab/t.txt $b render $scene "$@" -o /tmp/speed-ab/out.exr --no-preview >/dev/null 2>&1
    set -- "$@"
    echo "$(basename $(dirname $(dirname $(dirname $b))))/$(basename $b) $(awk '{printf "cpu %.2f wall %.2f", $1+$2, $3}' /tmp/speed-ab/t.txt) load $(cut -d' ' -f1 /proc/loadavg)"
  done
done
