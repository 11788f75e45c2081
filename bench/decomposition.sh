#!/usr/bin/env bash
# How LIGGGHTS shares big nests among MPI ranks (issue #36), from its own output: the owned
# spheres of the busiest rank over the mean (Nlocal max / ave) and the ghost spheres per owned
# one (Nghost ave / Nlocal ave), at 16 and 64 ranks, for the 97,921-sphere nest (4 blocks under
# 8 x 8 top columns, 18 rows) and a 991,441-sphere one (18 x 18 top columns, 36 rows), each on
# the grid granstack chooses and on the deck as it was before (the data file's box one top
# radius wider than the lattice in x and y, the grid LIGGGHTS chose for `processors * * 1`).
# Deterministic: counts, not times, so a 2-core machine measures them (ranks oversubscribed, 4
# steps each). Also granstack's prediction beside its choice (they agree to the last digit
# LIGGGHTS prints).
# With OUT set, also writes the rows to $OUT/decomposition.json (the docs' table is made from the
# one kept in bench/results/ by scripts/doc_tables.py).
# Usage: bench/decomposition.sh   (about four minutes on 2 cores)
set -euo pipefail
source "$(dirname "$0")/common.sh"
few=(--dt 6.27e-8 --duration 2.508e-7 --dump-every 2 --series-every 2)
declare -A nests=([97921]="--blocks 4 --top-columns 8 --rows 18" [991441]="--blocks 4 --top-columns 18 --rows 36")
printf '%-8s %5s %-7s %-8s %16s %16s %18s\n' spheres ranks deck grid "busiest / mean" "ghosts / owned" "predicted (b, g)"
for n in 97921 991441; do
  # shellcheck disable=SC2086
  "$gs" generate -o "$work/$n" --geometry nested3d ${nests[$n]} "${few[@]}" >/dev/null
  cp -r "$work/$n" "$work/$n-before"
  widen_box_as_before "$work/$n-before/data.stack"
  for ranks in 16 64; do
    side=$([ "$ranks" = 16 ] && echo 4 || echo 8)
    # granstack's choice, with its prediction beside LIGGGHTS's counts
    "$gs" run --force --np "$ranks" "$work/$n" >/dev/null 2>&1
    python3 - "$work/$n/run.json" "$n" "$ranks" "$work/rows.jsonl" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))["decomposition"]
l, p = d["liggghts"], d["predicted"]
grid = "x".join(str(g) for g in l["grid"])
print(f"{sys.argv[2]:8s} {sys.argv[3]:>5s} {'now':7s} {grid:8s} {l['busiest_over_mean']:16.3f} {l['ghosts_per_owned']:16.3f}"
      f"     ({p['busiest_over_mean']:.3f}, {p['ghosts_per_owned']:.3f})")
row = {"spheres": int(sys.argv[2]), "ranks": int(sys.argv[3]), "deck": "now", "grid": l["grid"],
       "busiest_over_mean": l["busiest_over_mean"], "ghosts_per_owned": l["ghosts_per_owned"],
       "predicted": {"busiest_over_mean": p["busiest_over_mean"], "ghosts_per_owned": p["ghosts_per_owned"]}}
open(sys.argv[4], "a").write(json.dumps(row) + "\n")
PY
    # the deck as it was: granstack refuses an edited data file, so LIGGGHTS runs it directly,
    # on the grid it chose for `processors * * 1` (side x side x 1)
    read -r _ _ busiest ghosts < <(liggghts_directly "$work/$n-before" "$ranks" "$side" "$side" 1)
    printf '%-8s %5s %-7s %-8s %16.3f %16.3f\n' "$n" "$ranks" before "${side}x${side}x1" "$busiest" "$ghosts"
    printf '{"spheres": %s, "ranks": %s, "deck": "before", "grid": [%s, %s, 1], "busiest_over_mean": %s, "ghosts_per_owned": %s}\n' \
      "$n" "$ranks" "$side" "$side" "$busiest" "$ghosts" >>"$work/rows.jsonl"
  done
done
[ -n "${OUT:-}" ] && python3 -c "import json,sys; json.dump([json.loads(l) for l in open(sys.argv[1])], open(sys.argv[2], 'w'), indent=1)" \
  "$work/rows.jsonl" "$OUT/decomposition.json"
exit 0
