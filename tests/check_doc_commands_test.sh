#!/usr/bin/env bash
# scripts/check-doc-commands.sh on a page of its own: a command that succeeds is reported ok,
# one that fails is reported with its status and makes the run fail, a block after a skip
# marker is listed with its reason and not run, shown output lines are not commands.
#   bash check_doc_commands_test.sh SOURCE_DIR BUILD_DIR
set -u
src=${1:?usage: check_doc_commands_test.sh SOURCE_DIR BUILD_DIR}
build=${2:?usage: check_doc_commands_test.sh SOURCE_DIR BUILD_DIR}
work=$(mktemp -d "${TMPDIR:-/tmp}/illum-doc-commands-test.XXXXXX")
trap 'rm -rf "$work"' EXIT
fail() { echo "FAILED: $*"; echo "--- output:"; cat "$work/out.txt"; exit 1; }

cat >"$work/page.md" <<'MD'
# A page

```sh
illum info cornell          # runs
illum: shown output, not a command
illum info no-such-scene    # fails
```

<!-- doc-commands: skip opens a window -->
```sh
illum view cornell
```

```json
{"illum": "not shell"}
```
MD
TMPDIR=$work bash "$src/scripts/check-doc-commands.sh" --build "$build" "$work/page.md" \
  >"$work/out.txt" 2>&1
status=$?
((status == 1)) || fail "exit status $status, expected 1 (one command failed)"
grep -q '^ok    .*page.md:4 .*illum info cornell' "$work/out.txt" || fail "no ok line for line 4"
grep -q '^FAIL  .*page.md:6  exit 2 .*illum info no-such-scene' "$work/out.txt" ||
  fail "no FAIL line with exit 2 for line 6"
grep -q '^SKIP  .*page.md:11  illum view cornell  \[opens a window\]' "$work/out.txt" ||
  fail "no SKIP line with the marker's reason for line 11"
grep -q 'shown output' "$work/out.txt" && fail "an output line was run as a command"
grep -q ': 2 run, 1 failed, 1 skipped' "$work/out.txt" || fail "wrong summary"

sed -i '/no-such-scene/d' "$work/page.md"
TMPDIR=$work bash "$src/scripts/check-doc-commands.sh" --build "$build" "$work/page.md" \
  >"$work/out.txt" 2>&1 || fail "exit status $?, expected 0 once every command succeeds"
echo "check-doc-commands: ok, fail and skip reported as marked"
