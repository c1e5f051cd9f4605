#!/bin/bash
# Issue 10 part 4: MPI ranks against threads on the GPU machine's CPU. Run from the
# repository root with the bundle in .device (illum + staged Sibenik) and Open MPI's Debian
# packages in .device/mpi (plus libnuma/libatomic in .device/mpi/lib), as
#   bash bench/results/h200-2026-12-02-mpi/run.sh
set -u
for f in .gl/*.deb .device/mpi/*.deb; do dpkg -x "$f" /; done
cp .device/mpi/lib/* /usr/lib/x86_64-linux-gnu/; ldconfig
gunzip -f .device/lib/libembree3.so.3.gz .device/scenes/sibenik/sibenik.obj.gz
source .device/env.sh
export ILLUM_DATA_DIR=$PWD/data OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# Without a preg component named, mpirun (Open MPI 4.1.4, PMIx 4 from the extracted debs)
# crashed in pmix_preg_base_generate_ppn (a NULL call) before starting any rank.
export PMIX_MCA_preg=native
mkdir -p ../shared/scenes && ln -sfn "$PWD/.device/scenes/sibenik" ../shared/scenes/sibenik
R=$OUT/mpi; mkdir -p $R
{ nproc; lscpu | grep -E "Model name|^CPU\(s\)|Thread|Core|Socket"; mpirun --version | head -1; } > $R/machine.txt 2>&1
cat $R/machine.txt
S="render sibenik --width 384 --height 256 --spp 64 --seed 1"
for t in 1 2 4 8 16; do
  /usr/bin/time -f "threads $t: %e s wall, %U s user" illum $S --threads $t -o $R/threads$t.exr 2>&1 | grep -E "wall|error"
done
for n in 1 2 4 8 16; do
  /usr/bin/time -f "ranks $n: %e s wall, %U s user" mpirun --oversubscribe --bind-to none -np $n \
    "$(command -v illum)" $S -o $R/ranks$n.exr 2>&1 | grep -E "wall|rror" | head -3
done
for f in $R/threads*.exr $R/ranks*.exr; do cmp -s $f $R/threads1.exr && echo "$(basename $f) = threads1" || echo "$(basename $f) DIFFERS"; done
rm -f $R/*.exr
