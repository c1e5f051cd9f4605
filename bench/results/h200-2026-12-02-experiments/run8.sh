#!/bin/bash
# One-off experiments on the H200 with a temporary build (environment switches that are not
# in the code base): cluster size, front-to-back order on/off, the visibility id target not
# cleared, and illum-bench raster's colour targets not cleared. Sibenik 1920x1080, shadow
# maps every frame, median of 200 frames after 20.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
gunzip -f .device/lib/libembree3.so.3.gz .device/scenes/sibenik/sibenik.obj.gz
source .device/env.sh
export ILLUM_DATA_DIR=$PWD/data
mkdir -p ../shared/scenes && ln -sfn "$PWD/.device/scenes/sibenik" ../shared/scenes/sibenik
R=/tmp/r; mkdir -p $R/x
f() {
  name=$1 tech=$2; shift 2
  env "$@" illum frame sibenik --width 1920 --height 1080 --technique $tech --shadows map \
    -p shadow_update_period=1 --frames 200 --warmup 20 --json $R/x/$name.json > $R/x/$name.txt 2>&1
  echo "$name: $(grep -E '^  (frame|visibility |cascades|shadow_maps|depth_prepass|gbuffer)' $R/x/$name.txt | tr -s ' ' | tr '\n' ';')"
}
f base visibility
f c128 visibility ILLUM_X_CLUSTER=128
f c256 visibility ILLUM_X_CLUSTER=256
f c2048 visibility ILLUM_X_CLUSTER=2048
f c8192 visibility ILLUM_X_CLUSTER=8192
f mesh visibility ILLUM_X_CLUSTER=100000000
f nosort visibility ILLUM_X_NOSORT=1
f idload visibility ILLUM_X_IDLOAD=1
f d_base deferred
f d_c2048 deferred ILLUM_X_CLUSTER=2048
f d_c128 deferred ILLUM_X_CLUSTER=128
illum-bench raster $R/x/base.json $R/x/d_base.json --repeats 30 --json $R/x/bench_clear.json > $R/x/bench_clear.txt 2>&1
ILLUM_X_COLOR_LOAD=1 illum-bench raster $R/x/base.json $R/x/d_base.json --repeats 30 --json $R/x/bench_dontcare.json > $R/x/bench_dontcare.txt 2>&1
for f in bench_clear bench_dontcare; do python3 -c "
import json
d = json.load(open('$R/x/$f.json'))
for b in d['raster_bounds']: print('$f', b['key'], 'slope %.4f fixed %.4f' % (b['ms_per_layer'], b['fixed_ms']))
"; done
tar czf $OUT/x.tgz -C $R x
