#!/usr/bin/env bash
# What stopping at the blow's end (stop = blow_end) costs LIGGGHTS: its deck runs one dump
# interval at a time and judges each frame between runs. For three cases (the default stack with a
# free bottom, the same over a wall, steel/Teflon/steel over a wall) it times, alternating, medians
# of REPEATS:
# - the blow_end case (it stops where the blow ended);
# - a plain case of exactly those steps and cadences (stop = duration): the difference is the
#   judging, per frame;
# - the case as the automatic duration has it: what stopping at the blow's end saves or adds.
# LIGGGHTS's wall time from run.json (wall_seconds: the process, its start and its judging included).
# Usage: bench/blow_end_stop.sh [REPEATS]   (about a minute with 3)
set -euo pipefail
repeats=${1:-3}
source "$(dirname "$0")/common.sh"
cd "$work"
declare -A flags=([free]="" [wall]="--bottom wall" [sandwich]="--blocks 3 --materials steel,teflon,steel --bottom wall")
field() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))$2)" "$1"; }
for c in free wall sandwich; do
  # shellcheck disable=SC2086
  "$gs" generate -o "$c-end" ${flags[$c]} --stop blow_end >/dev/null
  "$gs" generate -o "$c-auto" ${flags[$c]} >/dev/null
  "$gs" run --engine refsim "$c-end" >/dev/null  # where the blow ends (both engines stop there)
  steps=$(field "$c-end/run.json" "['steps']")
  dt=$(field "$c-end/manifest.json" "['derived']['dt']")
  every=$(field "$c-end/manifest.json" "['derived']['dump_every']")
  series=$(field "$c-end/manifest.json" "['derived']['series_every']")
  duration=$(python3 -c "print(repr($steps * $dt))")
  # shellcheck disable=SC2086
  "$gs" generate -o "$c-plain" ${flags[$c]} --duration "$duration" --dump-every "$every" --series-every "$series" >/dev/null
  echo "$c $steps $every" >> cases.txt
done
for ((k = 1; k <= repeats; k++)); do
  for c in free wall sandwich; do
    for v in end plain auto; do
      "$gs" run --force "$c-$v" >/dev/null
      echo "$c $v $(field "$c-$v/run.json" "['wall_seconds']") $(field "$c-$v/run.json" "['steps']")" >> times.txt
    done
  done
done
python3 - cases.txt times.txt <<'PY'
import collections, statistics, sys
cases = {c: (int(s), int(e)) for c, s, e in (l.split() for l in open(sys.argv[1]))}
t = collections.defaultdict(list)
steps = {}
for line in open(sys.argv[2]):
    c, v, w, s = line.split()
    t[(c, v)].append(float(w))
    steps[(c, v)] = int(s)
m = statistics.median
print("| case | blow ends at step | frames | stopped at the blow's end (s) | plain run, same steps (s) | judging per frame (ms) | automatic duration: steps, s |")
print("|---|---|---|---|---|---|---|")
for c, (s, every) in cases.items():
    frames = s // every
    end, plain, auto = m(t[(c, "end")]), m(t[(c, "plain")]), m(t[(c, "auto")])
    print(f"| {c} | {s} | {frames} | {end:.3g} | {plain:.3g} | {1e3 * (end - plain) / frames:.3g} | {steps[(c, 'auto')]}, {auto:.3g} |")
print(f"(medians of {len(t[(c, 'end')])} alternating runs; wall seconds of `granstack run`, LIGGGHTS on one rank)")
PY
