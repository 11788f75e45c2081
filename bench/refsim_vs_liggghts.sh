#!/usr/bin/env bash
# Speed of refsim against LIGGGHTS, measured in one run on the same case (issue #4, section 4):
# the 4-block stack with 8 top columns (961 spheres), the automatic dt, 2e-4 s (3190 steps),
# no dumps or series in the loop (one frame at each end). Runs the engines alternately REPEATS
# times and reports the median particle-steps per second of each and their ratio, for
# 1 LIGGGHTS rank against 1 refsim thread, and 2 ranks against 2 threads. refsim runs its
# automatic kernel (AVX-512 where the CPU has it); its scalar reference kernel is timed too.
# Usage: bench/refsim_vs_liggghts.sh [REPEATS]   (about a minute)
set -euo pipefail
repeats=${1:-7}
here=$(cd "$(dirname "$0")/.." && pwd)
gs=${GRANSTACK:-$here/build/release/app/granstack}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$gs" generate -o "$work/case" --blocks 4 --top-columns 8 --duration 2e-4 --dump-every 1000000000 \
  --series-every 1000000000 >/dev/null
for engine in liggghts liggghts2 refsim refsim2 reference; do cp -r "$work/case" "$work/$engine"; done
rate() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['particle_steps_per_second'])" "$1/run.json"; }
declare -A rates
for ((k = 1; k <= repeats; k++)); do
  "$gs" run --force "$work/liggghts" >/dev/null
  rates[liggghts]+="$(rate "$work/liggghts") "
  "$gs" run --force --engine refsim "$work/refsim" >/dev/null
  rates[refsim]+="$(rate "$work/refsim") "
  "$gs" run --force --np 2 "$work/liggghts2" >/dev/null
  rates[liggghts2]+="$(rate "$work/liggghts2") "
  "$gs" run --force --engine refsim --threads 2 "$work/refsim2" >/dev/null
  rates[refsim2]+="$(rate "$work/refsim2") "
  "$gs" run --force --engine refsim --kernel reference "$work/reference" >/dev/null
  rates[reference]+="$(rate "$work/reference") "
done
kernel=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['kernel'])" "$work/refsim/run.json")
python3 - "$kernel" "${rates[liggghts]}" "${rates[refsim]}" "${rates[liggghts2]}" "${rates[refsim2]}" "${rates[reference]}" <<'PY'
import statistics, sys
kernel = sys.argv[1]
l1, r1, l2, r2, s1 = ([float(x) for x in a.split()] for a in sys.argv[2:7])
m = lambda xs: statistics.median(xs)
print(f"961 spheres, 3190 steps, {len(l1)} alternating runs each (median; min..max); refsim kernel: {kernel}")
for name, xs in (("LIGGGHTS, 1 rank", l1), ("LIGGGHTS, 2 ranks", l2), ("refsim, 1 thread", r1), ("refsim, 2 threads", r2),
                 ("refsim reference kernel, 1 thread", s1)):
    print(f"  {name:34s} {m(xs):.3e} particle-steps/s  ({min(xs):.3e}..{max(xs):.3e})")
print(f"ratio refsim 1 thread / LIGGGHTS 1 rank:  {m(r1) / m(l1):.2f}")
print(f"ratio refsim 2 threads / LIGGGHTS 2 ranks: {m(r2) / m(l2):.2f}")
print(f"ratio refsim reference kernel / LIGGGHTS 1 rank: {m(s1) / m(l1):.2f}")
PY
