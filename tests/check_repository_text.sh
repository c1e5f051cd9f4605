#!/usr/bin/env bash
# Tracked files speak of the product only: no absolute path of one machine (a path starting
# with /home, /root, /work or /tmp/<name>; example commands use relative paths or $TMPDIR) and
# no pointer to a tracker ("issue" followed by a number; a comment or doc states the fact
# itself). Run as a test (tests/CMakeLists.txt): bash check_repository_text.sh SOURCE_DIR.
# Prints every offending file:line and exits 1. Without git, or outside a git checkout, it
# exits 77 (ctest: skipped) with a message, except under CI (CI=true or 1, as .ci/run sets
# it), where that fails too: CI must not pass by skipping.
set -u
src=${1:?usage: check_repository_text.sh SOURCE_DIR}

# Files that need such a path or word on purpose, as git pathspecs relative to the top.
# Keep it short and say why for each; none needs one today.
allow=()

in_ci() { [[ ${CI:-} == true || ${CI:-} == 1 ]]; }
missing() {
  if in_ci; then
    echo "CI=true but $1; CI must run this check on a git checkout" >&2
    exit 1
  fi
  echo "$1; skipped (with CI=true this fails)"
  exit 77
}

command -v git >/dev/null 2>&1 || missing "git is not on PATH"
top=$(git -C "$src" rev-parse --show-toplevel 2>/dev/null) || missing "$src is not a git checkout"
[[ $(cd "$top" && pwd -P) == $(cd "$src" && pwd -P) ]] ||
  missing "$src is not the top of a git checkout (that is $top)"

excludes=()
for path in ${allow[@]+"${allow[@]}"}; do excludes+=(":(exclude)$path"); done

# The character before the path must not continue a longer path or a variable
# (build/fuzz/work/, $TMPDIR/work/, https://host/home/ are fine).
paths='(^|[^A-Za-z0-9_.~$}/-])(/(home|root|work)/|/tmp/[A-Za-z])'
issues='(^|[^A-Za-z])issues? ?#?[0-9]'

status=0
report() {  # $1: what is wrong, $2: git grep's output (file:line:text)
  [[ -z $2 ]] && return
  status=1
  echo "$1:"
  while IFS= read -r hit; do echo "  ${hit:0:200}"; done <<<"$2"
}
# -I: text files only; tracked files of the working tree, with their uncommitted changes.
out=$(git -C "$top" grep -nIE "$paths" -- . ${excludes[@]+"${excludes[@]}"}) ; rc=$?
((rc > 1)) && { echo "git grep failed ($rc)" >&2; exit 2; }
report "absolute machine paths (use a relative path or \$TMPDIR)" "$out"
out=$(git -C "$top" grep -nIiE "$issues" -- . ${excludes[@]+"${excludes[@]}"}) ; rc=$?
((rc > 1)) && { echo "git grep failed ($rc)" >&2; exit 2; }
report "tracker references (state the fact instead)" "$out"

if ((status == 0)); then
  echo "$(git -C "$top" ls-files | wc -l) tracked files: no machine paths, no tracker references"
fi
exit $status
