#!/usr/bin/env bash
# What the blow's end gains by leaving out courses to the striker that run into other spheres
# (issue #67 item 5): each (design, scenario) a design store censored as "the striker was still
# coming" is made a case (its stored spec, the scenario's striker speed and yield pressure factor,
# stop = blow_end at CAP automatic durations) and run on refsim. The run stops where every course
# is gone (the rule the engines' decks judge, BlowEnd::stop_at); reduce reports the blow's end,
# clear courses only. Prints one row per run and the counts: which ran to the cap (the old rule
# censored them), which ended, and why the rest did not.
# Usage: STORE=DIR/design.sqlite [CAP=60] [GRANSTACK=...] bench/blow_end_courses.sh > RECORD.md
set -euo pipefail
source "$(dirname "$0")/common.sh"
: "${STORE:?set STORE to a design store (DIR/design.sqlite)}"
python3 - "$gs" "$STORE" "$work" "${CAP:-60}" <<'PY'
import json, re, sqlite3, subprocess, sys
gs, store, work, cap = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])

def toml(v):
    if isinstance(v, bool): return "true" if v else "false"
    if isinstance(v, str): return json.dumps(v)
    if isinstance(v, list): return "[" + ", ".join(toml(x) for x in v) + "]"
    if isinstance(v, dict): return "{" + ", ".join(f"{k} = {toml(x)}" for k, x in v.items()) + "}"
    return repr(v)

rows = sqlite3.connect(store).execute(
    "select description, spec, violations from evaluations where violations like '%still coming%' order by rowid").fetchall()
counts = {"runs": 0, "to_cap": 0, "ended": 0, "ended_to_cap": 0, "still_coming": 0, "taken_back": 0, "hold": 0}
print(f"| design | m/s | p_y / Y | the run's steps (cap) | the blow's end, or why not |\n|---|---|---|---|---|")
for i, (desc, spec, violations) in enumerate(rows):
    s = json.loads(spec)
    if "block_rows" in s: s.pop("rows", None)
    for part in violations.split("; "):
        m = re.match(r"at ([0-9.]+) m/s, striker [0-9.]+ R_1, p_y ([0-9.]+) Y: censored.*still coming", part)
        if not m: continue
        case = dict(s, striker_speed=float(m[1]), stop="blow_end", cap_durations=cap)
        if case.get("normal_model") in ("thornton", "thornton_ning"): case["yield_pressure_factor"] = float(m[2])
        d = f"{work}/c{i}_{m[1]}_{m[2]}"
        open(d + ".toml", "w").write("".join(f"{k} = {toml(v)}\n" for k, v in case.items() if v != {}))
        subprocess.run([gs, "generate", "--config", d + ".toml", "-o", d], capture_output=True, check=True)
        subprocess.run([gs, "run", "--engine", "refsim", d], capture_output=True, check=True)
        summary = json.load(open(f"{d}/reduce/summary.json")) if subprocess.run(
            [gs, "reduce", d], capture_output=True).returncode == 0 else {}
        steps = json.load(open(f"{d}/run.json"))["steps"]
        cap_steps = json.load(open(f"{d}/manifest.json"))["derived"]["steps"]
        case_row = summary["cases"][0] if "cases" in summary else summary
        end, why = case_row.get("blow_end_time"), case_row.get("blow_not_ended", "")
        counts["runs"] += 1
        counts["to_cap"] += steps == cap_steps
        if end is not None:
            counts["ended"] += 1
            counts["ended_to_cap"] += steps == cap_steps
        elif "still coming" in why: counts["still_coming"] += 1
        elif "seemed to end" in why: counts["taken_back"] += 1
        else: counts["hold"] += 1
        said = f"ended at {end:.4g} s" if end is not None else why
        print(f"| {desc} | {m[1]} | {m[2]} | {steps} ({cap_steps}) | {said} |", flush=True)
        subprocess.run(["rm", "-rf", f"{d}/dumps"])
print(f"\n{json.dumps(counts)}")
PY
