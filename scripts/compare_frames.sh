#!/bin/bash
# Real-time frames from two `illum` binaries, compared byte for byte: Cornell and Sibenik,
# forward/deferred × none/map/vsm/volume, PNG and EXR (32 frames). For a change that must
# leave today's frames alone (an add-on switched off), run main's binary against the branch's.
#
#   scripts/compare_frames.sh ILLUM_A ILLUM_B OUTDIR [-- extra illum frame options]
#
# Prints each differing frame and "N of 32 frames byte-identical"; exit 1 if any differ or
# fail, 2 on bad arguments.
set -uo pipefail
if [ $# -lt 3 ]; then
  echo "usage: $0 ILLUM_A ILLUM_B OUTDIR [-- illum frame options]" >&2
  exit 2
fi
a=$1 b=$2 out=$3
shift 3
[ "${1:-}" = "--" ] && shift
for x in "$a" "$b"; do [ -x "$x" ] || { echo "$0: $x is not an executable" >&2; exit 2; }; done
mkdir -p "$out" || exit 2
n=0 same=0
for scene in cornell sibenik; do
  for t in forward deferred; do
    for s in none map vsm volume; do
      for ext in png exr; do
        name=$scene-$t-$s.$ext
        opts=(frame "$scene" --technique "$t" --shadows "$s" --width 96 --height 64
              -p shadow_resolution=256 "$@")
        "$a" "${opts[@]}" -o "$out/a-$name" > /dev/null 2>&1
        "$b" "${opts[@]}" -o "$out/b-$name" > /dev/null 2>&1
        n=$((n + 1))
        if [ -f "$out/a-$name" ] && cmp -s "$out/a-$name" "$out/b-$name"; then
          same=$((same + 1))
        else
          echo "differs or missing: $name"
        fi
      done
    done
  done
done
echo "$same of $n frames byte-identical"
[ "$same" -eq "$n" ]
