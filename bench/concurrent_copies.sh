#!/usr/bin/env bash
# The machine's own ceiling on strong scaling (issue #36): the 97,921-sphere nest's first 1000
# steps on one core, alone and as COPIES copies at once (one per core, nothing shared but the
# machine: memory bandwidth, caches, clock), on LIGGGHTS (1 rank) and on refsim (1 thread),
# alternating, REPEATS times. A copy's loop time (LIGGGHTS's without its output) over the lone
# run's is the slowdown every rank of a COPIES-rank run meets before any communication or
# imbalance: its inverse bounds the parallel efficiency any decomposition can reach there.
# Prints the medians; with OUT set, writes $OUT/concurrent_copies.json.
# Usage: bench/concurrent_copies.sh [REPEATS] [COPIES]   (about two minutes on 16 cores)
set -euo pipefail
repeats=${1:-3}
copies=${2:-$(nproc)}
source "$(dirname "$0")/common.sh"
"$gs" generate -o "$work/case" --geometry nested3d --blocks 4 --top-columns 8 --rows 18 --dt 6.27e-8 \
  --duration 6.27e-5 --dump-every 1000 --series-every 1000 >/dev/null
for ((c = 0; c < copies; c++)); do cp -r "$work/case" "$work/c$c"; done
seconds() {  # CASE ENGINE: the loop seconds of its last run (LIGGGHTS's without its output)
  if [ "$2" = liggghts ]; then
    awk '/^Loop time of/ {loop = $4} /^Outpt time/ {out = $5} END {print loop - out}' "$1/log.liggghts"
  else
    python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['loop_seconds'])" "$1/run.json"
  fi
}
engine_args() { [ "$1" = liggghts ] && echo "--np 1" || echo "--engine refsim --threads 1"; }
for ((k = 1; k <= repeats; k++)); do
  for engine in liggghts refsim; do
    # shellcheck disable=SC2046
    "$gs" run --force $(engine_args $engine) "$work/c0" >/dev/null 2>&1
    echo "$engine alone $(seconds "$work/c0" $engine)" >>"$work/times"
    pids=()
    for ((c = 0; c < copies; c++)); do
      # shellcheck disable=SC2046
      taskset -c "$c" "$gs" run --force $(engine_args $engine) "$work/c$c" >/dev/null 2>&1 &
      pids+=($!)
    done
    wait "${pids[@]}"
    for ((c = 0; c < copies; c++)); do echo "$engine copies $(seconds "$work/c$c" $engine)" >>"$work/times"; done
    echo "repeat $k: $engine done" >&2
  done
done
python3 - "$work/times" "$copies" "${OUT:-}" <<'PY'
import json, statistics, sys
rows = {}
for line in open(sys.argv[1]):
    engine, how, s = line.split()
    rows.setdefault((engine, how), []).append(float(s))
copies, out = int(sys.argv[2]), sys.argv[3]
record = {"copies": copies}
print(f"97,921-sphere nest, 1000 steps on one core each: alone and {copies} copies at once (medians)")
for engine in ("liggghts", "refsim"):
    alone, many = statistics.median(rows[(engine, "alone")]), statistics.median(rows[(engine, "copies")])
    slowest = max(rows[(engine, "copies")])
    record[engine] = {"alone_seconds": alone, "copy_seconds": many, "slowest_copy_seconds": slowest,
                      "slowdown": many / alone, "efficiency_bound": alone / many,
                      "runs": {"alone": rows[(engine, "alone")], "copies": rows[(engine, "copies")]}}
    print(f"{engine:9s} alone {alone:7.3f} s   a copy {many:7.3f} s (slowest {slowest:.3f})   "
          f"slowdown {many / alone:.2f}: efficiency at most {100 * alone / many:.0f} %")
if out:
    json.dump(record, open(out + "/concurrent_copies.json", "w"), indent=1)
PY
