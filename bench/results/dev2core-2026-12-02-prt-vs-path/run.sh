#!/bin/sh
# The PRT-vs-path-tracer figures and image grids of docs/prt.md ("Against the path tracer"),
# issue 11's "done when". Run from the repository root after `cmake --build --preset ci`.
# On the shared 2-core machine (load ~2 from other jobs, run at nice 19): 23 min in all, the
# Cornell box with an opening ~12 min, Sibenik ~11 min.
set -e
B=build/ci/bin/illum-bench
R=bench/results/dev2core-2026-12-02-prt-vs-path
ENV=../shared/scenes/envmaps/venice_sunset_1k.hdr
$B prt-vs-path --scene data/scenes/cornell-opening/cornell-opening.illum.json \
  --sun 0.25,-1,0.3,8 --sun=-0.4,-0.5,1,6 --env $ENV \
  --bands 6 --resolution 128 --bake-spp 256 --width 128 --height 128 --path-spp 512 \
  --max-bounces 16 --threads 2 --seed 1 \
  --image docs/images/prt_vs_path_cornell_opening.png --json $R/cornell_opening.json \
  | tee $R/cornell_opening.txt
$B prt-vs-path --scene sibenik \
  --sun 0.354,-0.866,-0.354,10 --sun=-0.5,-0.7,0.5,10 --env $ENV \
  --bands 6 --resolution 512 --bake-spp 64 --width 96 --height 64 --path-spp 1024 \
  --max-bounces 8 --threads 2 --seed 1 \
  --image docs/images/prt_vs_path_sibenik.png --json $R/sibenik.json \
  | tee $R/sibenik.txt
