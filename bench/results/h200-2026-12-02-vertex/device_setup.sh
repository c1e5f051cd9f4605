# Sourced by this folder's scripts on the device, from the repository root: unpacks the GL
# loader packages and the gzipped bundle (.device/bin: the new build, .device/base: main's
# illum before the change), sets the bundle's environment and links the staged Sibenik where
# the scene files expect it; results go under R=/tmp/r.
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
gunzip -f .device/lib/*.gz .device/scenes/sibenik/sibenik.obj.gz .device/bin/*.gz .device/base/*.gz
chmod +x .device/bin/* .device/base/*
source .device/env.sh
export ILLUM_DATA_DIR=$PWD/data
mkdir -p ../shared/scenes && ln -sfn "$PWD/.device/scenes/sibenik" ../shared/scenes/sibenik
R=/tmp/r; mkdir -p $R
