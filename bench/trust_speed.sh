#!/usr/bin/env bash
# What the trust checks cost (issue #46): `granstack reduce` of a LIGGGHTS text dump (the
# 961-sphere stack, 4 blocks of 8 top columns, dumped every 8 steps: about 300 MB), which digests
# the run's outputs against run.json, against `wc -l` on the same file; and `granstack submit
# --dry-run` of a 10,000-case sweep (a config file's lists: 4 block counts x 2500 restitutions),
# which reads and checks every manifest. With GRANSTACK_BASE, another build (e.g. the commit
# before) is timed in the same rounds, alternating. Warm page cache; medians of REPEATS rounds.
# Usage: [GRANSTACK_BASE=...] [OUT=FILE.json] bench/trust_speed.sh [REPEATS]   (about 3 minutes)
set -euo pipefail
repeats=${1:-5}
source "$(dirname "$0")/common.sh"
base=${GRANSTACK_BASE:-}
# Each build reduces a case it ran itself (run.json's digests are each build's own kind); LIGGGHTS
# writes the same bytes for both.
for name in this ${base:+base}; do
  exe=$gs
  [ "$name" = base ] && exe=$base
  "$exe" generate -o "$work/big-$name" --blocks 4 --top-columns 8 --dump-every 8 >/dev/null
  "$exe" run "$work/big-$name" >/dev/null
done
[ -z "$base" ] || cmp "$work/big-this/dumps/dump.txt" "$work/big-base/dumps/dump.txt"
python3 -c "
print('blocks = [1, 2, 3, 4]')
print('restitution = [' + ', '.join(str(round(0.5 + i * 0.0002, 4)) for i in range(2500)) + ']')" > "$work/sweep.toml"
"$gs" generate --large -o "$work/sweep" --config "$work/sweep.toml" >/dev/null 2>&1
OUT="${OUT:-}" python3 - "$gs" "$base" "$work" "$repeats" <<'PY'
import json, os, statistics, subprocess, sys, time
gs, base, work, repeats = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
dump = os.path.join(work, "big-this", "dumps", "dump.txt")
size = os.path.getsize(dump) / 1e6
def timed(cmd):
    t = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t
subprocess.run(["cat", dump], stdout=subprocess.DEVNULL)  # warm the page cache
builds = {"this": gs, **({"base": base} if base else {})}
runs = {"wc": []}
for name in builds:
    runs[f"reduce_{name}"], runs[f"submit_{name}"] = [], []
for _ in range(repeats):
    runs["wc"].append(timed(["wc", "-l", dump]))
    for name, exe in builds.items():
        runs[f"reduce_{name}"].append(timed([exe, "reduce", os.path.join(work, "big-" + name)]))
        runs[f"submit_{name}"].append(timed([exe, "submit", "--dry-run", os.path.join(work, "sweep")]))
m = statistics.median
print(f"{os.cpu_count()} cores; medians of {repeats} alternating rounds; a {size:.0f} MB LIGGGHTS text dump")
print(f"wc -l {m(runs['wc']):.3f} s ({size / m(runs['wc']):.0f} MB/s)")
# wc -l takes 45-70 ms on these machines as their load drifts: the ratio is also given per round
# (reduce against the wc -l of its own round), whose median drift moves less.
ratios = {name: [w / r for w, r in zip(runs["wc"], runs[f"reduce_{name}"])] for name in builds}
for name in builds:
    r, s = m(runs[f"reduce_{name}"]), m(runs[f"submit_{name}"])
    print(f"{name}: reduce {r:.3f} s ({size / r:.0f} MB/s, {m(runs['wc']) / r:.3f} of wc -l; per round, median "
          f"{m(ratios[name]):.3f}, {min(ratios[name]):.3f}..{max(ratios[name]):.3f}); "
          f"submit --dry-run of 10,000 cases {s:.2f} s")
if os.environ["OUT"]:
    json.dump({"cores": os.cpu_count(), "repeats": repeats, "dump_mb": size, "builds": builds, "seconds": runs},
              open(os.environ["OUT"], "w"), indent=1)
PY
