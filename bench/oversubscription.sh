#!/usr/bin/env bash
# What running more threads than CPUs costs refsim: one case (Fig. 3's three steel blocks of 8
# rows, the automatic duration) run with --threads 1 and with --threads 4 x the CPUs granstack
# may use, alternating, REPEATS times; the medians and their ratio as JSON on stdout (the record
# bench/results/oversubscription-DATE.json, which the reference's paragraph on `run`'s warning
# is made from: scripts/doc_tables.py).
# Usage: bench/oversubscription.sh [REPEATS]   (about a minute on 2 cores)
set -euo pipefail
repeats=${1:-3}
source "$(dirname "$0")/common.sh"
cpus=$(nproc)
many=$((4 * cpus))
"$gs" generate -o "$work/case" --blocks 3 --rows 8 >/dev/null
python3 - "$gs" "$work/case" "$repeats" "$cpus" "$many" <<'PY'
import json, statistics, subprocess, sys, time
gs, case, repeats, cpus, many = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
def timed(threads):
    t = time.perf_counter()
    subprocess.run([gs, "run", "--engine", "refsim", "--force", "--threads", str(threads), case], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t
runs = {1: [], many: []}
for _ in range(repeats):
    for threads in runs:
        runs[threads].append(timed(threads))
one, over = statistics.median(runs[1]), statistics.median(runs[many])
print(json.dumps({"benchmark": "bench/oversubscription.sh", "cpus": cpus, "case": "generate --blocks 3 --rows 8",
                  "repeats": repeats, "threads": many, "seconds_one_thread": one, "seconds_oversubscribed": over,
                  "ratio": over / one, "runs": {str(k): v for k, v in runs.items()}}, indent=2))
PY
