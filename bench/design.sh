#!/usr/bin/env bash
# granstack design's speed (#25, #34: 5,000 distinct designs of up to about 1,000 spheres in 10
# minutes on 2 cores with refsim).
#  1. The search of bench/design_space.toml (up to 993 spheres, run to the blow's end over a
#     wall), asynchronous, -j JOBS, from scratch, for at most 5,000 distinct designs and at most
#     600 s (--max-designs 5000 --time-limit 600): the distinct designs it ran in that time,
#     counted from the store (every evaluation that ran: the probes, the infeasible and the
#     censored included), per second, and the busy cores.
#  2. The in-situ mode against files, on the same 40 designs (a generation 0 of 40), REPEATS
#     alternating runs, medians: `design run` (in situ) against generating the same designs as
#     cases and `granstack run --engine refsim -j 2` on them (dumps and series written), the
#     baseline. ONLY=target skips it.
#     It also says where refsim's time went: the designs whose blow ended against those censored
#     at the cap (their count, refsim seconds in all and per design, mean spheres).
# Usage: bench/design.sh [REPEATS] [JOBS]   (part 1 takes 10 minutes; TIME_LIMIT=S shortens it,
# and the target is then not judged)
set -euo pipefail
repeats=${1:-3}
jobs=${2:-2}
source "$(dirname "$0")/common.sh"
seconds() { local t0=$(date +%s.%N); "$@" >/dev/null 2>&1; python3 -c "import sys,time; print(time.time() - float(sys.argv[1]))" "$t0"; }

python3 - "$gs" "$here/bench/design_space.toml" "$work/whole" "$jobs" "${TIME_LIMIT:-600}" <<'PY'
import resource, sqlite3, subprocess, sys, time
gs, space, out, jobs, limit = sys.argv[1:6]
t0 = time.time()
subprocess.run([gs, "design", "run", space, "-o", out, "-j", jobs, "--no-report", "--max-designs", "5000",
                "--time-limit", limit, "--generations", "100000"], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
wall = time.time() - t0
ru = resource.getrusage(resource.RUSAGE_CHILDREN)
c = sqlite3.connect(f"{out}/design.sqlite")
runs, cpu, biggest = c.execute("select count(*), sum(seconds), max(spheres) from evaluations where seconds > 0").fetchone()
censored, = c.execute("select count(*) from evaluations where seconds > 0 and violations like '%censored%'").fetchone()
print(f"search: {runs} distinct designs run on refsim (the largest {biggest} spheres) in {wall:.1f} s wall, "
      f"{runs / wall:.2f} distinct designs/s, {(ru.ru_utime + ru.ru_stime) / wall:.2f} cores busy on -j {jobs}; "
      f"{cpu:.1f} s of refsim in all ({cpu / runs:.3f} s per design), {censored} censored (the blow not ended at the "
      f"cap); target: 5000 in < 600 s: "
      f"{('met' if runs >= 5000 and wall < 600 else 'not met') if limit == '600' else 'not judged (TIME_LIMIT)'}")
for name, test in (("ended", "not like"), ("censored", "like")):
    n, total, spheres = c.execute(f"select count(*), sum(seconds), avg(spheres) from evaluations "
                                  f"where seconds > 0 and violations {test} '%censored%'").fetchone()
    if n:
        print(f"  {name}: {n} designs, {total:.1f} s of refsim ({total / cpu:.0%}), {total / n:.2f} s per design, "
              f"{spheres:.0f} spheres on average")
PY
[ "${ONLY:-}" = target ] && exit 0

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
