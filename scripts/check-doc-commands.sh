#!/usr/bin/env bash
# Runs every shell command that README.md and docs/*.md show, as written, against a built
# tree, and reports the ones that fail.
#
#   scripts/check-doc-commands.sh [--build DIR] [--timeout SECONDS] [--list] [FILE.md ...]
#
# Commands are the lines of fenced blocks (```sh, ```bash, ```console or no language) whose
# first word is a program the docs run (illum, illum-bench, mpirun, cmake, ctest, or a path
# under scripts/, build/, bench/); other lines of such blocks are shown output. A line ending
# in `\` continues on the next. Each page's commands run in order in a folder of their own
# under $TMPDIR (one command may read what an earlier one wrote), with DIR/bin first on PATH,
# bench/, data/ and scripts/ linked to the checkout's, build/release and build/ci linked to DIR, and
# an empty docs/images (so a benchmark that writes the docs' images leaves the checkout's
# alone). The docs' placeholder scene `scene.gltf` is an unlit 2 m floor quad in one file.
# Without a display, `illum view` runs under xvfb-run.
#
# A block is skipped, and listed with its reason, when the line before its fence is
#   <!-- doc-commands: skip REASON -->
# (a window, several machines, a build of its own, a rewrite of docs/images, ...).
# --list prints what would run and what is skipped, and runs nothing. Exit status: 0 when
# every command ran with status 0, 1 otherwise, 2 for bad arguments.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=""
timeout_s=3600
list=0
files=()
while (($#)); do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --timeout) timeout_s=$2; shift 2 ;;
    --list) list=1; shift ;;
    -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
    -*) echo "check-doc-commands: unknown option $1" >&2; exit 2 ;;
    *) files+=("$1"); shift ;;
  esac
done
if [[ -z $build ]]; then
  for b in build/release build/ci; do
    if [[ -x $root/$b/bin/illum ]]; then build=$root/$b; break; fi
  done
fi
build=$(cd "${build:-.}" 2>/dev/null && pwd || true)
if [[ ! -x $build/bin/illum ]]; then
  echo "check-doc-commands: no bin/illum under '${build}' (give --build DIR)" >&2
  exit 2
fi
if ((${#files[@]} == 0)); then
  files=("$root/README.md")
  for f in "$root"/docs/*.md; do files+=("$f"); done
fi

# One record per command: FILE, LINE, run|skip, REASON, COMMAND, separated by \x1f (a tab is
# whitespace to `read`, which would merge the empty REASON of a command that runs).
extract() {
  python3 - "$@" <<'PY'
import re, sys
programs = ("illum", "illum-bench", "mpirun", "cmake", "ctest")
prefixes = ("scripts/", "build/", "bench/")
for path in sys.argv[1:]:
    lines = open(path, encoding="utf-8").read().split("\n")
    i, skip = 0, None
    while i < len(lines):
        line = lines[i]
        m = re.match(r"\s*<!--\s*doc-commands:\s*skip\s+(.*?)\s*-->", line)
        if m:
            skip = m.group(1)
            i += 1
            continue
        fence = re.match(r"\s*```(\S*)", line)
        if not fence:
            if line.strip():
                skip = None
            i += 1
            continue
        lang, i = fence.group(1), i + 1
        shell = lang in ("", "sh", "bash", "console", "shell")
        while i < len(lines) and not re.match(r"\s*```", lines[i]):
            start, cmd = i + 1, lines[i].strip()
            while cmd.endswith("\\") and i + 1 < len(lines):
                i += 1
                cmd = cmd[:-1].rstrip() + " " + lines[i].strip()
            i += 1
            if cmd.startswith("$ "):
                cmd = cmd[2:]
            words = cmd.split()
            if not shell or not words:
                continue
            if words[0] not in programs and not words[0].startswith(prefixes):
                continue
            state = "skip" if skip else "run"
            print("\x1f".join([path, str(start), state, skip or "", cmd]))
        i += 1
        skip = None
PY
}

# The docs' placeholder scene.gltf: a 2 m floor quad facing up, its buffer a data URI.
scene_gltf() {
  python3 - <<'PY'
import base64, json, struct
data = struct.pack("<12f", -1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1) + struct.pack("<6H", 0, 2, 1, 0, 3, 2)
print(json.dumps({
    "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    "buffers": [{"byteLength": len(data),
                 "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                    {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                   "min": [-1, 0, -1], "max": [1, 0, 1]},
                  {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}]}))
PY
}

records=$(extract "${files[@]}")
if ((list)); then
  printf '%s\n' "$records" | awk -F'\x1f' -v root="$root/" '{
    sub(root, "", $1)
    if ($3 == "skip") printf "SKIP %s:%s  %s  [%s]\n", $1, $2, $5, $4
    else printf "RUN  %s:%s  %s\n", $1, $2, $5 }'
  exit 0
fi

work=$(mktemp -d "${TMPDIR:-/tmp}/illum-doc-commands.XXXXXX")
echo "check-doc-commands: illum from $build/bin, working in $work"
export PATH="$build/bin:$PATH"
# Open MPI refuses root without these (docs/distributed.md); containers and CI run as root.
if [[ $(id -u) -eq 0 ]]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
failures=0 ran=0 skipped=0
summary=()
while IFS=$'\x1f' read -r file line state reason cmd; do
  rel=${file#"$root/"}
  if [[ $state == skip ]]; then
    skipped=$((skipped + 1))
    summary+=("SKIP  $rel:$line  $cmd  [$reason]")
    continue
  fi
  page="$work/$(basename "$file" .md)"
  if [[ ! -d $page ]]; then
    mkdir -p "$page"
    mkdir -p "$page/build" "$page/docs/images"
    for d in bench data scripts; do ln -s "$root/$d" "$page/$d"; done
    for d in release ci; do ln -s "$build" "$page/build/$d"; done
    scene_gltf >"$page/scene.gltf"
  fi
  ran=$((ran + 1))
  start=$(date +%s%N)
  set +e
  run=$cmd
  if [[ $cmd == "illum view "* && -z ${DISPLAY:-} ]]; then run="xvfb-run -a $cmd"; fi
  (cd "$page" && timeout "$timeout_s" bash -c "$run") >"$page/out-$line.txt" 2>&1 </dev/null
  status=$?
  set -e
  ms=$((($(date +%s%N) - start) / 1000000))
  seconds="$((ms / 1000)).$((ms % 1000 / 100))"
  if ((status == 0)); then
    result="ok    $rel:$line  ${seconds} s  $cmd"
  else
    failures=$((failures + 1))
    result="FAIL  $rel:$line  exit $status after ${seconds} s  $cmd
      $(tail -n 3 "$page/out-$line.txt" | tr '\n' ' ' | cut -c1-400)"
  fi
  summary+=("$result")
  echo "$result"
done <<<"$records"

echo
printf '%s\n' "${summary[@]}"
echo "check-doc-commands: $ran run, $failures failed, $skipped skipped (outputs in $work)"
((failures == 0))
