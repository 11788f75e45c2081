#!/usr/bin/env bash
# The loop rates behind two figures of the docs (particle-steps per second from run.json, one
# rank or one thread, everything alternating, medians of REPEATS):
# - LIGGGHTS with text dumps (the default) on the default case, a 961-sphere frictional stack
#   and a 673-sphere nest: the slowest is model::kLiggghtsParticleStepsPerSecond, generate's
#   cost estimate and submit's default --time;
# - the default case with binary dumps on both engines, Hertz (the study's) and Hooke: how much
#   faster refsim is on each contact model.
# Usage: bench/engine_rates.sh [REPEATS]   (about a minute with 3)
set -euo pipefail
repeats=${1:-3}
source "$(dirname "$0")/common.sh"
cd "$work"
"$gs" generate -o txt >/dev/null
"$gs" generate -o wide --top-columns 8 --restitution 0.9 --friction 0.25 >/dev/null
"$gs" generate -o nest --geometry nested3d --blocks 3 >/dev/null
"$gs" generate -o hertz --dump-format binary >/dev/null
"$gs" generate -o hooke --dump-format binary --normal-model hooke >/dev/null
rate() { python3 -c "import json,sys; print(json.load(open(sys.argv[1] + '/run.json'))['particle_steps_per_second'])" "$1"; }
for ((k = 1; k <= repeats; k++)); do
  for c in txt wide nest; do
    "$gs" run --force "$c" >/dev/null
    echo "liggghts-text $c $(rate "$c")" >> rates.txt
  done
  for c in hertz hooke; do
    for e in liggghts refsim; do
      "$gs" run --force --engine "$e" "$c" >/dev/null
      echo "$e $c $(rate "$c")" >> rates.txt
    done
  done
done
python3 - rates.txt <<'PY'
import collections, statistics, sys
runs = collections.defaultdict(list)
for line in open(sys.argv[1]):
    engine, case, rate = line.split()
    runs[(engine, case)].append(float(rate))
m = statistics.median
show = lambda xs: f"{m(xs):.3g} ({min(xs):.3g}..{max(xs):.3g})"
n = len(next(iter(runs.values())))
print(f"particle-steps/s, {n} alternating runs each, median (min..max)")
for case, what in (("txt", "default case, 241 spheres"), ("wide", "961 spheres, e 0.9, mu 0.25"), ("nest", "3D nest, 673 spheres")):
    print(f"LIGGGHTS, text dumps, {what}: {show(runs[('liggghts-text', case)])}")
print(f"slowest LIGGGHTS text-dump run: {min(min(runs[('liggghts-text', c)]) for c in ('txt', 'wide', 'nest')):.3g}")
for case in ("hertz", "hooke"):
    l, r = runs[("liggghts", case)], runs[("refsim", case)]
    print(f"{case}, binary dumps: LIGGGHTS {show(l)}, refsim {show(r)}, refsim / LIGGGHTS {m(r) / m(l):.2g}")
PY
