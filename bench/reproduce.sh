#!/usr/bin/env bash
# Wall time of `granstack reproduce` (issue #12's speed targets: every experiment on LIGGGHTS in
# under 60 s on 2 cores, under 90 s with --validate, --quick under 30 s), each from scratch
# (--force: every case generated, run, reduced and judged again), -j 2. Runs the four
# alternately REPEATS times and reports the median (min..max) of each. The baseline in the same
# run: `granstack run -j 2 --force` on the very same 54 cases, LIGGGHTS alone (no reduce, no
# analysis, no report), so the ratio is what reproduce adds to the engine's own time.
# Usage: bench/reproduce.sh [REPEATS]   (about five minutes with 3; OUT=FILE.json keeps the record,
# from which the docs' "N cases, about T s on 2 cores" is made: scripts/doc_tables.py)
set -euo pipefail
repeats=${1:-3}
source "$(dirname "$0")/common.sh"
seconds() { local t0=$(date +%s.%N); "$@" >/dev/null; python3 -c "import sys,time; print(time.time() - float(sys.argv[1]))" "$t0"; }
declare -A times
"$gs" reproduce -o "$work/all" -j 2 >/dev/null  # the cases the baseline runs again
mapfile -t cases < <(find "$work/all" -name manifest.json -not -path '*/validate/*' -printf '%h\n' | sort)
for ((k = 1; k <= repeats; k++)); do
  times[all]+="$(seconds "$gs" reproduce -o "$work/all" -j 2 --force) "
  times[run]+="$(seconds "$gs" run -j 2 --force "${cases[@]}") "
  times[validate]+="$(seconds "$gs" reproduce -o "$work/validate" -j 2 --force --validate) "
  times[quick]+="$(seconds "$gs" reproduce -o "$work/quick" -j 2 --force --quick) "
done
OUT="${OUT:-}" python3 - "${#cases[@]}" "${times[all]}" "${times[run]}" "${times[validate]}" "${times[quick]}" <<'PY'
import json, os, statistics, sys
n = sys.argv[1]
all_, run, val, quick = ([float(x) for x in a.split()] for a in sys.argv[2:6])
m = statistics.median
f = lambda xs: f"{m(xs):6.1f} s  ({min(xs):.1f}..{max(xs):.1f})"
print(f"{len(all_)} alternating runs each, -j 2, from scratch (median, min..max)")
print(f"reproduce, every experiment ({n} cases)   {f(all_)}   target < 60 s")
print(f"reproduce --validate                     {f(val)}   target < 90 s")
print(f"reproduce --quick                        {f(quick)}   target < 30 s")
print(f"baseline: granstack run -j 2 on the same {n} cases (LIGGGHTS alone)   {f(run)}")
print(f"reproduce / baseline: {m(all_) / m(run):.2f}")
if os.environ["OUT"]:
    json.dump({"cases": int(n), "cores": os.cpu_count(), "jobs": 2, "repeats": len(all_), "seconds": {
        "reproduce": all_, "baseline_run": run, "validate": val, "quick": quick}}, open(os.environ["OUT"], "w"), indent=1)
PY
