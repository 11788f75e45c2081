#!/usr/bin/env bash
# Reading speed of `granstack reduce` against `wc -l` on the same file, measured in one run
# (issue #3, section 5). The dump: the whole impact on the 961-sphere stack (4 blocks, 8 top
# columns, the automatic duration of 16 200 steps), every DUMP_EVERY steps, full precision,
# written by refsim in LIGGGHTS's format: about 1.1 GB of text at DUMP_EVERY=2, and its binary
# twin (decompressed: LIGGGHTS's bytes). Warm page cache; the three commands alternate, REPEATS
# times, and the medians count.
# Peak memory (from /usr/bin/time) is also taken on a quarter of the run, to show it does not
# grow with the number of frames.
# With OUT=FILE.json the medians are also written there (the performance page's table is made from
# such a record by scripts/doc_tables.py). With GRANSTACK_BASE=BUILD, that build's reduce (2
# threads) is timed in every round too, and each round's ratio of the two is kept: a change
# measured against the build before it on the same machine at the same time (these machines
# drift by 30 % within minutes, more than most changes).
# Usage: [GRANSTACK_BASE=BUILD] [OUT=FILE.json] bench/reduce_vs_wc.sh [REPEATS] [DUMP_EVERY]
#   (a few minutes, about 3 GB of disk)
set -euo pipefail
repeats=${1:-5}
every=${2:-2}
source "$(dirname "$0")/common.sh"
for format in text binary; do
  for part in full quarter; do
    duration=()
    [ "$part" = quarter ] && duration=(--duration 2.54e-4)
    "$gs" generate -o "$work/$format-$part" --blocks 4 --top-columns 8 --dump-every "$every" "${duration[@]}" \
      --series-every 1000000000 --dump-format "$format" >/dev/null
    "$gs" run --engine refsim "$work/$format-$part" >/dev/null
    # refsim writes its binary dump as a zstd stream: LIGGGHTS's own bytes are what is timed (the
    # run's digest is of the content, so reduce takes the plain file as the run's).
    if [ "$format" = binary ]; then
      zstd -q -d -c "$work/$format-$part/dumps/dump.bin" > "$work/plain.bin"
      mv "$work/plain.bin" "$work/$format-$part/dumps/dump.bin"
    fi
  done
done
OUT="${OUT:-}" python3 - "$gs" "$work" "$repeats" "${GRANSTACK_BASE:-}" <<'PY'
import json, os, statistics, subprocess, sys, time
gs, work, repeats, base = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
def timed(cmd):
    t = time.perf_counter(); subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL); return time.perf_counter() - t
def peak_mb(cmd):
    out = subprocess.run(["/usr/bin/time", "-f", "%M"] + cmd, check=True, stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, text=True)
    return int(out.stderr.strip().splitlines()[-1]) / 1024
print(f"{os.cpu_count()} cores; medians of {repeats} alternating runs")
version = subprocess.run([gs, "--version"], check=True, capture_output=True, text=True).stdout.strip()
out = {"granstack": version, "cores": os.cpu_count(), "repeats": repeats, "formats": {}}
if base:
    out["base"] = subprocess.run([base, "--version"], check=True, capture_output=True, text=True).stdout.strip()
for fmt, name in (("text", "dump.txt"), ("binary", "dump.bin")):
    case = os.path.join(work, fmt + "-full")
    path = os.path.join(case, "dumps", name)
    size = os.path.getsize(path) / 1e6
    subprocess.run(["cat", path], stdout=subprocess.DEVNULL)  # warm the page cache
    runs = {"wc": [], "reduce": [], "reduce1": []}
    if base:
        runs["reduce_base"] = []
    for k in range(repeats):
        runs["wc"].append(timed(["wc", "-l", path]))
        # the two builds in turn, each first in every other round
        for build in ([gs, base] if k % 2 == 0 else [base, gs]) if base else [gs]:
            runs["reduce" if build == gs else "reduce_base"].append(timed([build, "reduce", case]))
        runs["reduce1"].append(timed([gs, "reduce", "--threads", "1", case]))
    wc, red, red1 = (statistics.median(runs[k]) for k in ("wc", "reduce", "reduce1"))
    mem_full = peak_mb([gs, "reduce", case])
    mem_quarter = peak_mb([gs, "reduce", os.path.join(work, fmt + "-quarter")])
    print(f"{fmt:6s} dump {size:6.0f} MB: wc -l {size / wc:5.0f} MB/s; reduce {size / red:5.0f} MB/s "
          f"(ratio {wc / red:.3f}), on one thread {size / red1:5.0f} MB/s (ratio {wc / red1:.3f}); "
          f"peak memory {mem_full:.0f} MB (a quarter of the frames: {mem_quarter:.0f} MB)")
    out["formats"][fmt] = {"dump_mb": size, "seconds": runs, "ratio": wc / red, "ratio_one_thread": wc / red1,
                           "peak_mb": mem_full, "peak_mb_quarter": mem_quarter}
    if base:
        per_round = [b / a for a, b in zip(runs["reduce"], runs["reduce_base"])]
        faster = sum(x > 1 for x in per_round)
        out["formats"][fmt]["base_over_this"] = statistics.median(per_round)
        print(f"       the base build took {statistics.median(per_round):.3f} times as long (median of the rounds' "
              f"ratios; this build faster in {faster} of {repeats}); its ratio to wc -l "
              f"{wc / statistics.median(runs['reduce_base']):.3f}")
if os.environ["OUT"]:
    json.dump(out, open(os.environ["OUT"], "w"), indent=1)
PY
