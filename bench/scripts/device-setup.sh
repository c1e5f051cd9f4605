# Sourced on the GPU machine before a GPU script, from the repository root of the checkout
# the device run carries:
#
#   source bench/scripts/device-setup.sh
#
# The bundle is made here first (a Release or `ci` build; Sibenik's files travel with it,
# since ../shared is not there):
#
#   ../shared/tools/device-bundle build/ci/bin/illum build/ci/bin/illum-bench ../shared/scenes/sibenik
#
# Files of the bundle may be gzipped to fit the run's carry limit (`gzip .device/lib/*.so*`):
# they are unpacked here. A `.gl/` folder of Debian packages (the GL/EGL loader libraries the
# bundled Vulkan loader needs, where the machine lacks them) is extracted into / when present.
# Sets the bundle's environment (PATH, LD_LIBRARY_PATH, the NVIDIA Vulkan driver manifest),
# ILLUM_DATA_DIR, and links the bundled Sibenik where the scene files expect it
# (../shared/scenes/sibenik).
if [ ! -f .device/env.sh ]; then
  echo "device-setup.sh: no .device/env.sh here (make the bundle with ../shared/tools/device-bundle, run from the repository root)" >&2
  return 2 2>/dev/null || exit 2
fi
if [ -d .gl ]; then
  for f in .gl/*.deb; do [ -f "$f" ] && dpkg -x "$f" /; done
  ldconfig
fi
find .device -name '*.gz' -exec gunzip -f {} +
chmod +x .device/bin/* 2>/dev/null
. .device/env.sh
export ILLUM_DATA_DIR=$PWD/data
for d in .device/sibenik .device/scenes/sibenik; do
  if [ -d "$d" ]; then
    mkdir -p ../shared/scenes && ln -sfn "$PWD/$d" ../shared/scenes/sibenik
    break
  fi
done
command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
true
