#!/usr/bin/env bash
# The 3D nest at scale (issue #14): 6 blocks under 4 x 4 top columns, 8 layers (174 721
# spheres), the first 320 steps of the impact with outputs only at the ends. LIGGGHTS on 1 and
# 2 MPI ranks, refsim on 1 and 2 threads, alternating, medians of REPEATS runs (particle-steps
# per second from run.json), then LIGGGHTS against refsim on the same case (`validate`) and
# LIGGGHTS's 2 ranks against its 1 (the last frame's largest relative position difference).
# Then memory at a million spheres (7 blocks, 4 x 4 top columns, 12 layers: 1 048 513): peak
# resident size of generate, of `run --engine refsim` over 100 steps, and of reduce.
# Usage: bench/nest_scale.sh [REPEATS]   (about four minutes with 3)
set -euo pipefail
repeats=${1:-3}
source "$(dirname "$0")/common.sh"
nest=(--geometry nested3d --top-columns 4 --series-every 1000000000)
generate_ends_only "$work/case" "${nest[@]}" --blocks 6 --duration 2e-5 >/dev/null
for run in l1 l2 r1 r2; do cp -r "$work/case" "$work/$run"; done
rate() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['particle_steps_per_second'])" "$1/run.json"; }
declare -A rates
for ((k = 1; k <= repeats; k++)); do
  "$gs" run --force "$work/l1" >/dev/null && rates[l1]+="$(rate "$work/l1") "
  "$gs" run --force --np 2 "$work/l2" >/dev/null && rates[l2]+="$(rate "$work/l2") "
  "$gs" run --force --engine refsim "$work/r1" >/dev/null && rates[r1]+="$(rate "$work/r1") "
  "$gs" run --force --engine refsim --threads 2 "$work/r2" >/dev/null && rates[r2]+="$(rate "$work/r2") "
done
python3 - "${rates[l1]}" "${rates[l2]}" "${rates[r1]}" "${rates[r2]}" <<'PY'
import statistics, sys
l1, l2, r1, r2 = ([float(x) for x in a.split()] for a in sys.argv[1:5])
m = statistics.median
print(f"174721-sphere nest, 320 steps, {len(l1)} alternating runs, median particle-steps/s (min..max)")
for name, v in (("LIGGGHTS, 1 rank", l1), ("LIGGGHTS, 2 ranks", l2), ("refsim, 1 thread", r1), ("refsim, 2 threads", r2)):
    print(f"  {name:18s} {m(v):.3e} ({min(v):.3e}..{max(v):.3e})")
print(f"  LIGGGHTS 2 ranks / 1 rank: {m(l2) / m(l1):.2f}; refsim 2 threads / 1 thread: {m(r2) / m(r1):.2f}; "
      f"refsim / LIGGGHTS, one core each: {m(r1) / m(l1):.1f}")
PY
"$gs" validate "$work/case" | tail -1
python3 - "$work/l1" "$work/l2" <<'PY'
import sys
from frames import last_frame
cols, a = last_frame(sys.argv[1])
_, b = last_frame(sys.argv[2])
ix = [cols.index(c) for c in ("x", "y", "z")]
worst = max(abs(a[i][k] - b[i][k]) / max(abs(a[i][k]), abs(b[i][k]), 1e-3) for i in a for k in ix)
print(f"LIGGGHTS 2 ranks against 1, last frame: largest position difference {worst:.2e} (relative, floor 1 mm)")
PY
big=(--geometry nested3d --top-columns 4 --blocks 7 --rows 12 --dt 6.27e-8 --duration 6.27e-6 --dump-every 100 --series-every 100)
peak() { /usr/bin/time -f "%M" "$@" 2>&1 >/dev/null | tail -1; }
echo "1048513-sphere nest, peak resident memory:"
echo "  generate            $(( $(peak "$gs" generate -o "$work/million" "${big[@]}") / 1024 )) MB"
echo "  run --engine refsim $(( $(peak "$gs" run --engine refsim "$work/million") / 1024 )) MB (100 steps)"
echo "  reduce              $(( $(peak "$gs" reduce "$work/million") / 1024 )) MB"
