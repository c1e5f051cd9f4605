#!/bin/sh
# The path tracer against Blender Cycles at equal noise (bench/results/path-tracer.md,
# "Against Blender Cycles"): `illum-bench converge` on Cornell 256×256 (1024-spp references)
# and Sibenik 192×128 (2048-spp references) at 16, 64 and 256 spp, REPS times (default 1),
# one scene after the other. Run it with nothing else on the machine: the figure is a ratio of
# times.
#
#   bench/scripts/converge.sh ILLUM_BENCH [OUTDIR]
#
# Build first: `cmake --build build/ci --target illum-bench`; needs `blender` (Cycles 3.4.1 was
# the peer of the table) on PATH, or PEER=none for illum alone. Run from the repository root
# (Sibenik is in ../shared/scenes). OUTDIR defaults to ${TMPDIR:-/tmp}/illum-bench/converge;
# the references are cached there (reference-RENDERER-SCENE-WxH-bB-Nspp.exr) and reused by the
# next run, so only the first run renders them (about 9 minutes on 2 cores; with them cached,
# about 3). Writes OUTDIR/SCENE-N.json, the renders and the plots (converge-SCENE-*.png), and
# prints the load before each scene. Exit 2 on bad arguments.
set -eu
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
  echo "usage: $0 ILLUM_BENCH [OUTDIR]" >&2
  exit 2
fi
bench=$1 out=${2:-${TMPDIR:-/tmp}/illum-bench/converge}
[ -x "$bench" ] || { echo "$0: $bench is not an executable" >&2; exit 2; }
peer=${PEER:-cycles}
mkdir -p "$out"
rep=1
while [ "$rep" -le "${REPS:-1}" ]; do
  echo "=== run $rep cornell $(date -u) load: $(cat /proc/loadavg)"
  "$bench" converge cornell --width 256 --height 256 --spp 16,64,256 --reference-spp 1024 \
    --peer "$peer" --out "$out" --json "$out/cornell-$rep.json"
  echo "=== run $rep sibenik $(date -u) load: $(cat /proc/loadavg)"
  "$bench" converge sibenik --width 192 --height 128 --spp 16,64,256 --reference-spp 2048 \
    --peer "$peer" --out "$out" --json "$out/sibenik-$rep.json"
  rep=$((rep + 1))
done
echo "=== done $(date -u) load: $(cat /proc/loadavg)"
