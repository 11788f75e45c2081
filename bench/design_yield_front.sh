#!/usr/bin/env bash
# The yielding example's front as docs/how-to/design.md shows it (issue #67 item 1): the shipped
# examples/design/yielding_protector.toml (Thornton's contacts, each blow at p_y = 1.6 Y and 3 Y),
# searched with the generational schedule (which repeats bit for bit) for GENERATIONS generations
# on 2 cores, with each front design and study design beside its elastic twin (Hertz, e = 1).
# Writes the record scripts/doc_tables.py makes the how-to's table and text from (OUT, JSON).
# Usage: OUT=bench/results/design-yield-front-DATE.json [GENERATIONS=6] bench/design_yield_front.sh
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
python3 - "$work" "$t0" "$t1" "$("$gs" --version)" "$(nproc)" "$generations" > "$OUT" <<'PY'
import json, sys
work, t0, t1, version, cores, generations = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), sys.argv[4], int(sys.argv[5]), int(sys.argv[6])
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
    "command": f"OUT=... GENERATIONS={generations} bench/design_yield_front.sh", "granstack": version, "cores": cores,
    "search_seconds": round(t1 - t0, 1), "evaluations": report["evaluations"],
    "front": [{**{k: e[k] for k in keep}, "elastic": {k: twins[e["digest"]][k] for k in keep}} for e in report["front"]],
    "study": [{"name": s["name"], **{k: s[k] for k in keep}, "elastic": {k: twins[s["digest"]][k] for k in keep}}
              for s in report["study_designs"]],
    "beside_elastic": paragraphs,
}, indent=1))
PY
echo "wrote $OUT"
