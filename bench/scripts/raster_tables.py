#!/usr/bin/env python3
"""Markdown tables of an `illum-bench raster` run over the frame matrix of raster_bounds.sh:
per scene, the frame GPU ms of each size and pipeline (shadow maps every frame / cached), and
each raster pass beside its bound (median ms / bound ms (ratio, what binds), maps every frame).
With a second raster.json (BASE, the same matrix with another `illum`) the frame table shows
BASE → RASTER. Needs no GPU.

    bench/scripts/raster_tables.py RASTER.json [BASE.json] > tables.md

The frame files must be named SCENE-WxH-PIPELINE-{every,cached}.json (raster_bounds.sh does).
Bad input: one line on stderr, exit 2.
"""
import json
import re
import sys

RASTER = ("cascades", "shadow_maps", "depth_prepass", "visibility", "gbuffer", "forward")
PIPELINES = ("visibility", "deferred", "forward")


def fail(message):
    print(f"raster_tables.py: {message}", file=sys.stderr)
    sys.exit(2)


def load(path):
    try:
        with open(path) as f:
            d = json.load(f)
    except (OSError, ValueError) as e:
        fail(f"{path}: {e}")
    out = {}
    for fr in d.get("frames", []):
        m = re.search(r"(\w+)-(\d+x\d+)-(\w+)-(every|cached)\.json$", fr.get("file", ""))
        if m:
            out[m.groups()] = fr
    if not out:
        fail(f"{path}: no frame named SCENE-WxH-PIPELINE-every|cached.json")
    return out


def main():
    if len(sys.argv) not in (2, 3):
        print("usage: raster_tables.py RASTER.json [BASE.json]", file=sys.stderr)
        sys.exit(2)
    new = load(sys.argv[1])
    base = load(sys.argv[2]) if len(sys.argv) == 3 else None
    scenes = sorted({k[0] for k in new}, key=lambda s: (s != "sibenik", s))
    for scene in scenes:
        sizes = sorted({k[1] for k in new if k[0] == scene}, key=lambda s: int(s.split("x")[0]))
        pipes = [p for p in PIPELINES if any(k[0] == scene and k[2] == p for k in new)]
        arrow = ", base → this run" if base else ""
        print(f"\n{scene}: frame GPU ms, maps every frame / cached{arrow}\n")
        print("| size | " + " | ".join(pipes) + " |\n| --- |" + " --- |" * len(pipes))
        for s in sizes:
            row = [s.replace("x", "×")]
            for p in pipes:
                def cell(runs):
                    v = [runs.get((scene, s, p, k), {}).get("frame_gpu_median_ms") for k in ("every", "cached")]
                    return " / ".join("—" if x is None else f"{x:.3f}" for x in v)
                row.append(f"{cell(base)} → {cell(new)}" if base else cell(new))
            print("| " + " | ".join(row) + " |")
        print(f"\n{scene}: raster passes, median ms / bound ms (ratio, what binds), maps every frame\n")
        print("| pass | " + " | ".join(s.replace("x", "×") for s in sizes) + " |\n| --- |" + " --- |" * len(sizes))
        for name in RASTER:
            row, seen = [f"`{name}`"], False
            for s in sizes:
                cells = [(q["median_ms"], q.get("bound_ms"), q.get("ratio"), q.get("bound"))
                         for p in pipes for q in new.get((scene, s, p, "every"), {}).get("passes", [])
                         if q["name"] == name and q.get("depth") == 0 and q.get("ratio")]
                if not cells:
                    row.append("—")
                    continue
                seen = True
                ms, rs = [c[0] for c in cells], [c[2] for c in cells]
                span = lambda v, f: f"{min(v):{f}}" if f"{min(v):{f}}" == f"{max(v):{f}}" else f"{min(v):{f}}–{max(v):{f}}"
                row.append(f"{span(ms, '.3f')} / {cells[0][1]:.3f} ({span(rs, '.2f')}, {cells[0][3]})")
            if seen:
                print("| " + " | ".join(row) + " |")
        worst = max(((q["ratio"], q["name"], "-".join(k[1:])) for k, fr in new.items() if k[0] == scene
                     for q in fr["passes"] if q.get("depth") == 0 and q["name"] in RASTER and q.get("ratio")),
                    default=None)
        if worst:
            print(f"\nlargest raster ratio ({scene}, every frame of the run): {worst[0]:.3f} {worst[1]} ({worst[2]})")


if __name__ == "__main__":
    main()
