#!/usr/bin/env bash
# What a granstack command costs before it does anything: `granstack --version` and `granstack
# status` of a one-sphere-row case, against /bin/true (the process start itself), and against
# another build when GRANSTACK_BASE names one (an A/B of a change). Every command pays this once;
# the test suite starts granstack thousands of times. Medians of REPEATS alternating runs.
# Usage: bench/startup.sh [REPEATS]   (seconds)
set -euo pipefail
repeats=${1:-31}
source "$(dirname "$0")/common.sh"
"$gs" generate -o "$work/case" --blocks 1 --rows 2 >/dev/null
python3 - "$gs" "$work/case" "$repeats" "${GRANSTACK_BASE:-}" <<'PY'
import statistics, subprocess, sys, time
gs, case, repeats, base = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
commands = {"true": ["/bin/true"], "version": [gs, "--version"], "status": [gs, "status", case]}
if base:
    commands.update({"base version": [base, "--version"], "base status": [base, "status", case]})
runs = {k: [] for k in commands}
for _ in range(repeats):
    for k, cmd in commands.items():
        t = time.perf_counter()
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        runs[k].append(time.perf_counter() - t)
ms = {k: 1e3 * statistics.median(v) for k, v in runs.items()}
print(f"medians of {repeats} alternating runs, ms: " + ", ".join(f"{k} {v:.1f}" for k, v in ms.items()))
for k in [k for k in ms if k != "true"]:
    print(f"  {k}: {ms[k] - ms['true']:.1f} ms beyond the process start")
PY
