#!/usr/bin/env bash
# Installs every Debian 12 package illum needs to build, test and benchmark.
# Idempotent: packages already present are skipped by apt; `apt-get update` runs once
# per invocation only when something is missing.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git file
  libembree-dev libtbb-dev libglm-dev libnanoflann-dev
  libtinygltf-dev libtinyobjloader-dev libstb-dev libopenexr-dev
  nlohmann-json3-dev libcli11-dev libspdlog-dev libfmt-dev libmeshoptimizer-dev
  libvulkan-dev glslc glslang-tools spirv-tools vulkan-validationlayers
  mesa-vulkan-drivers vulkan-tools libglfw3-dev libimgui-dev xvfb xauth xdotool
  libgtest-dev libgmock-dev libbenchmark-dev clang-format
  # The asan preset and the fuzz harnesses: clang with libFuzzer and the sanitizer runtimes,
  # and llvm-symbolizer for readable reports. Clang 16, not Debian's default 14: clang 14
  # cannot compile libstdc++ 12's std::source_location, which illum::Error uses.
  clang-16 libclang-rt-16-dev llvm-16
  # Distributed render and bake (`mpirun -np N illum ...`, src/illum/distributed).
  openmpi-bin libopenmpi-dev
)
# Optional group, with `--engine-check`: Chromium, Node.js and npm for scripts/engine-check
# (three.js reads an exported .glb in headless Chromium; ctest label `engine`, outside CI).
# An npm already on the PATH (e.g. a newer Node.js's own) is kept: Debian's would conflict.
if [[ ${1:-} == --engine-check ]]; then
  packages+=(chromium)
  command -v npm > /dev/null || packages+=(nodejs npm)
fi
# Optional, not installed here: `blender` (Debian's, 3.4) for `illum-bench converge`'s Cycles
# peer (bench/peers/; its test has the label `peer`, outside CI), `linux-perf` for profiling.

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo=""
if [[ $(id -u) -ne 0 ]]; then sudo="sudo"; fi
echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
$sudo apt-get update -q
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
