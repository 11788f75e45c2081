#!/usr/bin/env bash
# What the blow-end judge costs LIGGGHTS: the study's decks as two builds write them, run bare
# (`liggghts -in in.stack` in a copy of each case's deck and data), case by case, the base build's
# deck and this build's one right after the other (which goes first alternates case by case and
# round by round), two such pairs at a time on the 2 cores; per round the CPU time summed over the
# cases. The two decks must give the same dumps and series, byte for byte (the judge reads the run,
# it never changes it): the script stops if a pair differs.
# Usage: GRANSTACK=<this build> GRANSTACK_BASE=<the base build> OUT=FILE.json bench/blow_end_judge.sh [REPEATS]
#   (each build makes the study with `granstack reproduce -o DIR -j 2`; about 3 minutes a round;
#   BASE_STUDY=DIR and THIS_STUDY=DIR take reproductions each build made already instead)
set -euo pipefail
repeats=${1:-3}
source "$(dirname "$0")/common.sh"
if [ -n "${BASE_STUDY:-}" ] && [ -n "${THIS_STUDY:-}" ]; then
  ln -s "$(cd "$BASE_STUDY" && pwd)" "$work/base"
  ln -s "$(cd "$THIS_STUDY" && pwd)" "$work/this"
else
  : "${GRANSTACK_BASE:?set GRANSTACK_BASE to the granstack whose decks are the baseline (or BASE_STUDY and THIS_STUDY)}"
  "$GRANSTACK_BASE" reproduce -o "$work/base" -j 2 >/dev/null
  "$gs" reproduce -o "$work/this" -j 2 >/dev/null
fi
mapfile -t cases < <(cd "$work/this/" && find . -name manifest.json -not -path '*/validate/*' -printf '%h\n' | sort)
for build in base this; do
  for ((i = 0; i < ${#cases[@]}; i++)); do
    mkdir -p "$work/bare_$build/$i/dumps"
    cp "$work/$build/${cases[$i]}/in.stack" "$work/$build/${cases[$i]}/data.stack" "$work/bare_$build/$i/"
  done
done
OUT="${OUT:-}" python3 - "$repeats" "$work" "${#cases[@]}" <<'PY'
import concurrent.futures, filecmp, json, os, shutil, statistics, subprocess, sys
repeats, work, n = int(sys.argv[1]), sys.argv[2], int(sys.argv[3])
liggghts = shutil.which("liggghts")

def bare(build, i):
    d = os.path.join(work, f"bare_{build}", str(i))
    with open(os.path.join(d, "screen.txt"), "w") as screen:
        p = subprocess.Popen([liggghts, "-in", "in.stack", "-log", "log.liggghts"], cwd=d, stdout=screen,
                             stderr=subprocess.DEVNULL)
        _, status, usage = os.wait4(p.pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"LIGGGHTS failed on {d}")
    return usage.ru_utime + usage.ru_stime

def outputs(build, i):
    d = os.path.join(work, f"bare_{build}", str(i))
    files = sorted(os.path.relpath(os.path.join(r, f), d) for r, _, fs in os.walk(d) for f in fs
                   if f.startswith("dump") or f == "ke_series.txt")
    return d, files

def pair(i, r):
    order = ["base", "this"] if (i + r) % 2 == 0 else ["this", "base"]
    t = {b: bare(b, i) for b in order}
    (a, fa), (b, fb) = outputs("base", i), outputs("this", i)
    if fa != fb or not all(filecmp.cmp(os.path.join(a, f), os.path.join(b, f), shallow=False) for f in fa):
        raise SystemExit(f"case {i}: the two decks' outputs differ")
    return t["base"], t["this"]

rounds = []
for r in range(repeats):
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        results = list(pool.map(lambda i: pair(i, r), range(n)))
    base, this = (sum(x[k] for x in results) for k in range(2))
    rounds.append({"base": base, "this": this})
    print(f"round {r + 1}: bare LIGGGHTS on the base build's decks {base:.1f} s, on this build's {this:.1f} s, "
          f"this / base {this / base:.4f}", flush=True)
ratio = [x["this"] / x["base"] for x in rounds]
print(f"{n} cases, outputs byte for byte the same; CPU time this / base, median of {repeats} rounds: "
      f"{statistics.median(ratio):.4f} ({min(ratio):.4f}..{max(ratio):.4f})")
if os.environ.get("OUT"):
    with open(os.environ["OUT"], "w") as f:
        json.dump({"cases": n, "cores": 2, "pairs_at_once": 2, "repeats": repeats, "rounds": rounds,
                   "ratio_median": statistics.median(ratio)}, f, indent=1)
PY
