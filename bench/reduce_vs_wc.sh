#!/usr/bin/env bash
# Reading speed of `granstack reduce` against `wc -l` on the same file, measured in one run
# (issue #3, section 5): a full-precision text dump of the 961-sphere stack (every step for
# 2e-4 s, about 440 MB, written by refsim in LIGGGHTS's format) and its binary twin. Warm page
# cache; medians of REPEATS runs; peak memory of reduce from /usr/bin/time.
# Usage: bench/reduce_vs_wc.sh [REPEATS] [DURATION]   (a minute or two, about 1 GB of disk)
set -euo pipefail
repeats=${1:-3}
duration=${2:-2e-4}
here=$(cd "$(dirname "$0")/.." && pwd)
gs=${GRANSTACK:-$here/build/release/app/granstack}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for format in text binary; do
  "$gs" generate -o "$work/$format" --blocks 4 --top-columns 8 --duration "$duration" --dump-every 1 \
    --series-every 1000000000 --dump-format "$format" >/dev/null
  "$gs" run --engine refsim "$work/$format" >/dev/null
done
python3 - "$gs" "$work" "$repeats" <<'PY'
import os, statistics, subprocess, sys, time
gs, work, repeats = sys.argv[1], sys.argv[2], int(sys.argv[3])
def timed(cmd):
    t = time.perf_counter(); subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL); return time.perf_counter() - t
def rss(cmd):
    out = subprocess.run(["/usr/bin/time", "-f", "%M"] + cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    return int(out.stderr.strip().splitlines()[-1]) / 1024
for fmt, name in (("text", "dump.txt"), ("binary", "dump.bin")):
    path = os.path.join(work, fmt, "dumps", name)
    size = os.path.getsize(path) / 1e6
    subprocess.run(["cat", path], stdout=subprocess.DEVNULL)  # warm the page cache
    wc = statistics.median(timed(["wc", "-l", path]) for _ in range(repeats))
    red = statistics.median(timed([gs, "reduce", os.path.join(work, fmt)]) for _ in range(repeats))
    print(f"{fmt:6s} dump {size:7.0f} MB: wc -l {size / wc:7.0f} MB/s, reduce {size / red:6.0f} MB/s "
          f"(ratio {wc / red:.3f}), reduce peak memory {rss([gs, 'reduce', os.path.join(work, fmt)]):.0f} MB")
PY
