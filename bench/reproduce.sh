#!/usr/bin/env bash
# Wall and CPU time of `granstack reproduce` (issue #12's speed targets: every experiment on
# LIGGGHTS in under 60 s on 2 cores, under 90 s with --validate, --quick under 30 s; the referee's
# fourth round: within 10 % of bare LIGGGHTS in CPU time), each from scratch (--force: every case
# generated, run, reduced and judged again), -j 2. Two baselines on the very same cases, two at a
# time: `granstack run -j 2 --force` (no reduce, no analysis, no report) and bare LIGGGHTS
# (`liggghts -in in.stack` in a copy of each case's inputs, what a user runs by hand), so the
# ratios say what reproduce adds to the engine's own time and what `run` adds to LIGGGHTS's.
# Runs the five alternately REPEATS times and reports the median (min..max) of each; CPU time is
# user + system of every process each one started (getrusage of the children).
# Usage: bench/reproduce.sh [REPEATS]   (about twelve minutes with 3; OUT=FILE.json keeps the
# record, from which the docs' "N cases, about T s on 2 cores" is made: scripts/doc_tables.py).
# GRANSTACK_BASE=PROGRAM adds another build's reproduce and run to the rounds (a change's before and
# after in the same run); RUNS="reproduce baseline_run bare_liggghts" times only those. Each granstack
# command's own CPU time (its process, not LIGGGHTS) is kept beside its total.
set -euo pipefail
repeats=${1:-3}
source "$(dirname "$0")/common.sh"
"$gs" reproduce -o "$work/all" -j 2 >/dev/null  # the cases the baselines run again
mapfile -t cases < <(find "$work/all" -name manifest.json -not -path '*/validate/*' -printf '%h\n' | sort)
# Bare LIGGGHTS's inputs: each case's deck and data file in a folder of its own.
for ((i = 0; i < ${#cases[@]}; i++)); do
  mkdir -p "$work/bare/$i/dumps"
  cp "${cases[$i]}/in.stack" "${cases[$i]}/data.stack" "$work/bare/$i/"
done
OUT="${OUT:-}" BASE="${GRANSTACK_BASE:-}" RUNS="${RUNS:-}" python3 - "$repeats" "$gs" "$work" "${cases[@]}" <<'PY'
import concurrent.futures, json, os, resource, shutil, statistics, subprocess, sys, time
repeats, gs, work, cases = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4:]
liggghts = shutil.which("liggghts")

def cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime

def timed(fn):
    t0, c0 = time.time(), cpu()
    own = fn()
    return time.time() - t0, cpu() - c0, own

TICK = os.sysconf("SC_CLK_TCK")

def command(*args):
    """A granstack command; it returns the CPU time of granstack's own process (every thread, not the
    programs it started), read from /proc/PID/stat every 20 ms until it ends: what granstack adds,
    measured in the same minute as the programs' time, so the machine's drift does not enter it."""
    def go():
        p = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        own = 0.0
        while p.poll() is None:
            try:
                fields = open(f"/proc/{p.pid}/stat").read().rsplit(")", 1)[1].split()
                own = (int(fields[11]) + int(fields[12])) / TICK  # utime, stime
            except (OSError, IndexError, ValueError):
                pass
            time.sleep(0.02)
        if p.returncode != 0:
            raise subprocess.CalledProcessError(p.returncode, args)
        return own
    return go

def bare_one(i):
    d = os.path.join(work, "bare", str(i))
    subprocess.run([liggghts, "-in", "in.stack", "-log", "log.liggghts"], cwd=d, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

def bare():
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        list(pool.map(bare_one, range(len(cases))))

runs = {"reproduce": command(gs, "reproduce", "-o", f"{work}/all", "-j", "2", "--force"),
        "baseline_run": command(gs, "run", "-j", "2", "--force", *cases),
        "bare_liggghts": bare,
        "validate": command(gs, "reproduce", "-o", f"{work}/validate", "-j", "2", "--force", "--validate"),
        "quick": command(gs, "reproduce", "-o", f"{work}/quick", "-j", "2", "--force", "--quick")}
base = os.environ["BASE"]
if base:
    runs["reproduce_base"] = command(base, "reproduce", "-o", f"{work}/all", "-j", "2", "--force")
    runs["baseline_run_base"] = command(base, "run", "-j", "2", "--force", *cases)
if os.environ["RUNS"]:
    runs = {k: fn for k, fn in runs.items() if k in os.environ["RUNS"].split()}
wall = {k: [] for k in runs}
cpus = {k: [] for k in runs}
own = {k: [] for k in runs if k != "bare_liggghts"}
for _ in range(repeats):
    for k, fn in runs.items():
        w, c, o = timed(fn)
        wall[k].append(w)
        cpus[k].append(c)
        if k in own:
            own[k].append(o)
m = statistics.median
f = lambda xs: f"{m(xs):6.1f} s  ({min(xs):.1f}..{max(xs):.1f})"
n = len(cases)
print(f"{repeats} alternating runs each, -j 2, from scratch (median, min..max): wall, CPU")
for k, label in [("reproduce", f"reproduce, every experiment ({n} cases)"), ("validate", "reproduce --validate"),
                 ("quick", "reproduce --quick"), ("baseline_run", f"granstack run -j 2 on the same {n} cases"),
                 ("bare_liggghts", "bare LIGGGHTS on the same cases, 2 at a time"),
                 ("reproduce_base", f"reproduce of {base}"), ("baseline_run_base", f"run of {base}")]:
    if k not in runs:
        continue
    print(f"{label:48s} {f(wall[k])}   CPU {f(cpus[k])}")
for a, b in [("reproduce", "bare_liggghts"), ("reproduce", "baseline_run"), ("baseline_run", "bare_liggghts"),
             ("reproduce_base", "bare_liggghts"), ("reproduce", "reproduce_base"), ("baseline_run", "baseline_run_base")]:
    if a not in runs or b not in runs:
        continue
    print(f"{a} / {b}: wall {m(wall[a]) / m(wall[b]):.3f}, CPU {m(cpus[a]) / m(cpus[b]):.3f}")
for k, xs in own.items():
    print(f"{k}: granstack's own process {m(xs):.1f} s of {m(cpus[k]):.1f} s CPU, its programs "
          f"{m([c - o for c, o in zip(cpus[k], xs)]):.1f} s (medians)")
if os.environ["OUT"]:
    record = {"cases": n, "cores": os.cpu_count(), "jobs": 2, "repeats": repeats, "seconds": wall, "cpu_seconds": cpus,
              "own_cpu_seconds": own}
    if base:
        record["base"] = subprocess.run([base, "--version"], capture_output=True, text=True, check=True).stdout.strip()
    json.dump(record,
              open(os.environ["OUT"], "w"), indent=1)
PY
