#!/usr/bin/env bash
# The design example's front as docs/how-to/design.md shows it (issue #47 item 9): the shipped
# example (examples/design/least_wall_force.toml, confined), searched with the generational
# schedule (which repeats bit for bit) on 2 cores; its front's first two designs confirmed on
# LIGGGHTS, each also run as the free strip (confirm --sides free); the study's three designs run
# both confined and as free strips (the same space with sides = "free", whose search stops after
# one design: its study designs are what it is run for); and the share of all designs beyond first
# yield. Writes the record scripts/doc_tables.py makes the how-to's tables from (OUT, JSON).
# Usage: OUT=bench/results/design-front-DATE.json bench/design_front.sh   (about 30 minutes)
set -euo pipefail
source "$(dirname "$0")/common.sh"
: "${OUT:?set OUT to the record to write (bench/results/design-front-DATE.json)}"
# The search its record was made with: 10 generational generations (the example now runs until it stops improving).
sed -e 's/^\[search\]$/[search]\nevaluation = "generational"/' -e 's/^generations = .*/generations = 10/' -e '/^algorithm = /d' \
  -e '/^stagnation = /d' -e '/^time_limit = /d' "$here/examples/design/least_wall_force.toml" > "$work/example.toml"
sed 's/^sides = "wall".*/sides = "free"/' "$work/example.toml" > "$work/strip.toml"
grep -q '^sides = "free"' "$work/strip.toml"
t0=$(date +%s.%N)
"$gs" design run "$work/example.toml" -o "$work/confined" -j 2 >/dev/null 2>&1
t1=$(date +%s.%N)
# confirm exits 1 when an engine disagrees: the record says so, the script goes on.
"$gs" design confirm "$work/confined" --top 2 --sides free > "$work/confirm.txt" 2>&1 || true
t2=$(date +%s.%N)
"$gs" design run "$work/strip.toml" -o "$work/strip" -j 2 --max-designs 1 >/dev/null 2>&1
python3 - "$work" "$t0" "$t1" "$t2" "$("$gs" --version)" "$(nproc)" > "$OUT" <<'PY'
import json, sqlite3, sys
work, t0, t1, t2, version, cores = sys.argv[1], *map(float, sys.argv[2:5]), sys.argv[5], int(sys.argv[6])
def report(d):
    return json.load(open(f"{work}/{d}/report/design.json"))
confined, strip = report("confined"), report("strip")
db = sqlite3.connect(f"{work}/confined/design.sqlite")
ratios = [r[0] for r in db.execute("select yield_ratio from evaluations where searched = 1 and yield_ratio is not null")]
confirmations = []
for digest, verdict, largest, objective, variant in db.execute(
        "select digest, verdict, largest_difference, objective_difference, variant from confirmations order by rowid"):
    v = json.loads(variant)
    description, = db.execute("select description from evaluations where digest = ?", (digest,)).fetchone()
    confirmations.append({"digest": digest, "description": description, "verdict": verdict.replace(work + "/", ""),
                          "largest_difference": largest, "objective_difference": objective,
                          "variant": v.get("label", ""), "strip_measures": v.get("measures", {}),
                          "strip_not_final": v.get("not_final", "")})
keep = ("description", "digest", "spheres", "areal_mass", "objectives", "measures", "feasible", "violations")
print(json.dumps({
    "what": "examples/design/least_wall_force.toml searched (generational), confirm --top 2 --sides free on LIGGGHTS, "
            "the study's designs confined and as free strips",
    "command": "OUT=... bench/design_front.sh", "granstack": version, "cores": cores,
    "search_seconds": round(t1 - t0, 1), "confirm_seconds": round(t2 - t1, 1),
    "evaluations": confined["evaluations"],
    "yield": {"judged": len(ratios), "beyond_first_yield": sum(r > 1.0 for r in ratios),
              "smallest_ratio": min(ratios), "largest_ratio": max(ratios)},
    "front": [{k: e[k] for k in keep} for e in confined["front"]],
    "confirmations": confirmations,
    "study_confined": [{"name": s["name"], **{k: s[k] for k in keep}} for s in confined["study_designs"]],
    "study_strip": [{"name": s["name"], **{k: s[k] for k in keep}} for s in strip["study_designs"]],
}, indent=1))
PY
echo "wrote $OUT"
