#!/usr/bin/env bash
# Strong scaling of the 97,921-sphere 3D nest (issue #36): 4 blocks under 8 x 8 top columns, 18
# rows, 2e-4 s (3190 steps), outputs only at the ends. LIGGGHTS on 1, 4 and 16 MPI ranks on the
# grid granstack chooses, and on 16 ranks on the other balanced grid and on the deck as it was
# before (the data file's box a top radius wider than the lattice, LIGGGHTS's own 4 x 4 x 1);
# refsim on 1, 4 and 16 threads. Everything alternating, medians of REPEATS runs: loop seconds
# and wall seconds from run.json, and each process's wall time as a user waits for it. Then the
# results across rank and thread counts: the largest relative difference of any position or
# velocity in the last frame against LIGGGHTS on one rank.
# Needs 16 cores to mean anything (on fewer the ranks share them). Prints a table; with OUT set,
# writes the runs' figures to $OUT/mpi_scaling.json.
# Usage: bench/mpi_scaling.sh [REPEATS]   (about five minutes on 16 cores with 3)
#        ONLY=refsim bench/mpi_scaling.sh [REPEATS]   (refsim's runs alone, against its 1 thread)
set -euo pipefail
repeats=${1:-3}
source "$(dirname "$0")/common.sh"
nest=(--geometry nested3d --blocks 4 --top-columns 8 --rows 18 --duration 2e-4 --dump-every 3190 --series-every 3190)
"$gs" generate -o "$work/case" "${nest[@]}" >/dev/null
chosen=$("$gs" decompose "$work/case" --np 16 --grids 1 | awk '/run --np chooses/{print $2}' | tr x ,)
other=$([ "$chosen" = "4,4,1" ] && echo 2,8,1 || echo 4,4,1)
declare -A runs=([l1]="--np 1" [l4]="--np 4" [l16]="--np 16" [l16other]="--np 16 --grid $other"
                 [r1]="--engine refsim --threads 1" [r4]="--engine refsim --threads 4" [r16]="--engine refsim --threads 16")
order=(l1 r1 l4 r4 l16 r16 l16other l16before)
[ "${ONLY:-}" = refsim ] && order=(r1 r4 r16)
for r in "${order[@]}"; do cp -r "$work/case" "$work/$r"; done
# The deck as granstack wrote it before: the box one top radius (8 mm) wider on each side in x and
# y, on LIGGGHTS's own grid for it (4 x 4 x 1). granstack refuses to run an edited data file, so
# LIGGGHTS runs it directly (its loop time is the same "Loop time" line run.json records).
[[ " ${order[*]} " == *" l16before "* ]] && widen_box_as_before "$work/l16before/data.stack"
figures() {
  python3 - "$1/run.json" "$2" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
d = r.get("decomposition", {}).get("liggghts", {})
o = r.get("outside_loop_seconds", {})
print(r["loop_seconds"], r["wall_seconds"], sys.argv[2], d.get("busiest_over_mean", 1), d.get("ghosts_per_owned", 0),
      *(o.get(k, 0) for k in ("read", "build", "first_output", "close")))
PY
}
for ((k = 1; k <= repeats; k++)); do
  for r in "${order[@]}"; do
    if [ "$r" = l16before ]; then
      read -r loop wall busiest ghosts < <(liggghts_directly "$work/$r" 16 4 4 1)
      echo "$r $loop $wall $wall $busiest $ghosts 0 0 0 0" >>"$work/times"
    else
      # shellcheck disable=SC2086
      t0=$(date +%s.%N) && "$gs" run --force ${runs[$r]} "$work/$r" >/dev/null 2>&1 && t1=$(date +%s.%N)
      echo "$r $(figures "$work/$r" "$(awk "BEGIN{print $t1 - $t0}")")" >>"$work/times"
    fi
    echo "repeat $k: $r done" >&2
  done
done
python3 - "$work" "$repeats" "$chosen" "$other" "${OUT:-}" <<'PY'
import json, statistics, sys
from frames import largest_difference, last_frame
work, repeats, chosen, other, out = sys.argv[1:6]
rows = {}
for line in open(work + "/times"):
    name, *values = line.split()
    rows.setdefault(name, []).append(tuple(float(v) for v in values))
m = lambda name, i: statistics.median(v[i] for v in rows[name])

first = "l1" if "l1" in rows else "r1"
cols, ref = last_frame(f"{work}/{first}")
worst = lambda case: largest_difference(cols, ref, last_frame(f"{work}/{case}")[1])

label = {"l1": "LIGGGHTS 1 rank", "l4": "LIGGGHTS 4 ranks", "l16": f"LIGGGHTS 16 ranks ({chosen}, chosen)",
         "l16other": f"LIGGGHTS 16 ranks ({other})", "l16before": "LIGGGHTS 16 ranks (before: wider box, 4,4,1)",
         "r1": "refsim 1 thread", "r4": "refsim 4 threads", "r16": "refsim 16 threads"}
print(f"97,921-sphere nest, 3190 steps, medians of {repeats} alternating runs")
print(f"{'':46s} {'loop s':>8s} {'speed-up':>8s} {'wall s':>8s} {'speed-up':>8s} {'process s':>9s} {'busiest':>7s} {'ghosts':>6s} {'last frame vs ' + label[first]:>20s}")
record = {}
for name in (n for n in ("l1", "l4", "l16", "l16other", "l16before", "r1", "r4", "r16") if n in rows):
    base = "l1" if name[0] == "l" else "r1"
    n = {"1": 1, "4": 4}.get(name[1:], 16)
    loop, wall, proc = m(name, 0), m(name, 1), m(name, 2)
    s_loop, s_wall = m(base, 0) / loop, m(base, 1) / wall
    diff = worst(name)
    record[name] = {"label": label[name], "units": n, "loop_seconds": loop, "wall_seconds": wall, "process_seconds": proc,
                    "loop_speedup": s_loop, "wall_speedup": s_wall, "efficiency": s_loop / n,
                    "busiest_over_mean": m(name, 3), "ghosts_per_owned": m(name, 4), "last_frame_vs_liggghts_1": diff,
                    "runs": rows[name]}
    print(f"{label[name]:46s} {loop:8.3f} {s_loop:8.2f} {wall:8.3f} {s_wall:8.2f} {proc:9.3f} {m(name, 3):7.3f} {m(name, 4):6.3f} {diff:20.2e}")
    if name[0] == "r":  # refsim's time outside the loop (run.json's outside_loop_seconds)
        parts = {k: m(name, 5 + i) for i, k in enumerate(("read", "build", "first_output", "close"))}
        record[name]["outside_loop_seconds"] = parts
        print(f"{'':46s} outside the loop: " + ", ".join(f"{k} {v:.3f} s" for k, v in parts.items()))
if out:
    json.dump(record, open(out + "/mpi_scaling.json", "w"), indent=1)
PY
