#!/usr/bin/env bash
# docs/distributed.md's speed-up figure: the Cornell box, 256x256, path tracer, 32 spp, one
# thread per rank, three times each: without mpirun, mpirun -np 1, mpirun -np 2 (wall time
# with start-up); then checks the three images are the same bytes. Run from the checkout:
#   scripts/mpi-speedup.sh [path/to/illum]   (default build/ci/bin/illum)
set -euo pipefail
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1  # containers run as root
illum=${1:-build/ci/bin/illum}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
args=(render cornell --width 256 --height 256 --spp 32 --seed 1 --threads 1)
for rep in 1 2 3; do
  /usr/bin/time -f "plain      %e s" "$illum" "${args[@]}" -o "$out/plain.png" 2>&1 | grep -v "^illum:"
  /usr/bin/time -f "mpirun N=1 %e s" mpirun -q -np 1 "$illum" "${args[@]}" -o "$out/n1.png" 2>&1 | grep -v "^illum:"
  /usr/bin/time -f "mpirun N=2 %e s" mpirun -q -np 2 "$illum" "${args[@]}" -o "$out/n2.png" 2>&1 | grep -v "^illum:"
done
cmp "$out/plain.png" "$out/n1.png" && cmp "$out/plain.png" "$out/n2.png" && echo "outputs identical"
