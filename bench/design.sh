#!/usr/bin/env bash
# granstack design's speed (issue #25: at least 5,000 designs of up to about 1,000 spheres
# evaluated in under 10 minutes on 2 cores with refsim).
#  1. The whole search of bench/design_space.toml (population 200, 25 generations: 5,200 designs
#     asked for, of up to 993 spheres), -j 2, from scratch: its wall time, the designs it ran
#     (each once; those asked for again come from the store) and the designs per second.
#  2. The in-situ mode against files, on the same 40 designs (a generation 0 of 40), REPEATS
#     alternating runs, medians: `design run` (in situ) against generating the same designs as
#     cases and `granstack run --engine refsim -j 2` on them (dumps and series written), the
#     baseline.
# Usage: bench/design.sh [REPEATS]   (long since every design runs to its blow's end over a wall:
# three generations took 13.5 minutes on 2 cores, 2026-11-26; bench/design_cap.sh is the quick one)
set -euo pipefail
repeats=${1:-3}
source "$(dirname "$0")/common.sh"
seconds() { local t0=$(date +%s.%N); "$@" >/dev/null 2>&1; python3 -c "import sys,time; print(time.time() - float(sys.argv[1]))" "$t0"; }

whole=$(seconds "$gs" design run "$here/bench/design_space.toml" -o "$work/whole" -j 2 --no-report)
python3 - "$work/whole/design.sqlite" "$whole" <<'PY'
import sqlite3, sys
c = sqlite3.connect(sys.argv[1])
# Every design that ran (seconds > 0), feasible or not (a censored blow ran to its cap).
runs, cpu, biggest = c.execute("select count(*), sum(seconds), max(spheres) from evaluations where searched = 1 and seconds > 0").fetchone()
censored, = c.execute("select count(*) from evaluations where searched = 1 and violations like '%censored%'").fetchone()
gens, = c.execute("select count(*) from generations").fetchone()
asked = gens * 200
wall = float(sys.argv[2])
print(f"whole search: {gens} generations of 200 ({asked} designs asked for), {runs} run on refsim (the largest "
      f"{biggest} spheres) in {wall:.1f} s wall, {runs / wall:.2f} designs/s; {cpu:.1f} s of refsim in all "
      f"({cpu / runs:.3f} s per design), {censored} of them censored (the blow not ended at the cap); "
      f"target: 5000 in < 600 s")
PY

# The same 40 designs, in situ and as cases.
sed 's/^population = 200/population = 40/; s/^generations = 25/generations = 0/' "$here/bench/design_space.toml" > "$work/sample.toml"
"$gs" design run "$work/sample.toml" -o "$work/sample" -j 2 --no-report >/dev/null 2>&1
mkdir -p "$work/specs"
python3 - "$work/sample/design.sqlite" "$work/specs" <<'PY'
import json, sqlite3, sys
def toml_value(v):
    if isinstance(v, bool): return "true" if v else "false"
    if isinstance(v, (int, float)): return repr(v)
    if isinstance(v, str): return json.dumps(v)
    if isinstance(v, list): return "[" + ", ".join(toml_value(x) for x in v) + "]"
    raise ValueError(v)
c = sqlite3.connect(sys.argv[1])
for digest, spec in c.execute("select digest, spec from evaluations where searched = 1 and seconds > 0"):
    s = json.loads(spec)
    if "block_rows" in s: s.pop("rows", None)
    lines = [f"{k} = {toml_value(v)}" for k, v in s.items() if v is not None and not isinstance(v, dict)]
    for k, v in s.items():
        if isinstance(v, dict) and v:
            lines.append(f"[{k}]")
            lines += [f"{json.dumps(a)} = {toml_value(b)}" if not isinstance(b, dict) else "" for a, b in v.items()]
    open(f"{sys.argv[2]}/{digest[:12]}.toml", "w").write("\n".join(lines) + "\n")
PY
mapfile -t specs < <(ls "$work/specs"/*.toml)
declare -a insitu files
for ((k = 1; k <= repeats; k++)); do
  rm -rf "$work/s$k"
  insitu+=("$(seconds "$gs" design run "$work/sample.toml" -o "$work/s$k" -j 2 --no-report)")
  rm -rf "$work/cases"
  mkdir -p "$work/cases"
  t0=$(date +%s.%N)
  for s in "${specs[@]}"; do "$gs" generate --config "$s" -o "$work/cases/$(basename "$s" .toml)" >/dev/null; done
  "$gs" run --engine refsim -j 2 "$work/cases"/* >/dev/null 2>&1
  files+=("$(python3 -c "import sys,time; print(time.time() - float(sys.argv[1]))" "$t0")")
done
python3 - "${#specs[@]}" "${insitu[*]}" "${files[*]}" <<'PY'
import statistics, sys
n = sys.argv[1]
a = [float(x) for x in sys.argv[2].split()]
b = [float(x) for x in sys.argv[3].split()]
m = statistics.median
print(f"the same {n} designs, {len(a)} alternating runs each, -j 2 (median, min..max)")
print(f"in situ (design run, generation 0)          {m(a):6.2f} s  ({min(a):.2f}..{max(a):.2f})")
print(f"baseline: generate + run --engine refsim    {m(b):6.2f} s  ({min(b):.2f}..{max(b):.2f})")
print(f"in situ / baseline: {m(a) / m(b):.2f}")
PY
