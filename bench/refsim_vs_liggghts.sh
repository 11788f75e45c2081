#!/usr/bin/env bash
# Speed of refsim against LIGGGHTS, measured in one run on the same case (issue #4, section 4):
# the 4-block stack with 8 top columns (961 spheres), the automatic dt, no dumps or series in
# the loop (one frame at each end). Runs the engines alternately REPEATS times and reports the
# median particle-steps per second of each and their ratio, for 1 LIGGGHTS rank against
# 1 refsim thread, and 2 ranks against 2 threads. refsim runs its automatic kernels (the best
# vector instruction set the CPU runs); its scalar reference kernel is timed too.
# The issue's case is the default spec (e = 1, mu = 0: elastic, frictionless contacts, which
# refsim's vector kernels compute without the tangential model), over two spans:
# - the first 2e-4 s (3190 steps): the pulse is still in the top blocks and most spheres are
#   at rest to the bit, pairs refsim's elastic kernel need not recompute (LIGGGHTS does);
# - the whole impact, the spec's default duration (16200 steps), 59 % of the spheres moving
#   per step on average: the fairer figure for a whole run.
# The same stack with e = 0.9 and mu = 0.25 (every contact damped and frictional; no pair is
# skipped) is timed over the first span.
# Usage: bench/refsim_vs_liggghts.sh [REPEATS]   (about two minutes)
set -euo pipefail
repeats=${1:-7}
source "$(dirname "$0")/common.sh"
stack=(--blocks 4 --top-columns 8 --series-every 1000000000)
generate_ends_only "$work/case" "${stack[@]}" --duration 2e-4 >/dev/null
generate_ends_only "$work/whole" "${stack[@]}" >/dev/null
generate_ends_only "$work/damped" "${stack[@]}" --duration 2e-4 --restitution 0.9 --friction 0.25 >/dev/null
for run in liggghts liggghts2 refsim refsim2 reference; do cp -r "$work/case" "$work/$run"; done
for run in liggghts refsim; do cp -r "$work/whole" "$work/whole_$run"; done
for run in liggghts refsim; do cp -r "$work/damped" "$work/damped_$run"; done
steps() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['derived']['steps'])" "$1/manifest.json"; }
rate() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['particle_steps_per_second'])" "$1/run.json"; }
declare -A rates
timed() {  # name, then the run arguments
  local name=$1
  shift
  "$gs" run --force "$@" "$work/$name" >/dev/null
  rates[$name]+="$(rate "$work/$name") "
}
for ((k = 1; k <= repeats; k++)); do
  timed liggghts
  timed refsim --engine refsim
  timed liggghts2 --np 2
  timed refsim2 --engine refsim --threads 2
  timed reference --engine refsim --kernel reference
  timed whole_liggghts
  timed whole_refsim --engine refsim
  timed damped_liggghts
  timed damped_refsim --engine refsim
done
kernel=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['kernel'])" "$work/refsim/run.json")
python3 - "$kernel" "$(steps "$work/case")" "$(steps "$work/whole")" "${rates[liggghts]}" "${rates[refsim]}" \
  "${rates[liggghts2]}" "${rates[refsim2]}" "${rates[reference]}" "${rates[whole_liggghts]}" "${rates[whole_refsim]}" \
  "${rates[damped_liggghts]}" "${rates[damped_refsim]}" <<'PY'
import statistics, sys
kernel, first, whole = sys.argv[1:4]
l1, r1, l2, r2, s1, wl, wr, dl, dr = ([float(x) for x in a.split()] for a in sys.argv[4:13])
m = lambda xs: statistics.median(xs)
print(f"961 spheres, {len(l1)} alternating runs each (median; min..max); refsim kernel: {kernel}")
print(f"e = 1, mu = 0 (the issue's case), the first {first} steps:")
for name, xs in (("LIGGGHTS, 1 rank", l1), ("LIGGGHTS, 2 ranks", l2), ("refsim, 1 thread", r1), ("refsim, 2 threads", r2),
                 ("refsim reference kernel, 1 thread", s1)):
    print(f"  {name:34s} {m(xs):.3e} particle-steps/s  ({min(xs):.3e}..{max(xs):.3e})")
print(f"  ratio refsim 1 thread / LIGGGHTS 1 rank:  {m(r1) / m(l1):.2f}")
print(f"  ratio refsim 2 threads / LIGGGHTS 2 ranks: {m(r2) / m(l2):.2f}")
print(f"  ratio refsim reference kernel / LIGGGHTS 1 rank: {m(s1) / m(l1):.2f}")
print(f"e = 1, mu = 0, the whole impact ({whole} steps):")
for name, xs in (("LIGGGHTS, 1 rank", wl), ("refsim, 1 thread", wr)):
    print(f"  {name:34s} {m(xs):.3e} particle-steps/s  ({min(xs):.3e}..{max(xs):.3e})")
print(f"  ratio refsim 1 thread / LIGGGHTS 1 rank:  {m(wr) / m(wl):.2f}")
print(f"e = 0.9, mu = 0.25, the first {first} steps:")
for name, xs in (("LIGGGHTS, 1 rank", dl), ("refsim, 1 thread", dr)):
    print(f"  {name:34s} {m(xs):.3e} particle-steps/s  ({min(xs):.3e}..{max(xs):.3e})")
print(f"  ratio refsim 1 thread / LIGGGHTS 1 rank:  {m(dr) / m(dl):.2f}")
PY
