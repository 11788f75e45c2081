#!/usr/bin/env bash
# The yielding example's front as docs/how-to/design.md shows it (issue #67 item 1): the shipped
# examples/design/yielding_protector.toml (Thornton's contacts, each blow at p_y = 1.6 Y and 3 Y),
# searched with the generational schedule (which repeats bit for bit) for GENERATIONS generations
# on 2 cores, with each front design and study design beside its elastic twin (Hertz, e = 1); then
# the front's first CONFIRM designs confirmed on LIGGGHTS (two runs at a time), which runs thornton_ning (Thornton's law
# it lacks), beside refsim under the same law, with the two laws' spread on each objective.
# Writes the record scripts/doc_tables.py makes the how-to's table and text from (OUT, JSON).
# Usage: OUT=bench/results/design-yield-front-DATE.json [GENERATIONS=6] [CONFIRM=2] bench/design_yield_front.sh
set -euo pipefail
source "$(dirname "$0")/common.sh"
: "${OUT:?set OUT to the record to write (bench/results/design-yield-front-DATE.json)}"
generations=${GENERATIONS:-6}
sed -e 's/^\[search\]$/[search]\nevaluation = "generational"/' -e "s/^generations = .*/generations = $generations/" \
  -e '/^algorithm = /d' -e '/^stagnation = /d' -e '/^time_limit = /d' "$here/examples/design/yielding_protector.toml" \
  > "$work/example.toml"
grep -q '^evaluation = "generational"' "$work/example.toml"
t0=$(date +%s.%N)
"$gs" design run "$work/example.toml" -o "$work/search" -j 2 >/dev/null 2>&1
t1=$(date +%s.%N)
confirm=${CONFIRM:-2}
# confirm exits 1 when the engines disagree: the record says so, the script goes on.
[ "$confirm" -gt 0 ] && { "$gs" design confirm "$work/search" --top "$confirm" -j 2 > "$work/confirm.txt" 2>&1 || true; }
t2=$(date +%s.%N)
python3 - "$work" "$t0" "$t1" "$t2" "$("$gs" --version)" "$(nproc)" "$generations" "$confirm" > "$OUT" <<'PY'
import json, sqlite3, sys
work, t0, t1, t2, version, cores = sys.argv[1], *map(float, sys.argv[2:5]), sys.argv[5], int(sys.argv[6])
generations, confirm = int(sys.argv[7]), int(sys.argv[8])
confirmations = []
for digest, verdict, largest, objectives, law in sqlite3.connect(f"{work}/search/design.sqlite").execute(
        "select digest, verdict, largest_difference, objective_difference, law from confirmations order by rowid"):
    law = json.loads(law or "{}")
    confirmations.append({"digest": digest, "verdict": verdict.replace(work + "/", ""), "largest_difference": largest,
                          "objective_difference": objectives, "law": law.get("law"), "law_spread": law.get("spread", {}),
                          "yield_range": law.get("yield_range"), "not_run": law.get("not_run")})
report = json.load(open(f"{work}/search/report/design.json"))
md = open(f"{work}/search/report/design.md").read()
# The report's section beside the elastic model: its paragraphs, as the report prints them.
section = md.split("## Beside the elastic model\n", 1)[1].split("\n## ", 1)[0]
paragraphs = [p for p in section.split("\n\n") if p.strip() and not p.startswith(("*", "|"))]
keep = ("description", "digest", "spheres", "areal_mass", "objectives", "measures", "feasible", "violations")
twins = report.get("elastic_twins", {})
print(json.dumps({
    "what": f"examples/design/yielding_protector.toml searched (generational, {generations} generations), each front "
            "design and study design beside its elastic twin",
    "command": f"OUT=... GENERATIONS={generations} CONFIRM={confirm} bench/design_yield_front.sh", "granstack": version,
    "cores": cores, "search_seconds": round(t1 - t0, 1), "confirm_seconds": round(t2 - t1, 1),
    "evaluations": report["evaluations"], "confirmations": confirmations,
    "front": [{**{k: e[k] for k in keep}, "elastic": {k: twins[e["digest"]][k] for k in keep}} for e in report["front"]],
    "study": [{"name": s["name"], **{k: s[k] for k in keep}, "elastic": {k: twins[s["digest"]][k] for k in keep}}
              for s in report["study_designs"]],
    "beside_elastic": paragraphs,
}, indent=1))
PY
echo "wrote $OUT"
