#!/usr/bin/env bash
# LIGGGHTS's strong scaling against the nest's size (issue #36): the 991,441-sphere 3D nest (4
# blocks under 18 x 18 top columns, 36 rows; the 97,921-sphere nest's ghosts per owned sphere
# at 16 ranks are three times its own), the impact's first STEPS steps (default 160), outputs
# at the ends only, on 1 and 16 MPI ranks (`run --np`, the grid granstack chooses), alternating,
# medians of REPEATS runs. For each: LIGGGHTS's "Loop time", its output time (the last frame's
# dump, gathered and written by rank 0 alone, whatever the ranks) and the loop without it, its
# pair, communication and other time, the busiest rank's owned spheres over the mean and the
# ghosts per owned sphere; the speed-up and parallel efficiency of 16 ranks over 1; and the last
# frames' largest relative difference in position and velocity between 16 ranks and 1.
# Needs 16 cores to mean anything. Prints a table; with OUT set, writes $OUT/mpi_large_nest.json.
# Usage: bench/mpi_large_nest.sh [REPEATS]   (about two and a half minutes on 16 cores with 3)
set -euo pipefail
repeats=${1:-3}
source "$(dirname "$0")/common.sh"
steps=${STEPS:-160}
nest=(--geometry nested3d --blocks 4 --top-columns 18 --rows 36 --dt 6.27e-8)
duration=$(python3 -c "print(repr($steps * 6.27e-8))")
"$gs" generate -o "$work/case" "${nest[@]}" --duration "$duration" --dump-every "$steps" --series-every "$steps" >/dev/null
for r in 1 16; do cp -r "$work/case" "$work/r$r"; done
for ((k = 1; k <= repeats; k++)); do
  for r in 1 16; do
    "$gs" run --force --np "$r" "$work/r$r" >/dev/null 2>&1
    awk -v ranks="$r" '
      /^Loop time of/ {loop = $4}
      /^Pair  time/ {pair = $5} /^Comm  time/ {comm = $5} /^Outpt time/ {outpt = $5} /^Other time/ {other = $5}
      /^Nlocal:/ {own = $2; own_max = $4} /^Nghost:/ {ghost = $2}
      END {print ranks, loop, outpt, pair, comm, other, own_max / own, ghost / own}' "$work/r$r/log.liggghts" >>"$work/times"
    echo "repeat $k: $r ranks done" >&2
  done
done
python3 - "$work" "$repeats" "$steps" "${OUT:-}" <<'PY'
import json, statistics, sys
from frames import largest_difference, last_frame
work, repeats, steps, out = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
rows = {}
for line in open(work + "/times"):
    ranks, *v = line.split()
    rows.setdefault(int(ranks), []).append([float(x) for x in v])
m = lambda r, i: statistics.median(v[i] for v in rows[r])

cols, ref = last_frame(f"{work}/r1")
diff = largest_difference(cols, ref, last_frame(f"{work}/r16")[1])
spheres = len(ref)
print(f"{spheres:,}-sphere nest, {steps} steps, LIGGGHTS, medians of {repeats} alternating runs")
print(f"{'ranks':>5s} {'loop s':>8s} {'output s':>8s} {'loop-out':>8s} {'pair':>7s} {'comm':>7s} {'other':>7s} {'busiest':>7s} {'ghosts':>6s}")
record = {"spheres": spheres, "steps": steps, "last_frame_16_vs_1": diff, "ranks": {}}
for r in sorted(rows):
    loop, outpt = m(r, 0), m(r, 1)
    record["ranks"][r] = {"loop_seconds": loop, "output_seconds": outpt, "loop_without_output": m(r, 0) - m(r, 1),
                          "pair_seconds": m(r, 2), "comm_seconds": m(r, 3), "other_seconds": m(r, 4),
                          "busiest_over_mean": m(r, 5), "ghosts_per_owned": m(r, 6), "runs": rows[r]}
    print(f"{r:5d} {loop:8.3f} {outpt:8.3f} {loop - outpt:8.3f} {m(r, 2):7.3f} {m(r, 3):7.3f} {m(r, 4):7.3f} {m(r, 5):7.3f} {m(r, 6):6.3f}")
one, many = record["ranks"][1], record["ranks"][16]
for key, name in (("loop_seconds", "loop"), ("loop_without_output", "loop without the output")):
    s = one[key] / many[key]
    record[f"speedup_{key}"] = s
    print(f"16 ranks over 1, {name}: {s:.2f} ({100 * s / 16:.0f} % efficiency)")
print(f"last frame, 16 ranks against 1: {diff:.2e}")
if out:
    json.dump(record, open(out + "/mpi_large_nest.json", "w"), indent=1)
PY
