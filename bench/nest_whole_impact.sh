#!/usr/bin/env bash
# A whole impact on a 3D nest of 10^5 spheres (issue #14): 5 blocks under 8 x 8 top columns,
# 5 layers each (109 121 spheres), the automatic duration (22 320 steps, until the pulse has
# left the bottom), outputs at the ends only. REPEATS alternating rounds of refsim on 1 and 2
# threads and LIGGGHTS on 1 and 2 MPI ranks; medians of the loop times from run.json. Then the
# last frames compared: refsim against LIGGGHTS, its 2 threads against its 1, and LIGGGHTS's 2
# ranks against its 1 (largest position difference, relative with a 1 mm floor, and the output
# sphere's kinetic energy).
# Usage: bench/nest_whole_impact.sh [REPEATS]   (about 6 minutes a round)
set -euo pipefail
repeats=${1:-3}
source "$(dirname "$0")/common.sh"
nest=(--geometry nested3d --blocks 5 --top-columns 8 --rows 5 --series-every 1000)
generate_ends_only "$work/case" "${nest[@]}" | head -1
for run in l1 l2 r1 r2; do cp -r "$work/case" "$work/$run"; done
loop() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['loop_seconds'])" "$1/run.json"; }
declare -A loops
for ((k = 1; k <= repeats; k++)); do
  "$gs" run --force --engine refsim "$work/r1" >/dev/null && loops[r1]+="$(loop "$work/r1") "
  "$gs" run --force --engine refsim --threads 2 "$work/r2" >/dev/null && loops[r2]+="$(loop "$work/r2") "
  "$gs" run --force "$work/l1" >/dev/null && loops[l1]+="$(loop "$work/l1") "
  "$gs" run --force --np 2 "$work/l2" >/dev/null && loops[l2]+="$(loop "$work/l2") "
done
python3 - "${loops[l1]}" "${loops[l2]}" "${loops[r1]}" "${loops[r2]}" "$work" <<'PY'
import statistics, sys
l1, l2, r1, r2 = ([float(x) for x in a.split()] for a in sys.argv[1:5])
work = sys.argv[5]
m = statistics.median
print(f"109121-sphere nest, whole impact, loop seconds, medians of {len(r1)} alternating runs (min..max)")
for name, v in (("LIGGGHTS, 1 rank", l1), ("LIGGGHTS, 2 ranks", l2), ("refsim, 1 thread", r1), ("refsim, 2 threads", r2)):
    print(f"  {name:18s} {m(v):9.2f} ({min(v):.2f}..{max(v):.2f})")
print(f"  LIGGGHTS 2 ranks / 1 rank: {m(l1) / m(l2):.2f}; refsim 2 threads / 1 thread: {m(r1) / m(r2):.2f}; "
      f"refsim / LIGGGHTS, one core each: {m(l1) / m(r1):.1f}; two cores each: {m(l2) / m(r2):.1f}")
from frames import last_frame
cols, frames = None, {}
for run in ("l1", "l2", "r1", "r2"):
    cols, frames[run] = last_frame(f"{work}/{run}")
ix = [cols.index(c) for c in ("x", "y", "z")]
iv = [cols.index(c) for c in ("vx", "vy", "vz")]
im = cols.index("mass")
import json
out = json.load(open(f"{work}/case/manifest.json"))["layout"]["output_sphere_id"]
for a, b in (("r1", "l1"), ("r2", "r1"), ("l2", "l1")):
    fa, fb = frames[a], frames[b]
    worst = max(abs(fa[i][k] - fb[i][k]) / max(abs(fa[i][k]), abs(fb[i][k]), 1e-3) for i in fa for k in ix)
    ke = lambda f: 0.5 * f[out][im] * sum(f[out][k] ** 2 for k in iv)
    print(f"  last frame, {a} against {b}: largest position difference {worst:.2e}; output sphere's kinetic energy "
          f"{ke(fa):.10e} against {ke(fb):.10e} J")
PY
