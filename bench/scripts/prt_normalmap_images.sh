#!/bin/bash
# The normal-mapped PRT pictures of docs/prt.md ("Normal maps"): a 2 m plane carrying a
# tangent-space normal map of 4×4 domes, baked once with normal maps (S002 §5.7) and once
# with `-p normal_maps=false`, each relit under two low suns.
#
#   bench/scripts/prt_normalmap_images.sh ILLUM [OUTDIR]
#
# Build first: `cmake --build build/ci --target illum`. OUTDIR defaults to
# ${TMPDIR:-/tmp}/illum-bench/prt-normalmap; copy the PNGs to docs/images to update them.
#
# Writes OUTDIR/prt_normalmap_{sun_a,sun_b}_{on,off}.png and the scene it made
# (OUTDIR/scene/: OBJ, MTL, the normal map as a PNG written by Python's zlib).
set -euo pipefail
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
  echo "usage: $0 ILLUM [OUTDIR]" >&2
  exit 2
fi
illum=$1 out=${2:-${TMPDIR:-/tmp}/illum-bench/prt-normalmap}
[ -x "$illum" ] || { echo "$0: $illum is not an executable" >&2; exit 2; }
mkdir -p "$out/scene"
python3 - "$out/scene" <<'PY'
import math, struct, sys, zlib
d = sys.argv[1]
W = 128  # one dome per texture period, the plane shows 4×4 periods
rows = []
for row in range(W):
    line = bytearray([0])  # PNG filter: none
    for col in range(W):
        # Tangent space: +x along increasing u, +y along increasing v (v = 0 at the top row).
        dx, dy = (col + 0.5) / W - 0.5, (row + 0.5) / W - 0.5
        r = 0.42
        if dx * dx + dy * dy < r * r:
            m = (dx / r, dy / r, math.sqrt(max(r * r - dx * dx - dy * dy, 0.0)) / r)
        else:
            m = (0.0, 0.0, 1.0)
        n = math.sqrt(sum(c * c for c in m))
        line += bytes(int(round(255 * (0.5 * c / n + 0.5))) for c in m)
    rows.append(bytes(line))
def chunk(kind, data):
    c = struct.pack(">I", len(data)) + kind + data
    return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, W, 8, 2, 0, 0, 0))
png += chunk(b"IDAT", zlib.compress(b"".join(rows), 9)) + chunk(b"IEND", b"")
open(f"{d}/domes_n.png", "wb").write(png)
open(f"{d}/plane.mtl", "w").write("newmtl stone\nKd 0.6 0.6 0.6\nnorm domes_n.png\n")
open(f"{d}/plane.obj", "w").write(
    "mtllib plane.mtl\no plane\n"
    "v -1 0 1\nv 1 0 1\nv 1 0 -1\nv -1 0 -1\n"
    "vt 0 0\nvt 4 0\nvt 4 4\nvt 0 4\nvn 0 1 0\n"
    "usemtl stone\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n")
open(f"{d}/plane.illum.json", "w").write("""{
  "name": "normalmap-plane",
  "meshes": [{"file": "plane.obj"}],
  "lights": [{"type": "sun", "direction": [-1, -0.5, 0], "irradiance": 3}],
  "camera": {"position": [0, 1.7, 2.0], "look_at": [0, 0, 0.15], "up": [0, 1, 0], "fov_y_deg": 45},
  "settings": {"width": 320, "height": 240, "spp": 16}
}
""")
PY
scene=$out/scene/plane.illum.json
for maps in on off; do
  flag=true
  [ $maps = off ] && flag=false
  "$illum" bake "$scene" --kind prt --mode shadowed --bands 6 --resolution 256 --spp 256 \
    --seed 1 --threads 2 -p normal_maps=$flag -o "$out/prt_$maps"
  # Sun A grazes from +x, sun B from −z (the far side); both 20–27° high.
  "$illum" relight "$scene" --baked "$out/prt_$maps" --sun=-1,-0.36,0,3 --threads 2 \
    -o "$out/prt_normalmap_sun_a_$maps.png"
  "$illum" relight "$scene" --baked "$out/prt_$maps" --sun=0,-0.5,1,3 --threads 2 \
    -o "$out/prt_normalmap_sun_b_$maps.png"
done
