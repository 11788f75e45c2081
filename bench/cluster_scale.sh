#!/usr/bin/env bash
# The cluster commands at scale (issue #13): `submit --dry-run` of a 10,000-case sweep (target
# under 2 s) and `status` of it (under 1 s), before and after its cases have run (refsim),
# under 100 MB of peak memory (GNU time), medians
# of REPEATS runs; then the MPI speed-up of 2 LIGGGHTS ranks over 1 on an 11,521-sphere stack
# (the default stack with 96 top columns, 1e-4 s), alternating, medians of REPEATS loop times.
# The sweep's cases are tiny (one block of one row: 3 spheres), since only their number matters.
# Usage: bench/cluster_scale.sh [REPEATS]   (about three minutes with 3, most of it generate)
set -euo pipefail
repeats=${1:-3}
source "$(dirname "$0")/common.sh"
values() { python3 -c "import sys; n=int(sys.argv[1]); print(','.join(f'{0.06 + 0.94 * (i + 1) / n:.6f}' for i in range(n)))" "$1"; }
"$gs" generate -o "$work/sweep" --blocks 1 --rows 1 --restitution "$(values 100)" --friction "$(values 100)" >/dev/null
timed() {  # FILE COMMAND...: appends "seconds peak_kB" to FILE
  local file=$1
  shift
  /usr/bin/time -f '%e %M' -o "$work/time.txt" "$@" >/dev/null
  tail -1 "$work/time.txt" >> "$file"
}
for ((k = 1; k <= repeats; k++)); do
  rm -rf "$work/sweep/slurm"
  timed "$work/dry.txt" "$gs" submit --dry-run "$work/sweep"
  timed "$work/status.txt" "$gs" status "$work/sweep"
done
# status once every case has run: it then looks at each run's recorded files (run.json's digests).
"$gs" run -j 2 --engine refsim "$work/sweep" >/dev/null
for ((k = 1; k <= repeats; k++)); do
  timed "$work/status_run.txt" "$gs" status "$work/sweep"
done
"$gs" generate -o "$work/one" --top-columns 96 --duration 1e-4 >/dev/null
cp -r "$work/one" "$work/two"
loop() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['loop_seconds'])" "$1/run.json"; }
one=() two=()
for ((k = 1; k <= repeats; k++)); do
  "$gs" run --force "$work/one" >/dev/null
  one+=("$(loop "$work/one")")
  "$gs" run --force --np 2 "$work/two" >/dev/null
  two+=("$(loop "$work/two")")
done
python3 - "$work/dry.txt" "$work/status.txt" "${one[*]}" "${two[*]}" "$work/status_run.txt" <<'PY'
import statistics, sys
pairs = lambda path: [tuple(map(float, line.split())) for line in open(path)]
dry, status, status_run = pairs(sys.argv[1]), pairs(sys.argv[2]), pairs(sys.argv[5])
one, two = [float(x) for x in sys.argv[3].split()], [float(x) for x in sys.argv[4].split()]
m = statistics.median
print(f"10,000-case sweep, {len(dry)} runs each (median; peak memory the largest)")
print(f"submit --dry-run   {m(t for t, _ in dry):.2f} s   {max(k for _, k in dry) / 1024:.0f} MB   target < 2 s, < 100 MB")
print(f"status             {m(t for t, _ in status):.2f} s   {max(k for _, k in status) / 1024:.0f} MB   target < 1 s, < 100 MB")
print(f"status, every case run (refsim)   {m(t for t, _ in status_run):.2f} s   {max(k for _, k in status_run) / 1024:.0f} MB   target < 1 s")
print(f"11,521 spheres, 1596 steps: LIGGGHTS loop, 1 rank {m(one):.2f} s, 2 ranks {m(two):.2f} s: speed-up {m(one) / m(two):.2f}")
PY
