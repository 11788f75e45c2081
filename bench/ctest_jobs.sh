#!/usr/bin/env bash
# The test suite's wall time at 2, 3 and 4 ctest jobs on this machine, the runs alternating
# (the suite as CI runs it: the ci build, already built). Chooses the ci preset's jobs: tests
# that wait on LIGGGHTS, SLURM or a program they started leave a core idle at one job per core.
# Usage: bench/ctest_jobs.sh [REPEATS]   (seconds; each repeat runs the suite three times)
set -euo pipefail
repeats=${1:-1}
cd "$(dirname "$0")/../build/ci"
python3 - "$repeats" <<'PY'
import statistics, subprocess, sys, time
repeats = int(sys.argv[1])
runs = {2: [], 3: [], 4: []}
for _ in range(repeats):
    for jobs in runs:
        t = time.perf_counter()
        rc = subprocess.run(["ctest", f"-j{jobs}"], stdout=subprocess.DEVNULL).returncode
        runs[jobs].append(time.perf_counter() - t)
        print(f"-j{jobs}: {runs[jobs][-1]:.0f} s (exit {rc})", flush=True)
print("medians: " + ", ".join(f"-j{j} {statistics.median(v):.0f} s" for j, v in runs.items()))
PY
