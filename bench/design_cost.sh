#!/usr/bin/env bash
# What a design of the yielding example costs, one build against another (#67 item 7: the search's
# ten minutes are spent running designs). Both builds run the same designs: a generation 0 of
# POPULATION designs drawn from SEED (the example's space, searched generationally for no further
# generation: the draw does not depend on any result), -j JOBS, REPEATS alternating rounds each.
# Printed: each build's median wall time (min..max) for the batch, per design, and the ratio; the
# designs both ran in full, and whether every objective and constraint measure of theirs is the
# same double in both stores (the raw, filtered and windowed measures; srs_peak to SRS_TOLERANCE,
# relative, since a build may sum the spectrum's oscillators otherwise).
# Usage: BASE=<granstack> THIS=<granstack> [SPACE=...] [POPULATION=48] [SEED=1] [JOBS=2]
#        [OUT=record.json] bench/design_cost.sh [REPEATS]
set -euo pipefail
repeats=${1:-3}
source "$(dirname "$0")/common.sh"
base=${BASE:?BASE=<the granstack to compare against>}
this=${THIS:-$gs}
space=${SPACE:-$here/examples/design/yielding_protector.toml}
population=${POPULATION:-48}
jobs=${JOBS:-2}
python3 - "$space" "$work/space.toml" "$population" "${SEED:-1}" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
search = (f'[search]\nevaluation = "generational"\nalgorithm = "nsga2"\npopulation = {sys.argv[3]}\n'
          f'generations = 0\nseed = {sys.argv[4]}\n')
open(sys.argv[2], "w").write(re.sub(r"\[search\].*", search, text, flags=re.S))
PY
declare -a times_base times_this
for ((k = 1; k <= repeats; k++)); do
  for who in base this; do
    exe=$base
    [ "$who" = this ] && exe=$this
    rm -rf "$work/$who$k"
    t0=$(date +%s.%N)
    "$exe" design run "$work/space.toml" -o "$work/$who$k" -j "$jobs" --no-report >/dev/null 2>&1
    t=$(python3 -c "import sys,time; print(time.time() - float(sys.argv[1]))" "$t0")
    if [ "$who" = base ]; then times_base+=("$t"); else times_this+=("$t"); fi
    echo "round $k, $who: $t s" >&2
  done
done
python3 - "$work" "$repeats" "${times_base[*]}" "${times_this[*]}" "$("$base" --version)" "$("$this" --version)" \
  "$population" "$jobs" "${SRS_TOLERANCE:-1e-12}" "${OUT:-}" <<'PY'
import json, sqlite3, statistics, sys
work, repeats = sys.argv[1], int(sys.argv[2])
tb = [float(x) for x in sys.argv[3].split()]
tt = [float(x) for x in sys.argv[4].split()]
vb, vt, population, jobs, srs_tol, out = sys.argv[5:11]
srs_tol = float(srs_tol)
def rows(path):
    c = sqlite3.connect(path)
    cols = ["peak_wall_force", "filtered_wall_force", "wall_impulse", "crush", "penetration", "srs_peak"]
    got = {}
    for r in c.execute(f"select digest, shortcut, seconds, {', '.join(cols)} from evaluations where seconds > 0"):
        got[r[0]] = {"shortcut": r[1], "seconds": r[2], **dict(zip(cols, r[3:]))}
    return got
b, t = rows(f"{work}/base1/design.sqlite"), rows(f"{work}/this1/design.sqlite")
both_full = [d for d in b if d in t and not b[d]["shortcut"] and not t[d]["shortcut"]]
exact = ["peak_wall_force", "filtered_wall_force", "wall_impulse", "crush", "penetration"]
same = all(b[d][m] == t[d][m] for d in both_full for m in exact)
srs = max((abs(b[d]["srs_peak"] / t[d]["srs_peak"] - 1) for d in both_full if b[d]["srs_peak"]), default=0.0)
m = statistics.median
record = {
    "what": "the cost of the yielding example's designs, one build against another (bench/design_cost.sh)",
    "base": vb, "this": vt, "population": int(population), "jobs": int(jobs), "repeats": repeats,
    "designs_run": {"base": len(b), "this": len(t)},
    "settled": {"base": sum(1 for v in b.values() if v["shortcut"]), "this": sum(1 for v in t.values() if v["shortcut"])},
    "seconds": {"base": tb, "this": tt},
    "median_seconds": {"base": m(tb), "this": m(tt)},
    "ratio": m(tt) / m(tb),
    "refsim_seconds": {"base": sum(v["seconds"] for v in b.values()), "this": sum(v["seconds"] for v in t.values())},
    "both_in_full": len(both_full), "measures_identical": same, "srs_largest_relative_difference": srs,
}
print(f"{population} designs drawn (generation 0), -j {jobs}, {repeats} alternating rounds; run: base {len(b)}, this {len(t)} "
      f"(settled by a shortcut: {record['settled']['base']}, {record['settled']['this']})")
print(f"base  {m(tb):7.2f} s ({min(tb):.2f}..{max(tb):.2f})  {vb}")
print(f"this  {m(tt):7.2f} s ({min(tt):.2f}..{max(tt):.2f})  {vt}")
print(f"this / base: {record['ratio']:.3f}; refsim seconds {record['refsim_seconds']['base']:.1f} -> {record['refsim_seconds']['this']:.1f}")
print(f"{len(both_full)} designs run in full by both: measures {'identical' if same else 'DIFFERENT'}, srs_peak within {srs:.2g}")
if out:
    json.dump(record, open(out, "w"), indent=1)
if not same or srs > srs_tol:
    sys.exit(1)
PY
