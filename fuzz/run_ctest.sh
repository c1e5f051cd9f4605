#!/usr/bin/env bash
# The fuzz tests ctest runs (fuzz/CMakeLists.txt, label fuzz).
#   run_ctest.sh replay BINARY DIR [--may-be-empty]
#                                          every file in DIR once; a missing or empty DIR
#                                          fails unless --may-be-empty (regressions/: empty
#                                          until a finding moves there)
#   run_ctest.sh session BINARY RUNS WORK DICT DIR...
#                                          RUNS inputs from seed 1, starting from the files in
#                                          the DIRs; new inputs go to WORK (emptied first),
#                                          findings to WORK/artifacts/
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
source "$here/flags.sh"
mode=$1 binary=$2
shift 2
case $mode in
  replay)
    dir=$1 may_be_empty=${2:-}
    files=()
    if [[ -d $dir ]]; then
      while IFS= read -r -d '' f; do files+=("$f"); done < <(find "$dir" -type f -print0 | sort -z)
    fi
    echo "replaying ${#files[@]} inputs from $dir"
    if ((${#files[@]} == 0)); then
      [[ $may_be_empty == --may-be-empty ]] && exit 0
      echo "no inputs in $dir" >&2
      exit 1
    fi
    exec "$binary" "${illum_fuzz_flags[@]}" "${files[@]}"
    ;;
  session)
    runs=$1 work=$2 dict=$3
    shift 3
    rm -rf "$work"
    mkdir -p "$work/new" "$work/artifacts"
    seeds=()
    for d in "$@"; do [[ -d $d ]] && seeds+=("$d"); done
    exec "$binary" "${illum_fuzz_flags[@]}" -seed=1 -runs="$runs" -dict="$dict" \
      -artifact_prefix="$work/artifacts/" -print_final_stats=1 "$work/new" "${seeds[@]}"
    ;;
  *)
    echo "usage: $0 replay|session ..." >&2
    exit 2
    ;;
esac
