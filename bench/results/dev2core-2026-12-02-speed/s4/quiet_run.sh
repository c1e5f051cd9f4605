#!/bin/sh
# The quiet-machine Cycles comparison for branch s4-speed, the same commands as ../quiet/:
# run it with nothing else on the machine, from the repository root, after
# `cmake --build --preset ci --target illum-bench`. OUT defaults to the folder that holds
# the first quiet run's cached references (illum 1024/2048 spp, Cycles 1024/2048 spp); the
# branch's renders are the same bytes as main's, so illum's cached reference still holds.
# About 3 minutes with the references cached (Cornell ~1.5, Sibenik ~1.3), about 9 without.
set -eu
bench=${BUILD:-build/ci}/bin/illum-bench
out=${OUT:-/tmp/speed-runs/peer/out}
here=$(dirname "$0")
echo "=== cornell $(date -u) load: $(cat /proc/loadavg)"
"$bench" converge cornell --width 256 --height 256 --spp 16,64,256 --reference-spp 1024 \
  --out "$out" --json "$here/cornell-quiet.json"
echo "=== sibenik $(date -u) load: $(cat /proc/loadavg)"
"$bench" converge sibenik --width 192 --height 128 --spp 16,64,256 --reference-spp 2048 \
  --out "$out" --json "$here/sibenik-quiet.json"
echo "=== done $(date -u) load: $(cat /proc/loadavg)"
