#!/usr/bin/env bash
# refsim against LIGGGHTS as a user meets them (issue #15, "end to end"): `granstack run` with
# each case's default outputs (dumps, in-situ series every step), loop times from run.json, the
# engines alternating, medians of REPEATS runs. Cases: the quickstart stack (241 spheres) and the
# 961-sphere stack (8 top columns), elastic and damped frictional (e = 0.9, mu = 0.25), whole
# impact. refsim runs its automatic kernel on one thread, LIGGGHTS one rank.
# Usage: bench/refsim_end_to_end.sh [REPEATS]   (about two minutes with 5)
set -euo pipefail
repeats=${1:-5}
source "$(dirname "$0")/common.sh"
"$gs" generate -o "$work/quick" >/dev/null
"$gs" generate -o "$work/wide" --top-columns 8 >/dev/null
"$gs" generate -o "$work/damped" --top-columns 8 --restitution 0.9 --friction 0.25 >/dev/null
for c in quick wide damped; do cp -r "$work/$c" "$work/${c}_refsim"; done
loop() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['loop_seconds'])" "$1/run.json"; }
declare -A t
for ((k = 1; k <= repeats; k++)); do
  for c in quick wide damped; do
    "$gs" run --force "$work/$c" >/dev/null
    t[$c]+="$(loop "$work/$c") "
    "$gs" run --force --engine refsim "$work/${c}_refsim" >/dev/null
    t[${c}_refsim]+="$(loop "$work/${c}_refsim") "
  done
done
kernel=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['kernel'])" "$work/quick_refsim/run.json")
python3 - "$kernel" "${t[quick]}" "${t[quick_refsim]}" "${t[wide]}" "${t[wide_refsim]}" "${t[damped]}" "${t[damped_refsim]}" <<'PY'
import statistics, sys
kernel = sys.argv[1]
v = [[float(x) for x in a.split()] for a in sys.argv[2:]]
m = statistics.median
print(f"default outputs, loop times, {len(v[0])} alternating runs (median; min..max); refsim kernel {kernel}")
for name, l, r in (("quickstart, 241 spheres, e = 1", v[0], v[1]), ("961 spheres, e = 1", v[2], v[3]),
                   ("961 spheres, e = 0.9, mu = 0.25", v[4], v[5])):
    print(f"{name:32s} LIGGGHTS {m(l):.3f} s ({min(l):.3f}..{max(l):.3f})  refsim {m(r):.3f} s ({min(r):.3f}..{max(r):.3f})  ratio {m(l) / m(r):.1f}")
PY
