#!/usr/bin/env python3
"""Which sun directions light the inside of Sibenik (the two suns of prt_vs_path.sh).

    bench/scripts/sibenik_sun_scan.py ILLUM [WORKDIR]

Build first: `cmake --build build/ci --target illum`. WORKDIR defaults to
${TMPDIR:-/tmp}/illum-bench/sibenik-sun-scan.

For 144 suns (elevation 15-85 deg by 10, azimuth by 20) renders the path tracer's direct
light only at 96x64 from the scene camera, 4 spp, exposure 0.3, and prints the share of
pixels whose red byte exceeds 20 (about 8 % of white), best last. Run from the repository
root (the OBJ is ../shared/scenes/sibenik); needs `convert FILE.png ppm:-`. ~2 min, 1 thread.
"""
import math
import os
import subprocess
import sys

if len(sys.argv) not in (2, 3):
    print("usage: sibenik_sun_scan.py ILLUM [WORKDIR]", file=sys.stderr)
    sys.exit(2)
illum = sys.argv[1]
if not (os.path.isfile(illum) and os.access(illum, os.X_OK)):
    print(f"sibenik_sun_scan.py: {illum} is not an executable", file=sys.stderr)
    sys.exit(2)
work = sys.argv[2] if len(sys.argv) > 2 else os.path.join(
    os.environ.get("TMPDIR", "/tmp"), "illum-bench", "sibenik-sun-scan")
os.makedirs(work, exist_ok=True)
obj = os.path.abspath("../shared/scenes/sibenik/sibenik.obj")
rows = []
for el in range(15, 90, 10):
    for az in range(0, 360, 20):
        e, a = math.radians(el), math.radians(az)
        d = ["%.3f" % c for c in (-math.cos(e) * math.cos(a), -math.sin(e), -math.cos(e) * math.sin(a))]
        scene, png = f"{work}/scan.illum.json", f"{work}/scan.png"
        with open(scene, "w") as f:
            f.write('{"name": "sibenik-scan", "meshes": [{"file": "%s", "hide": ["glas__glas"]}],'
                    ' "lights": [{"type": "sun", "direction": [%s], "irradiance": 10.0}],'
                    ' "camera": {"position": [22, 4, 0], "look_at": [-10, 5, 0], "up": [0, 1, 0],'
                    ' "fov_y_deg": 60}, "settings": {"width": 96, "height": 64, "spp": 4,'
                    ' "max_bounces": 1}}' % (obj, ",".join(d)))
        subprocess.run([illum, "render", scene, "-o", png, "--bounce-mode", "direct", "--threads", "1",
                        "--tonemap", "clamp", "--fixed-exposure", "--exposure", "0.3"],
                       check=True, capture_output=True)
        ppm = subprocess.run(["convert", png, "ppm:-"], check=True, capture_output=True).stdout
        px = ppm.split(b"\n", 3)[3]
        lit = sum(1 for i in range(0, len(px), 3) if px[i] > 20) / (len(px) // 3)
        rows.append((lit, el, az, ",".join(d)))
for lit, el, az, d in sorted(rows):
    print("%.4f  elevation %2d  azimuth %3d  --sun=%s,10" % (lit, el, az, d))
