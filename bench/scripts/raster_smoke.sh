#!/bin/sh
# ctest illum_bench.raster_smoke: tiny lavapipe frames of every frame pipeline with shadow
# maps, and of the deferred pipeline with stencil volumes, through `illum-bench raster`,
# validation on. Fails when a row is missing, a pass with work has no bound or ratio, the
# passing and rejected fragments or the volumes' z-fail fragments were not counted, the
# forward pass has no shading bound or it is scaled wrongly, or anything was validated.
#   bench/scripts/raster_smoke.sh ILLUM ILLUM_BENCH [OUTDIR]
# (build/ci/bin/illum and illum-bench; OUTDIR, emptied first, defaults to
# ${TMPDIR:-/tmp}/illum-bench/raster-smoke). Exit 2 on bad arguments.
set -eu
if [ $# -lt 2 ] || [ $# -gt 3 ]; then
  echo "usage: $0 ILLUM ILLUM_BENCH [OUTDIR]" >&2
  exit 2
fi
illum=$1 bench=$2 out=${3:-${TMPDIR:-/tmp}/illum-bench/raster-smoke}
for x in "$illum" "$bench"; do
  [ -x "$x" ] || { echo "$0: $x is not an executable" >&2; exit 2; }
done
rm -rf "$out"
mkdir -p "$out"
export ILLUM_VULKAN_VALIDATION=1
run() {
  name=$1
  shift
  "$illum" frame cornell --width 48 --height 32 --frames 2 --warmup 1 -p shadow_resolution=64 \
    --json "$out/$name.json" "$@" > "$out/$name.txt"
}
run forward-map --technique forward --shadows map
run deferred-map --technique deferred --shadows map
run deferred-volume --technique deferred --shadows volume
run visibility-map --technique visibility --shadows map
# lavapipe counts no passing fragments, so the mixed bound's grids (passing layers and
# rasterized triangles drawn together) are exercised on a synthetic frame: the deferred
# frame's pre-pass given 1.5 passing layers of 200 rasterized triangles, in 720 quads
# (1.25 × the samples: the quad bound draws 1.875 layers). A copy whose quad count saw other
# samples than the occlusion query must be refused.
python3 - "$out/deferred-map.json" "$out/synthetic.json" <<'PY'
import copy, json, sys
fr = json.load(open(sys.argv[1]))
fr["technique"] = "synthetic"
for p in fr["passes"]:
    if p["name"] == "depth_prepass":
        passing = copy.deepcopy(p["work"]["fills"][0])
        passing["depth"], passing["count"] = 1, 1.5
        p["work"]["fills"].append(passing)
        p["work"]["rasterized_triangles"] = p["work"]["triangles"] = 200.0
        p["work"]["quads"], p["work"]["quad_samples"] = 720.0, 1.5 * 48 * 32
json.dump(fr, open(sys.argv[2], "w"))
for p in fr["passes"]:
    if p["name"] == "depth_prepass":
        p["work"]["quad_samples"] = 1.5 * 48 * 32 - 7
json.dump(fr, open(sys.argv[2].replace("synthetic", "mismatch"), "w"))
PY
# The shading bound's scaling on a synthetic copy of the forward frame: a full-screen lighting
# of 2 ms over all 1536 pixels, 576 quads (1.5 lanes a pixel) and one passing layer of the
# forward pass's attachments (so its fixed cost f is measured): 2 ms scales to f + (2 − f) × 1.5.
# A copy whose bound shaded more pixels than the pass passed samples must be refused.
python3 - "$out/forward-map.json" "$out/shading.json" <<'PY'
import copy, json, sys
fr = json.load(open(sys.argv[1]))
fr["technique"] = "synthetic-shading"
for p in fr["passes"]:
    if p["name"] == "forward":
        w = p["work"]
        assert "shading" in w, w
        passing = copy.deepcopy(w["fills"][0])
        passing["depth"], passing["count"] = 2, 1.0
        w["fills"].append(passing)
        w["quads"], w["quad_samples"] = 576.0, 1536.0
        w["shading"].update(runs_ms=[2.0, 2.0, 2.0], pixels=1536.0, input_bytes=32.0 * 1536)
json.dump(fr, open(sys.argv[2], "w"))
for p in fr["passes"]:
    if p["name"] == "forward":
        p["work"]["shading"]["pixels"] = 2000.0
json.dump(fr, open(sys.argv[2].replace("shading", "overshaded"), "w"))
PY
mv "$out/overshaded.json" "$out/overshaded.json.bad"
if "$bench" raster "$out/overshaded.json.bad" --repeats 1 --bandwidth-mib 1 > "$out/overshaded.txt" 2>&1; then
  echo "illum-bench raster accepted a shading bound over more pixels than the pass shaded" >&2
  exit 1
fi
grep -q "the shading bound shaded 2000 pixels, the pass passed only 1536 samples" "$out/overshaded.txt"
mv "$out/mismatch.json" "$out/mismatch.json.bad"
if "$bench" raster "$out/mismatch.json.bad" --repeats 1 --bandwidth-mib 1 > "$out/mismatch.txt" 2>&1; then
  echo "illum-bench raster accepted a quad count that disagrees with the occlusion query" >&2
  exit 1
fi
grep -q "the quad count saw 2297 passing samples, the occlusion query 2304" "$out/mismatch.txt"
"$bench" raster "$out"/*.json --repeats 3 --bandwidth-mib 4 --json "$out/raster.json" > "$out/raster.txt"
python3 - "$out/raster.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d["validation_messages"] == 0, "validation messages in illum-bench raster"
assert d["copy"]["gb_per_s"] > 0, "no copy bandwidth"
assert d["raster_bounds"] and all(b["ms_per_layer"] >= 0 for b in d["raster_bounds"]), d["raster_bounds"]
keys = [b["key"] for b in d["raster_bounds"]]
# On lavapipe the scene draws' fragments all count as rejected (bench/README.md); the
# stencil-volume lighting's layer is a passing configuration measured here.
assert "48x32 rgba16f+d32s8 stencil-test blend" in [k.replace("d24s8", "d32s8") for k in keys], keys
names = {}
for f in d["frames"]:
    for p in f["passes"]:
        names.setdefault(f["technique"] + "/" + f["shadows"], []).append(p)
        if p["bound"] in ("raster", "memory", "geometry", "mixed", "quads", "nested"):
            assert p["bound_ms"] > 0 and p["ratio"] > 0, p
for run, passes in names.items():
    got = {p["name"]: p for p in passes}
    assert run.startswith("visibility") or "depth_prepass" in got, (run, list(got))
def listed(run, name, want):
    got = [p for p in names[run] if p["name"] == name]
    assert got and any(want in w.replace("d24s8", "d32s8") for w in got[0]["work"]), (run, name, want, got)
listed("deferred/map", "depth_prepass", "48x32 d32s8 reject")
listed("deferred/map", "gbuffer", "48x32 rgba16f+rgba16f+rgba8+rgba16f+d32s8 reject")
listed("forward/map", "forward", "48x32 rgba16f+d32s8 reject")
listed("forward/map", "shadow_maps", "64x64 r32f+d32 reject")
listed("visibility/map", "visibility", "48x32 r32ui+d32s8 reject")
vol = [p for p in names["deferred/volume"] if p["name"] == "stencil_volumes"]
assert vol and any("zfail" in w for w in vol[0]["work"]), vol
vis = {p["name"]: p for p in names["visibility/map"]}
assert "depth_prepass" not in vis, list(vis)
assert any("r32ui" in w for w in vis["visibility"]["work"]), vis["visibility"]
assert vis["visibility_resolve"]["bound"] in ("memory", "dispatch"), vis["visibility_resolve"]
assert any("triangles" in w for w in vis["visibility"]["work"]), vis["visibility"]
assert d["triangles"]["ms_per_triangle"] > 0, d["triangles"]
assert d["setup_triangles"]["ms_per_triangle"] > 0, d["setup_triangles"]
# One-sample triangles (each checked by its occlusion query inside the bench) into every
# depth-only attachment set: the pre-pass's.
cover = {c["key"].replace("d24s8", "d32s8"): c for c in d["covering_triangles"]}
assert "48x32 d32s8 write" in cover and all(c["ms_per_triangle"] > 0 for c in cover.values()), cover
for n in ["forward-map", "deferred-map", "deferred-volume", "visibility-map"]:
    fr = json.load(open(sys.argv[1].replace("raster.json", n + ".json")))
    assert fr["validation_messages"] == 0, n
    # Scene draws count the triangles that left clipping (pipeline statistics), except in
    # lavapipe frames with stencil volumes (no queries around depth-tested draws there).
    # Clipping may split a triangle, so the count can exceed the triangles submitted (the
    # bench charges at most those).
    for p in fr["passes"]:
        w = p.get("work", {})
        if p["name"] in ("depth_prepass", "visibility", "shadow_maps", "cascades"):
            if n == "deferred-volume":
                assert "rasterized_triangles" not in w, (n, p)
            else:
                assert w["rasterized_triangles"] > 0 and w["triangles"] > 0, (n, p)
# (The synthetic-shading frame's passing layer adds grids of its own, on the forward pass's set.)
grids = [g for g in d["mixed_bounds"] if g["key"].replace("d24s8", "d32s8") == "48x32 d32s8 write"]
assert [(g["triangles"], g["layers"]) for g in grids] == [(200, 1.5), (200, 1.875)], grids
assert grids[0]["ms"] > 0 and grids[1]["ms"] > 0, grids
syn = {p["name"]: p for p in names["synthetic/map"]}
assert any(w.startswith("mixed ") for w in syn["depth_prepass"]["work"]), syn["depth_prepass"]
assert any(w.startswith("quads ") and "720 quads, 1.250×" in w
           for w in syn["depth_prepass"]["work"]), syn["depth_prepass"]
assert syn["depth_prepass"]["bound_ms"] >= grids[1]["ms"], syn["depth_prepass"]
# The shading bound: measured for the forward pass (its lighting over the same view), part of
# its bound, its G-buffer reads priced; scaled by 4 × quads / pixels above the fixed cost.
fwd = {p["name"]: p for p in names["forward/map"]}["forward"]
assert fwd["shading_bound_ms"] > 0 and fwd["bound_ms"] >= fwd["shading_bound_ms"], fwd
assert fwd["shading"]["pixels"] > 0 and fwd["shading"]["input_ms"] > 0, fwd
for run in names:
    if not run.startswith("forward") and not run.startswith("synthetic-shading"):
        assert all("shading_bound_ms" not in p for p in names[run]), run
syn = {p["name"]: p for p in names["synthetic-shading/map"]}["forward"]
fixed = {b["key"]: b["fixed_ms"] for b in d["raster_bounds"]}["48x32 rgba16f+d32s8 test"]
want = fixed + (2.0 - fixed) * 1.5
assert abs(syn["shading_bound_ms"] - want) < 1e-9, (syn["shading_bound_ms"], want, fixed)
assert syn["shading"]["lanes_per_pixel"] == 1.5 and syn["bound"] == "shading", syn
print("raster smoke ok:", len(keys), "bounds,", sum(len(v) for v in names.values()), "passes")
PY
