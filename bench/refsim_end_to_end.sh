#!/usr/bin/env bash
# refsim against LIGGGHTS as a user meets them (issue #15): `granstack run` on the quickstart
# stack (241 spheres) and the 961-sphere stack (8 top columns), elastic and damped frictional
# (e = 0.9, mu = 0.25), whole impact, loop times from run.json, everything alternating, medians
# of REPEATS runs. Each case twice: with its default outputs (dumps, in-situ series every step)
# and with outputs off (--dump-every and --series-every at the run's length: the kernels alone).
# refsim runs one thread with its best vector kernels and again with AVX2 forced (a laptop's,
# where this CPU has better), each as `granstack run` starts it here (its outputs written on the
# second CPU, write_behind in run.json), and with its best kernels held to one CPU (taskset -c 0:
# the outputs written in line, the per-core figure); LIGGGHTS one rank. Writing's share of
# refsim's loop is 1 - (loop without outputs) / (loop with them).
# Usage: bench/refsim_end_to_end.sh [REPEATS]   (about three minutes with 5)
set -euo pipefail
repeats=${1:-5}
source "$(dirname "$0")/common.sh"
off=(--series-every 1000000000)
declare -A args=([quick]="" [wide]="--top-columns 8" [damped]="--top-columns 8 --restitution 0.9 --friction 0.25")
cases=(quick wide damped)
for c in "${cases[@]}"; do
  # shellcheck disable=SC2086
  "$gs" generate -o "$work/$c" ${args[$c]} >/dev/null
  # shellcheck disable=SC2086
  generate_ends_only "$work/${c}_off" ${args[$c]} "${off[@]}" >/dev/null
done
best=$("$gs" run --help | sed -n 's/.*or one of this CPU.s: \([a-z0-9]*\).*/\1/p')
engines=(liggghts best onecpu)
grep -q "avx2" <("$gs" run --help) && [ "$best" != avx2 ] && engines+=(avx2)
loop() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['loop_seconds'])" "$1/run.json"; }
declare -A t
for ((k = 1; k <= repeats; k++)); do
  for c in "${cases[@]}"; do
    for o in "" _off; do
      for e in "${engines[@]}"; do
        dir="$work/$c$o.$e"
        [ -d "$dir" ] || cp -r "$work/$c$o" "$dir"
        case $e in
          liggghts) "$gs" run --force "$dir" >/dev/null ;;
          best) "$gs" run --force --engine refsim "$dir" >/dev/null ;;
          onecpu) taskset -c 0 "$gs" run --force --engine refsim "$dir" >/dev/null ;;
          *) "$gs" run --force --engine refsim --kernel "$e" "$dir" >/dev/null ;;
        esac
        t[$c$o.$e]+="$(loop "$dir") "
      done
    done
  done
done
{
  echo "$repeats $best ${engines[*]}"
  for key in "${!t[@]}"; do echo "$key ${t[$key]}"; done
} | python3 -c '
import statistics, sys
lines = sys.stdin.read().splitlines()
repeats, best, *engines = lines[0].split()
t = {l.split()[0]: [float(x) for x in l.split()[1:]] for l in lines[1:]}
m = statistics.median
lab = lambda e: {"best": best, "onecpu": best + " 1 CPU"}.get(e, e)
names = {"quick": "quickstart, 241 spheres, e = 1", "wide": "961 spheres, e = 1", "damped": "961 spheres, e = 0.9, mu = 0.25"}
print(f"loop times, {repeats} alternating runs, median (min..max); refsim one thread (outputs on the other CPU, or 1 CPU), LIGGGHTS one rank")
for o, title in (("", "default outputs (dumps, series every step)"), ("_off", "outputs off (the kernels alone)")):
    print(title)
    for c in ("quick", "wide", "damped"):
        l = t[f"{c}{o}.liggghts"]
        row = f"  {names[c]:32s} LIGGGHTS {m(l):.3f} s ({min(l):.3f}..{max(l):.3f})"
        for e in engines[1:]:
            r = t[f"{c}{o}.{e}"]
            label = lab(e)
            row += f"  refsim {label} {m(r):.3f} s ({min(r):.3f}..{max(r):.3f}) ratio {m(l) / m(r):.1f}"
        print(row)
print("writing share of refsim loop, 1 - off / default")
for c in ("quick", "wide", "damped"):
    row = f"  {names[c]:32s}"
    for e in engines[1:]:
        label = lab(e)
        share = 1 - m(t[c + "_off." + e]) / m(t[c + "." + e])
        row += f"  {label} {share:.0%}"
    print(row)
'
