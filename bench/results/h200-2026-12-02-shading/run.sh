#!/bin/bash
# The shading bound on the H200: the quads run (bench/results/h200-2026-12-02-quads/run.sh:
# Sibenik and Cornell × SIZES × PIPELINES × {maps every frame, cached} through
# bench/raster_bounds.sh), whose `illum frame --json` now also times the forward pass's
# lighting as one full-screen pass over a G-buffer of the same view, and whose
# `illum-bench raster` prints it as the `shading bound ms` column; then every forward pass's
# shading bound in detail (full-screen time, covered pixels, lanes a pixel, fixed cost,
# G-buffer reads at the copy bandwidth).
#   bash bench/results/h200-2026-12-02-shading/run.sh NAME "SIZES" "PIPELINES" (from the
#   repository root, the bundle in .device; this folder: shading1 "960x540 1920x1080 3840x2160"
#   "forward deferred visibility")
set -u
name=$1
bash "$(dirname "$0")/../h200-2026-12-02-quads/run.sh" "$@"
python3 - /tmp/r/$name/raster.json <<'PY' | tee /tmp/r/$name/shading.txt
import json, sys
d = json.load(open(sys.argv[1]))
print(f"{d['device']}; copy {d['copy']['gb_per_s']:.0f} GB/s")
print("frame | forward ms | shading bound ms | ratio | binds | full-screen ms | pixels | lanes/pixel | fixed ms | G-buffer reads ms")
for f in d["frames"]:
    for p in f["passes"]:
        if "shading" in p:
            s = p["shading"]
            print(f"{f['file'].split('/')[-1]} | {p['median_ms']:.3f} | {p['shading_bound_ms']:.3f} | "
                  f"{p['ratio']:.2f} | {p['bound']} | {s['full_screen_ms']:.3f} | {s['pixels']:.0f} | "
                  f"{s['lanes_per_pixel']:.3f} | {s['fixed_ms']:.3f} | {s['input_ms']:.4f}")
PY
cp /tmp/r/$name/shading.txt $OUT/ 2>/dev/null || true
