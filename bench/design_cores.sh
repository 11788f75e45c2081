#!/usr/bin/env bash
# granstack design's busy cores and distinct designs per second (#34): the same space searched
# asynchronously ([search] evaluation = "asynchronous", the default) and generationally (pagmo2's
# NSGA-II, a generation at a time), -j JOBS, REPEATS alternating runs from scratch. Each run is
# given the same number of designs to ask for: DESIGNS (asynchronous: --max-designs; generational:
# DESIGNS / population generations, which run fewer distinct designs: a design asked for again
# comes from the store). For each run: the wall time, the CPU time of granstack and its threads
# (getrusage of the finished child), busy cores = CPU / wall, the distinct designs run (counted
# from the store: every evaluation that ran, the probes and the infeasible included) and distinct
# designs per second. Medians, min..max.
# Usage: bench/design_cores.sh [REPEATS] [JOBS] [DESIGNS]
#   SPACE=FILE (default examples/design/least_wall_force.toml), OUT=FILE.json (the record),
#   MODES="asynchronous generational" (either or both), GEN_DESIGNS=N (the generational runs'
#   designs to ask for, when they should be fewer: a generation waits for its slowest design).
set -euo pipefail
repeats=${1:-3}
jobs=${2:-$(nproc)}
designs=${3:-240}
source "$(dirname "$0")/common.sh"
space=${SPACE:-$here/examples/design/least_wall_force.toml}
python3 - "$gs" "$space" "$work" "$repeats" "$jobs" "$designs" "${OUT:-}" "${MODES:-asynchronous generational}" "${GEN_DESIGNS:-$designs}" <<'PY'
import json, os, re, resource, sqlite3, statistics, subprocess, sys, time
gs, space, work, repeats, jobs, designs, out = sys.argv[1], sys.argv[2], sys.argv[3], *map(int, sys.argv[4:7]), sys.argv[7]
modes, gen_designs = sys.argv[8].split(), int(sys.argv[9])
text = open(space).read()
population = int(re.search(r"^population\s*=\s*(\d+)", text, re.M).group(1))
if "[search]" not in text:
    sys.exit(f"{space}: no [search] table")
spaces = {}
for mode in modes:
    spaces[mode] = os.path.join(work, f"{mode}.toml")
    open(spaces[mode], "w").write(re.sub(r"^\[search\]\s*$", f'[search]\nevaluation = "{mode}"', text, flags=re.M))
generations = max(0, gen_designs // population - 1)

def one(mode, k):
    d = os.path.join(work, f"{mode}{k}")
    cmd = [gs, "design", "run", spaces[mode], "-o", d, "-j", str(jobs), "--no-report"]
    cmd += ["--max-designs", str(designs), "--generations", "100000"] if mode == "asynchronous" else ["--generations", str(generations)]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.time()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.time() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    c = sqlite3.connect(os.path.join(d, "design.sqlite"))
    ran, = c.execute("select count(*) from evaluations where seconds > 0").fetchone()
    searched, = c.execute("select count(*) from evaluations where searched = 1 and seconds > 0").fetchone()
    asked = searched
    if mode == "generational":  # the designs its populations asked for, clones included
        asked = sum(len(json.loads(p)) for p, in c.execute("select population from generations"))
    c.close()
    subprocess.run(["rm", "-rf", d], check=True)
    return {"wall": wall, "cpu": cpu, "busy": cpu / wall, "distinct": ran, "searched": searched, "asked": asked,
            "per_second": ran / wall}

runs = {m: [] for m in spaces}
for k in range(repeats):
    for mode in spaces:
        r = one(mode, k)
        runs[mode].append(r)
        print(f"{mode:12s} run {k + 1}: {r['wall']:7.1f} s wall, {r['cpu']:7.1f} s CPU, {r['busy']:5.2f} cores busy, "
              f"{r['distinct']} distinct designs run, {r['per_second']:.2f} per s", flush=True)
m = statistics.median
print(f"\n{os.path.basename(space)}, -j {jobs} on {os.cpu_count()} cores, {designs} designs asked for "
      f"(generational: {generations + 1} generations of {population}); medians of {repeats} alternating runs")
summary = {}
for mode, rs in runs.items():
    s = {key: m([r[key] for r in rs]) for key in rs[0]}
    span = lambda key: f"{min(r[key] for r in rs):.2f}..{max(r[key] for r in rs):.2f}"
    print(f"{mode:12s} busy cores {s['busy']:5.2f} ({span('busy')}), wall {s['wall']:6.1f} s, "
          f"{s['distinct']:.0f} distinct designs, {s['per_second']:.2f} designs/s ({span('per_second')})")
    if mode == "generational":
        print(f"{'':12s} of the {s['asked']:.0f} designs its generations asked for, "
              f"{1 - s['searched'] / s['asked']:.0%} were clones of designs already run")
    summary[mode] = {"median": s, "runs": rs}
if len(summary) == 2:
    a, g = summary["asynchronous"]["median"], summary["generational"]["median"]
    print(f"asynchronous / generational: busy cores {a['busy'] / g['busy']:.2f}x, distinct designs per second "
          f"{a['per_second'] / g['per_second']:.2f}x (their designs differ, and so does their cost)")
if out:
    json.dump({"space": os.path.basename(space), "jobs": jobs, "cores": os.cpu_count(), "designs": designs,
               "generational_designs": gen_designs,
               "population": population, "repeats": repeats, "modes": summary}, open(out, "w"), indent=1)
PY
