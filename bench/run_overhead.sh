#!/usr/bin/env bash
# What `granstack run` adds to LIGGGHTS in CPU time (the referee's fourth round: within 3 % of bare
# LIGGGHTS), measured case by case: each of the study's cases is run bare (`liggghts -in in.stack`
# in a copy of its inputs, its screen output to a file as granstack writes it) and by `granstack
# run --force` on the case, one right after the other (which goes first alternates case by case and
# round by round), two such pairs at a time on the 2 cores. The machine's CPU time drifts by 15 %
# over minutes (bench/reproduce.sh's rounds), by far less over the seconds between a case and its
# twin; summed over the cases, the two totals compare what the same decks cost either way.
# granstack's own process (every thread, not LIGGGHTS) is read from /proc/PID/stat beside it,
# and so is that of `granstack --version` (a start alone: this benchmark starts granstack once per
# case, where `granstack run -j 2 CASES...` starts it once).
# Usage: bench/run_overhead.sh [REPEATS]   (about 2 minutes a round; CASES=DIR takes the cases of a
# reproduction already made with `granstack reproduce -o DIR`; OUT=FILE.json keeps the record)
set -euo pipefail
repeats=${1:-3}
source "$(dirname "$0")/common.sh"
if [ -z "${CASES:-}" ]; then
  "$gs" reproduce -o "$work/all" -j 2 >/dev/null
  CASES=$work/all
fi
mapfile -t cases < <(find "$CASES" -name manifest.json -not -path '*/validate/*' -printf '%h\n' | sort)
for ((i = 0; i < ${#cases[@]}; i++)); do
  mkdir -p "$work/bare/$i/dumps"
  cp "${cases[$i]}/in.stack" "${cases[$i]}/data.stack" "$work/bare/$i/"
done
OUT="${OUT:-}" python3 - "$repeats" "$gs" "$work" "${cases[@]}" <<'PY'
import concurrent.futures, json, os, resource, shutil, statistics, subprocess, sys, threading, time
repeats, gs, work, cases = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4:]
liggghts, TICK = shutil.which("liggghts"), os.sysconf("SC_CLK_TCK")

def timed(args, cwd=None, stdout=subprocess.DEVNULL):
    """CPU time of the process and everything it started (wait4's rusage), and of the process alone
    (/proc/PID/stat, read every 10 ms until it ends)."""
    p = subprocess.Popen(args, cwd=cwd, stdout=stdout, stderr=subprocess.DEVNULL)
    own = 0.0
    while True:
        try:
            fields = open(f"/proc/{p.pid}/stat").read().rsplit(")", 1)[1].split()
            own = (int(fields[11]) + int(fields[12])) / TICK
        except (OSError, IndexError, ValueError):
            pass
        pid, status, usage = os.wait4(p.pid, os.WNOHANG)
        if pid:
            break
        time.sleep(0.01)
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        raise subprocess.CalledProcessError(p.returncode, args)
    # wait4 gives the process's own usage with its waited-for children's.
    return usage.ru_utime + usage.ru_stime, own

def bare(i):
    d = os.path.join(work, "bare", str(i))
    with open(os.path.join(d, "screen.txt"), "w") as screen:
        return timed([liggghts, "-in", "in.stack", "-log", "log.liggghts"], cwd=d, stdout=screen)[0]

def pair(i, r):
    run_first = (i + r) % 2 == 0
    if run_first:
        g = timed([gs, "run", "--force", cases[i]])
        b = bare(i)
    else:
        b = bare(i)
        g = timed([gs, "run", "--force", cases[i]])
    return b, g[0], g[1]

rounds = []
for r in range(repeats):
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        results = list(pool.map(lambda i: pair(i, r), range(len(cases))))
    start = statistics.median(timed([gs, "--version"])[1] for _ in range(5))
    b, g, o = (sum(x[k] for x in results) for k in range(3))
    rounds.append({"bare": b, "run": g, "own": o, "start": start})
    print(f"round {r + 1}: bare LIGGGHTS {b:.1f} s, granstack run {g:.1f} s (its own process {o:.2f} s), "
          f"run / bare {g / b:.4f}", flush=True)
m = statistics.median
ratio = [x["run"] / x["bare"] for x in rounds]
own = [x["own"] / x["bare"] for x in rounds]
starts = [len(cases) * x["start"] / x["bare"] for x in rounds]
print(f"{len(cases)} cases, each run bare and by granstack run one after the other, {repeats} rounds (median, min..max):")
print(f"granstack run / bare LIGGGHTS, CPU time: {m(ratio):.4f} ({min(ratio):.4f}..{max(ratio):.4f})")
print(f"granstack's own process / bare LIGGGHTS: {100 * m(own):.2f} % ({100 * min(own):.2f}..{100 * max(own):.2f}); "
      f"of which the {len(cases)} starts of granstack (--version's own time each): {100 * m(starts):.2f} %")
if os.environ["OUT"]:
    json.dump({"cases": len(cases), "cores": os.cpu_count(), "pairs_at_once": 2, "repeats": repeats, "rounds": rounds},
              open(os.environ["OUT"], "w"), indent=1)
PY
