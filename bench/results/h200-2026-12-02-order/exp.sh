# The experiment that chose the cluster order and size (issue 9): Sibenik 1920x1080,
# visibility and deferred frames, every map each frame, for each "ORDER CLUSTER" pair —
# ORDER 0: the cluster's centre as the sort key (main before), 1: its nearest corner, 2: its
# farthest corner; CLUSTER: triangles per cluster. It ran on a build with two experiment-only
# environment variables (EXP_ORDER, EXP_CLUSTER) read in visible_clusters() and gpu_scene.cpp
# that were never committed; the committed code is ORDER 2, CLUSTER 256.
#   CONFIGS='"0 512" "1 512" ...' bash exp.sh   (from the repository root, the bundle in .device)
set -u
for f in .gl/*.deb; do dpkg -x $f / 2>/dev/null; done; ldconfig
gunzip -f .device/lib/libembree3.so.3.gz .device/scenes/sibenik/sibenik.obj.gz 2>/dev/null
source .device/env.sh; export ILLUM_DATA_DIR=$PWD/data
mkdir -p ../shared/scenes && ln -sfn "$PWD/.device/scenes/sibenik" ../shared/scenes/sibenik
R=/tmp/exp; rm -rf $R; mkdir -p $R
for cfg in ${CONFIGS:-"0 512" "1 512" "2 512"}; do
  set -- $cfg; o=$1 c=$2
  for t in visibility deferred; do
    EXP_ORDER=$o EXP_CLUSTER=$c illum frame sibenik --width 1920 --height 1080 --technique $t --shadows map -p shadow_update_period=1 --frames 200 --warmup 20 --json $R/o$o-c$c-$t.json > $R/o$o-c$c-$t.txt 2>/dev/null
  done
  echo "order $o cluster $c: $(grep -hE '^  (frame|shadow_maps|visibility |depth_prepass|cascades)' $R/o$o-c$c-*.txt | tr -s ' ' | tr '\n' ';')"
done
illum-bench raster $R/*.json --repeats 20 > $R/raster.txt 2>&1
grep -E "^/tmp|  (shadow_maps|depth_prepass|visibility|gbuffer) " $R/raster.txt
tar czf $OUT/exp.tgz -C /tmp exp
