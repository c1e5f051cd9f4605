#!/bin/bash
# MPI ranks against threads on one machine (bench/results/mpi.md): renders
# `illum render sibenik --width 384 --height 256 --spp 64 --seed 1` with --threads T in one
# process (T = 1, 2, 4, … up to the cores) and with `mpirun --oversubscribe --bind-to none
# -np N` (N ranks sharing the cores), wall and user time by /usr/bin/time, including the scene
# load and BVH build every process does (and mpirun's start-up), then checks that every image
# is byte-identical to the one-thread image.
#
#   bench/scripts/mpi_scaling.sh ILLUM [OUTDIR]
#
# Build first: `cmake --build build/ci --target illum` with MPI found (Debian: libopenmpi-dev;
# docs/distributed.md); needs `mpirun`. Run from the repository root (Sibenik is in
# ../shared/scenes). OUTDIR defaults to ${TMPDIR:-/tmp}/illum-bench/mpi; it gets machine.txt
# and the log; the images are removed after the comparison. Exit 2 on bad arguments.
#
# On the GPU machine's 16 cores (no MPI installed there: bundle Open MPI's Debian packages and
# their dependencies into .device/mpi/ and extract them with `dpkg -x` first; with PMIx 4,
# `export PMIX_MCA_preg=native`, or mpirun crashes before starting a rank; as root
# `export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1`), from the repository root:
#   source bench/scripts/device-setup.sh
#   bench/scripts/mpi_scaling.sh .device/bin/illum "$OUT/mpi"
set -uo pipefail
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
  echo "usage: $0 ILLUM [OUTDIR]" >&2
  exit 2
fi
illum=$1 out=${2:-${TMPDIR:-/tmp}/illum-bench/mpi}
[ -x "$illum" ] || { echo "$0: $illum is not an executable" >&2; exit 2; }
command -v mpirun > /dev/null || { echo "$0: mpirun not found" >&2; exit 2; }
mkdir -p "$out"
illum=$(cd "$(dirname "$illum")" && pwd)/$(basename "$illum")
{ nproc; lscpu | grep -E "Model name|^CPU\(s\)|Thread|Core|Socket"; mpirun --version | head -1; } > "$out/machine.txt" 2>&1
cat "$out/machine.txt"
cores=$(nproc)
args=(render sibenik --width 384 --height 256 --spp 64 --seed 1)
n=1
while [ "$n" -le "$cores" ]; do
  /usr/bin/time -f "threads $n: %e s wall, %U s user" "$illum" "${args[@]}" --threads "$n" \
    -o "$out/threads$n.exr" 2>&1 | grep -E "wall|error"
  n=$((n * 2))
done
n=1
while [ "$n" -le "$cores" ]; do
  /usr/bin/time -f "ranks $n: %e s wall, %U s user" mpirun --oversubscribe --bind-to none -np "$n" \
    "$illum" "${args[@]}" -o "$out/ranks$n.exr" 2>&1 | grep -E "wall|rror" | head -3
  n=$((n * 2))
done
for f in "$out"/threads*.exr "$out"/ranks*.exr; do
  if cmp -s "$f" "$out/threads1.exr"; then echo "$(basename "$f") = threads1"; else echo "$(basename "$f") DIFFERS"; fi
done | tee "$out/identical.txt"
rm -f "$out"/*.exr
