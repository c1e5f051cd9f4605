#!/usr/bin/env bash
# Fuzzes one of illum's readers on one core:   scripts/fuzz.sh TARGET SECONDS
#   TARGET: obj, gltf, illum_json, image or lightmap (fuzz/README.md says what each covers)
# Builds fuzz_TARGET in the asan preset's tree (clang, ASan + UBSan), then runs libFuzzer for
# SECONDS from the committed seeds (fuzz/corpus/TARGET), the regression inputs and, when
# ../shared/scenes is beside the checkout, bigger seeds made from the shared scenes. The corpus
# it grows and its findings (crash-*, timeout-*, oom-*, leak-*) go to
# build/asan/fuzz/work/TARGET/. It stops at the first finding; KEEP_GOING=1 goes on (libFuzzer's
# fork mode with one worker) to collect several in one run. FUZZ_BIN=DIR runs DIR/fuzz_TARGET
# and builds nothing (a copy of the binaries, fuzzed while the tree is being rebuilt).
# FUZZ_ARGS adds libFuzzer flags after the usual ones (fuzz/flags.sh), e.g. FUZZ_ARGS=-timeout=2
# so a known hang costs less time per hit.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
targets="obj gltf illum_json image lightmap"
usage() { echo "usage: scripts/fuzz.sh TARGET SECONDS  (TARGET: ${targets// /, })" >&2; }
if (($# != 2)) || [[ " $targets " != *" $1 "* ]] || ! [[ $2 =~ ^[1-9][0-9]*$ ]]; then
  usage
  exit 2
fi
target=$1 seconds=$2
cd "$root"
if [[ -n ${FUZZ_BIN:-} ]]; then
  binary=$FUZZ_BIN/fuzz_$target
else
  [[ -f build/asan/CMakeCache.txt ]] || cmake --preset asan >/dev/null
  cmake --build --preset asan --target "fuzz_$target" >/dev/null
  binary=build/asan/bin/fuzz_$target
fi

work=build/asan/fuzz/work/$target
shared=$root/../shared/scenes
mkdir -p "$work/corpus" "$work/findings"
rm -rf "$work/shared-seeds"
mkdir -p "$work/shared-seeds"
seeds=(fuzz/corpus/"$target")
[[ -d fuzz/regressions/$target ]] && seeds+=(fuzz/regressions/"$target")

# Seeds from the shared scenes, cut to the 64 KiB inputs are limited to (fuzz/flags.sh) and
# renamed to the files the harness writes (fuzz_support.h: kNextFile, companions).
next_file=$'\n--illum-fuzz-next-file--\n'
obj_with_mtl() {  # OBJ (first 60 kB, mtllib → scene.mtl), separator, MTL
  { head -c 60000 "$1" | sed 's/^mtllib .*/mtllib scene.mtl/'; printf '%s' "$next_file"; cat "$2"; }
}
if [[ -d $shared ]]; then
  case $target in
    obj)
      obj_with_mtl "$shared/cornell-box/cornell_box.obj" "$shared/cornell-box/cornell_box.mtl" \
        >"$work/shared-seeds/cornell"
      obj_with_mtl "$shared/caustics/caustics.obj" "$shared/caustics/caustics.mtl" \
        >"$work/shared-seeds/caustics"
      obj_with_mtl "$shared/sibenik/sibenik.obj" "$shared/sibenik/sibenik.mtl" \
        >"$work/shared-seeds/sibenik"
      cp "$shared/bunny/bunny_res4.obj" "$work/shared-seeds/bunny_res4"
      ;;
    image)
      # The Sibenik JPEGs cut to 64 KiB (header, tables, part of the scan); the environment maps
      # cut to the whole scanlines that fit, header adjusted (make_seeds.py: hdr_first_rows),
      # since a cut scanline makes today's HDR reader hang (fuzz/README.md: findings).
      for f in "$shared"/sibenik/*.jpg; do
        head -c 65536 "$f" >"$work/shared-seeds/$(basename "$f")"
      done
      python3 - "$work/shared-seeds" "$shared"/envmaps/*.hdr <<'EOF'
import os, sys
sys.path.insert(0, "fuzz")
from make_seeds import hdr_first_rows
for path in sys.argv[2:]:
    data = open(path, "rb").read()
    rows = 1
    while len(hdr_first_rows(data, rows + 1)) <= 65536:
        rows += 1
    open(os.path.join(sys.argv[1], os.path.basename(path)), "wb").write(hdr_first_rows(data, rows))
EOF
      ;;
    gltf)
      # Sponza's JSON (98 kB minified) cut to its first 12 primitives and what they use; its
      # buffer becomes the 44-byte companion, so every buffer view overruns it.
      python3 - "$shared/sponza/glTF/Sponza.gltf" "$work/shared-seeds/sponza.gltf" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
d["meshes"][0]["primitives"] = d["meshes"][0]["primitives"][:12]
used = sorted({i for p in d["meshes"][0]["primitives"]
               for i in list(p["attributes"].values()) + [p.get("indices", 0)]})
remap = {old: new for new, old in enumerate(used)}
d["accessors"] = [d["accessors"][i] for i in used]
for p in d["meshes"][0]["primitives"]:
    p["attributes"] = {k: remap[v] for k, v in p["attributes"].items()}
    if "indices" in p:
        p["indices"] = remap[p["indices"]]
d["buffers"][0] = {"uri": "buffer.bin", "byteLength": 44}
json.dump(d, open(sys.argv[2], "w"), separators=(",", ":"))
EOF
      ;;
  esac
else
  echo "fuzz: $shared not found; seeding from fuzz/corpus/$target only"
fi
if [[ $target == illum_json ]]; then  # the built-in scene files, their meshes → companions
  for f in data/scenes/*/*.illum.json; do
    sed -E 's/"file": *"[^"]*\.obj"/"file": "mesh.obj"/' "$f" >"$work/shared-seeds/$(basename "$f")"
  done
fi
compgen -G "$work/shared-seeds/*" >/dev/null && seeds+=("$work/shared-seeds")

source fuzz/flags.sh
args=("${illum_fuzz_flags[@]}" -max_total_time="$seconds" -dict="fuzz/dicts/$target.dict"
      -artifact_prefix="$work/findings/" -print_final_stats=1)
[[ ${KEEP_GOING:-0} == 1 ]] && args+=(-fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1)
read -r -a extra <<<"${FUZZ_ARGS:-}"
args+=("${extra[@]}")
echo "fuzz: $target for $seconds s; corpus $work/corpus; findings $work/findings/"
exec "$binary" "${args[@]}" "$work/corpus" "${seeds[@]}"
