#!/usr/bin/env bash
# How long a clean build takes, as CI builds it (`cmake --preset ci`, then `cmake --build -j2`:
# the program, the libraries, the tests and the benchmarks), for each of several commits in
# turn: each commit checked out into a scratch worktree, built from nothing, the commits
# alternating, medians of REPEATS builds (min..max). A ratio against the first commit, in the
# same run, is what to compare: this machine drifts by 30 %.
# A commit may carry configure options after a '+': HEAD+-DGRANSTACK_UNITY_BUILD=OFF builds HEAD
# without unity batches (options separated by '+').
# Usage: bench/build.sh REPEATS BASE_COMMIT COMMIT...   (about 15 minutes a round on 2 cores)
set -euo pipefail
repeats=${1:?usage: bench/build.sh REPEATS BASE_COMMIT COMMIT...}
shift
[ $# -ge 2 ] || { echo "bench/build.sh: name a base commit and at least one other" >&2; exit 2; }
source "$(dirname "$0")/common.sh"
cd "$here"
declare -A walls
declare -A trees
for spec in "$@"; do
  rev=${spec%%+*}
  git rev-parse --verify -q "$rev^{commit}" >/dev/null || { echo "bench/build.sh: no commit '$rev'" >&2; exit 2; }
  [ -n "${trees[$rev]:-}" ] || git worktree add -q --detach "$work/src-$rev" "$rev"
  trees[$rev]=1
done
trap 'for rev in "${!trees[@]}"; do git worktree remove --force "$work/src-$rev" 2>/dev/null || true; done; rm -rf "$work"' EXIT
for ((i = 1; i <= repeats; i++)); do
  for rev in "$@"; do
    options=()
    [[ "$rev" == *+* ]] && IFS=+ read -r -a options <<<"${rev#*+}"
    rm -rf "$work/build"
    t0=$(date +%s.%N)
    cmake --preset ci "${options[@]}" -S "$work/src-${rev%%+*}" -B "$work/build" >/dev/null
    cmake --build "$work/build" -j2 >"$work/build.log" 2>&1 || { tail -20 "$work/build.log" >&2; exit 1; }
    t1=$(date +%s.%N)
    walls[$rev]+=" $(awk "BEGIN{printf \"%.1f\", $t1 - $t0}")"
    echo "round $i, $rev: ${walls[$rev]##* } s" >&2
  done
done
for rev in "$@"; do echo "$rev${walls[$rev]}"; done | python3 -c '
import statistics, sys
rows = [line.split() for line in sys.stdin]
base = statistics.median(map(float, rows[0][1:]))
for rev, *t in rows:
    t = [float(x) for x in t]
    m = statistics.median(t)
    print(f"{rev}: {m:.1f} s ({min(t):.1f}..{max(t):.1f}), {m / base:.2f} of {rows[0][0]}")
print(f"(clean builds as CI makes them, cmake --build -j2 on {len(t)} alternating rounds; this machine, {sys.argv[1]} cores)")' "$(nproc)"
