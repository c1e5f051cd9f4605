#!/usr/bin/env python3
"""Recomputes `illum-bench raster`'s pass table from its JSON and the `illum frame --json`
files it read, with the bound model of bench/README.md: per rendering, the fixed cost of its
attachment set (one trivial full-screen layer's time minus the per-layer slope) plus the
slope times its passing layers; geometry (triangles x the culled-triangle time) and memory
(bytes / copy bandwidth) beside it; a pass's bound is the largest. Needs no GPU.

    bench/raster_model.py RASTER.json FRAME.json... > table.txt
"""
import json
import statistics
import sys


def main():
    if len(sys.argv) < 3:
        print(__doc__.strip().splitlines()[-1].strip(), file=sys.stderr)
        sys.exit(2)
    raster = json.load(open(sys.argv[1]))
    per_layer, fixed = {}, {}
    for b in raster["raster_bounds"]:
        one = statistics.median(b["one_layer_runs_ms"])
        slope = b["ms_per_layer"]
        per_layer[b["key"]] = slope
        fixed[b["key"]] = max(0.0, one - slope)
    tri_ms = raster["triangles"]["ms_per_triangle"]
    bytes_per_ms = raster["copy"]["gb_per_s"] * 1e6
    print(f"device {raster['device']} ({raster['driver']}); copy {raster['copy']['gb_per_s']:.1f} GB/s; "
          f"{1e-3 / tri_ms:.0f} Mtriangles/s")
    print(f"  {'attachment set, fragment':<52} {'fixed ms':>9} {'ms/layer':>9}")
    for k in sorted(per_layer):
        print(f"  {k:<52} {fixed[k]:9.4f} {per_layer[k]:9.4f}")
    for path in sys.argv[2:]:
        fr = json.load(open(path))
        print(f"\n{path}: {fr['scene']} {fr['width']}x{fr['height']}, {fr['technique']}, "
              f"frame {fr['frame_gpu_median_ms']:.4f} ms")
        print(f"  {'pass':<22} {'median':>8} {'bound':>8} {'ratio':>6}  {'binds':<9} passing layers")
        for p in fr["passes"]:
            w = p.get("work")
            med = p["median_ms"]
            if med < raster["dispatch_bound_ms"]:
                print(f"  {p['name']:<22} {med:8.4f} {'-':>8} {'-':>6}  dispatch")
                continue
            if not w:
                print(f"  {p['name']:<22} {med:8.4f} {'-':>8} {'-':>6}  none")
                continue
            ras, layers = 0.0, 0.0
            for f in w["fills"]:
                if f["depth"] in (5, 6):  # rejected, z-fail: listed, not bounded
                    continue
                ras += fixed[f["key"]] + per_layer[f["key"]] * f["count"]
                layers += f["count"]
            geo = w.get("triangles", 0.0) * tri_ms
            mem = w.get("bytes", 0.0) / bytes_per_ms
            bound = max(ras, geo, mem)
            binds = "raster" if bound == ras and ras > 0 else "geometry" if bound == geo and geo > 0 else "memory" if mem > 0 else "none"
            ratio = f"{med / bound:6.2f}" if bound > 0 else f"{'-':>6}"
            print(f"  {p['name']:<22} {med:8.4f} {bound:8.4f} {ratio}  {binds:<9} {layers:.2f}")


if __name__ == "__main__":
    main()
