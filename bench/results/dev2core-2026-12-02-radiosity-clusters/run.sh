#!/bin/bash
# Under the build lock: mutations, full build + ctest, then the measurements (2 threads).
cd /work/wt/radiosity
L=/tmp/radmut/log.txt
: > $L
for m in M1 M2 M3 M4; do
  echo "=== $m $(date -u)" >> $L
  python3 /tmp/radmut/mut.py $m >> $L 2>&1
  cmake --build --preset ci -j2 --target bake_radiosity_tests bake_progressive_shooting_tests 2>&1 | grep -E "error" >> $L
  ctest --preset ci -R "Clusters|ShadowEdge" -V 2>&1 | grep -E "Failure|Expected|actual|Which is|FAILED  \]|Cornell 40²: rel|furnace 48|cube 16|tests passed" | head -20 >> $L
  git checkout -- src/illum/bake/shooting_clusters.h
done
echo "=== full build $(date -u)" >> $L
cmake --build --preset ci -j2 2>&1 | grep -E "error|FAILED" | head >> $L
echo "=== ctest $(date -u)" >> $L
ctest --preset ci -j2 2>&1 | tail -15 >> $L
echo "=== done $(date -u)" >> $L
R=bench/results/dev2core-2026-12-02-radiosity-clusters
B=build/ci/bin/illum-bench
run() { name=$1; shift; { date -u; uptime; echo "+ illum-bench $*"; } > $R/$name.log; /usr/bin/time -v timeout 1500 $B "$@" --json $R/$name.json >> $R/$name.log 2>&1; { uptime; date -u; } >> $R/$name.log; }
run cornell-64 radiosity --scene cornell --resolution 64 --threshold 0.001 --threads 2 --cluster-ratio 0,0.1
run cornell-128 radiosity --scene cornell --resolution 128 --threshold 0.001 --threads 2 --cluster-ratio 0,0.1
run sibenik-384 radiosity --scene sibenik --resolution 384 --reference-spp 64 --threshold 0.01 --max-spp 0 --threads 2 --cluster-ratio 0,0.1,0.2
run sibenik-768 radiosity --scene sibenik --resolution 768 --reference-spp 64 --threshold 0.01 --max-spp 0 --threads 2 --cluster-ratio 0.1
