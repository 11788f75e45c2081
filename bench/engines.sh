#!/usr/bin/env bash
# The three engines on the same cases (issue #35): how far apart they are, and how fast.
# 1. Agreement (deterministic, run once): `granstack validate --engines A,B` on the elastic
#    two-body collision of physics.md section 5 and small stacks (3 blocks of 4 rows): elastic,
#    with a bottom wall, damped (e = 0.9), damped on a wall, frictional (mu = 0.3), and frictional
#    with walls and gravity; each pair of LIGGGHTS, LAMMPS and refsim (by LIGGGHTS's rules beside
#    LIGGGHTS, by LAMMPS's beside LAMMPS): the largest relative difference over every dumped
#    column, series column and the output fraction, and where.
# 2. Speed: `granstack run` on the quickstart stack (241 spheres, e = 1) and the 961-sphere
#    damped frictional stack (8 top columns, e = 0.9, mu = 0.25), each with its default outputs and
#    with outputs off (dumps and series at the run's length); LIGGGHTS and LAMMPS one rank, refsim
#    one thread (its best kernels, LIGGGHTS's rules); loop seconds from run.json,
#    engines alternating, medians of REPEATS runs.
# Usage: bench/engines.sh [REPEATS]   (OUT=FILE.json keeps the record; about 4 minutes with 3)
set -euo pipefail
repeats=${1:-3}
source "$(dirname "$0")/common.sh"

# --- 1. agreement ---
declare -A spec=(
  [two_body]="--blocks 1 --rows 1 --top-columns 2 --striker-radius-ratio 2"
  [elastic]="--blocks 3 --rows 4"
  [elastic_wall]="--blocks 3 --rows 4 --bottom wall"
  [damped]="--blocks 3 --rows 4 --restitution 0.9"
  [damped_wall]="--blocks 3 --rows 4 --restitution 0.9 --bottom wall"
  [friction]="--blocks 3 --rows 4 --restitution 0.9 --friction 0.3"
  [friction_walls_gravity]="--blocks 3 --rows 4 --restitution 0.9 --friction 0.3 --bottom wall --sides wall --gravity"
)
agreement_cases=(two_body elastic elastic_wall damped damped_wall friction friction_walls_gravity)
agreement=""
for c in "${agreement_cases[@]}"; do
  for pair in liggghts,lammps lammps,refsim liggghts,refsim; do
    dir="$work/agree_${c}_${pair/,/_}"
    # shellcheck disable=SC2086
    "$gs" generate -o "$dir" ${spec[$c]} >/dev/null
    last=$("$gs" validate --engines "$pair" "$dir" 2>&1 | tail -1) || true
    agreement+="$c $pair $last"$'\n'
  done
done

# --- 2. speed ---
declare -A args=([quick]="" [damped]="--top-columns 8 --restitution 0.9 --friction 0.25")
off=(--series-every 1000000000)
for c in quick damped; do
  # shellcheck disable=SC2086
  "$gs" generate -o "$work/$c" ${args[$c]} >/dev/null
  # shellcheck disable=SC2086
  generate_ends_only "$work/${c}_off" ${args[$c]} "${off[@]}" >/dev/null
done
loop() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['loop_seconds'])" "$1/run.json"; }
declare -A t
for ((k = 1; k <= repeats; k++)); do
  for c in quick damped; do
    for o in "" _off; do
      for e in liggghts lammps refsim; do
        dir="$work/$c$o.$e"
        [ -d "$dir" ] || cp -r "$work/$c$o" "$dir"
        "$gs" run --force --engine "$e" "$dir" >/dev/null
        t[$c$o.$e]+="$(loop "$dir") "
      done
    done
  done
done

{
  echo "$repeats"
  printf '%s' "$agreement"
  echo "--"
  for key in "${!t[@]}"; do echo "$key ${t[$key]}"; done
} | OUT="${OUT:-}" python3 -c '
import json, os, re, statistics, sys
lines = sys.stdin.read().splitlines()
repeats = int(lines[0])
cut = lines.index("--")
agreement = []
for l in lines[1:cut]:
    case, pair, verdict = l.split(" ", 2)
    m = re.search(r"largest difference (\S+) \(([^)]*)\)", verdict)
    agreement.append({"case": case, "engines": pair.split(","), "agree": verdict.startswith("agree"),
                      "largest": float(m.group(1)) if m else None, "where": m.group(2) if m else verdict})
t = {l.split()[0]: [float(x) for x in l.split()[1:]] for l in lines[cut + 1:]}
speed = {k: {"runs": v, "median": statistics.median(v)} for k, v in sorted(t.items())}
names = {"quick": "quickstart, 241 spheres, e = 1", "damped": "961 spheres, e = 0.9, mu = 0.25"}
print("agreement: largest relative difference (validate), and where")
for a in agreement:
    case, (first, second), largest, where = a["case"], a["engines"], a["largest"], a["where"]
    verdict = "agree" if a["agree"] else "DIFFER"
    print(f"  {case:24s} {first:9s} {second:8s} {largest:.3g}  {verdict}  ({where})")
print(f"loop seconds, medians of {repeats} alternating runs (min..max), one rank or thread")
for o, title in (("", "default outputs"), ("_off", "outputs off")):
    print(" ", title)
    for c in ("quick", "damped"):
        row = f"    {names[c]:32s}"
        for e in ("liggghts", "lammps", "refsim"):
            r = t[f"{c}{o}.{e}"]
            row += f"  {e} {statistics.median(r):.3f} s ({min(r):.3f}..{max(r):.3f})"
        print(row)
if os.environ["OUT"]:
    json.dump({"repeats": repeats, "agreement": agreement, "speed": speed, "cases": names}, open(os.environ["OUT"], "w"), indent=1)
'
