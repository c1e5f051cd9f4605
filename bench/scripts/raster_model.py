#!/usr/bin/env python3
"""Recomputes `illum-bench raster`'s pass table from its JSON and the `illum frame --json`
files it read, with the bound model of bench/README.md: per rendering, the fixed cost of its
attachment set (one trivial full-screen layer's time minus the per-layer slope) plus the
slope times its passing layers, rejected fragments at the slope of a rejected layer;
geometry (rasterized triangles x the setup time, the rest x the culled-triangle time);
mixed (the measured trivial passes of `mixed_bounds`, one per rendering, plus the culled
triangles and the rejected fragments); memory (bytes / copy bandwidth); shading (the timed
full-screen lighting of `work.shading`, its part above the attachment set's fixed cost
scaled by 4 x quads / covered pixels); a pass's bound is the largest. Needs no GPU.

    bench/scripts/raster_model.py RASTER.json FRAME.json... > table.txt
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
    setup_ms = max(tri_ms, raster["setup_triangles"]["ms_per_triangle"])
    mixed = {(m["key"], m["triangles"], round(m["layers"], 4)): m["ms"]
             for m in raster.get("mixed_bounds", [])}
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
            ras, layers, rejected_ms = 0.0, 0.0, 0.0
            renderings = {}
            for f in w["fills"]:
                if f["depth"] in (5, 6):  # rejected, z-fail: the rejected layer's slope only
                    rejected_ms += per_layer[f["key"]] * f["count"]
                    continue
                ras += fixed[f["key"]] + per_layer[f["key"]] * f["count"]
                layers += f["count"]
                n, c = renderings.get(f["key"], (0, 0.0))
                renderings[f["key"]] = (n + 1, c + f["count"])
            ras += rejected_ms
            triangles = w.get("triangles", 0.0)
            rasterized = min(triangles, w.get("rasterized_triangles", 0.0))
            geo = (triangles - rasterized) * tri_ms + rasterized * setup_ms
            mix = 0.0
            if rasterized >= 1.0:
                mix = rejected_ms + (triangles - rasterized) * tri_ms
                for key, (n, c) in renderings.items():
                    if layers <= 0.0 or c <= 0.0:
                        mix += n * fixed[key]
                        continue
                    each = min(max(round(rasterized * c / layers / n), 1), 16777216)
                    mix += n * mixed[(key, each, round(c / n, 4))]
            mem = w.get("bytes", 0.0) / bytes_per_ms
            shade = 0.0
            sh = w.get("shading")
            if sh and sh["pixels"] > 0:
                full = statistics.median(sh["runs_ms"])
                lanes = 4.0 * w["quads"] / sh["pixels"] if w.get("quads", -1) > 0 else 1.0
                set_fixed = min(full, max([fixed[k] for k in renderings] or [0.0]))
                shade = set_fixed + (full - set_fixed) * lanes
            bound = max(ras, geo, mix, mem, shade)
            binds = ("shading" if bound == shade and shade > 0
                     else "raster" if bound == ras and ras > 0 else "geometry" if bound == geo and geo > 0
                     else "mixed" if bound == mix and mix > 0 else "memory" if mem > 0 else "none")
            ratio = f"{med / bound:6.2f}" if bound > 0 else f"{'-':>6}"
            print(f"  {p['name']:<22} {med:8.4f} {bound:8.4f} {ratio}  {binds:<9} {layers:.2f}")


if __name__ == "__main__":
    main()
