"""The record of bench/design_budget.sh: each run's progress against the reference front (the
front of every run together, or with REFERENCE=FILE a front kept from earlier runs by
bench/design_reference.py), in the normalised box every store fixed alike before its search.

The hypervolume here (exact, by slicing, for 2 or 3 objectives) is checked against the one
granstack's report gives for the same designs (pagmo2's) at every point of every run, to 1e-9.
"""
import json
import os
import sqlite3
import statistics
import sys

from pareto import hypervolume, igd_plus, join, point, reference_front, store_designs

work, version, cores, max_designs, time_limit, jobs, space, stagnation = sys.argv[1:9]
TARGET_HV = 0.98        # of the reference front's hypervolume
TARGET_IGD = 0.005      # IGD+ in the normalised box
TARGET_DESIGNS = 500
TARGET_SECONDS = 600.0


runs = {}
for line in open(f"{work}/runs.txt"):
    name, t0, t1, last = line.rstrip("\n").split(" ", 3)
    runs[name] = (float(t0), float(t1), last)

box, designs_of = None, {}
for name in runs:
    out = f"{work}/{name}/out"
    axes, joins, described = store_designs(f"{out}/design.sqlite")
    assert box is None or axes == box, f"{name}: another box ({axes} against {box})"
    box = axes
    report = json.load(open(f"{out}/report/design.json"))
    rows = {d: (feasible, shortcut, values) for d, (feasible, shortcut, values, _) in described.items()}
    db = sqlite3.connect(f"{out}/design.sqlite")
    finished = [int(t) for (t,) in db.execute("select strftime('%s', finished) from generations where run = 0 order by generation")]
    designs_of[name] = (joins, rows, report, finished)

# The reference front: every run's feasible designs run in full, together; or one kept.
everything = [point(box, v) for joins, rows, *_ in designs_of.values() for d in joins
              for feasible, shortcut, v in [rows[d]] if feasible and not shortcut]
kept = os.environ.get("REFERENCE", "")
if kept:
    made = json.load(open(kept))
    assert made["box"] == box, f"{kept}: its box is not the runs' ({made['box']} against {box})"
    reference_designs = made["designs"]
    about = {"kept": os.path.relpath(kept), "made": made["made"]}
else:
    _, reference_designs = reference_front(f"{work}/{name}/out/design.sqlite" for name in runs)
    # "feasible": the count; "designs" names the front's designs in every record (as a kept front's file does).
    about = {"runs": len(designs_of), "feasible": len(everything)}
reference = [tuple(d["point"]) for d in reference_designs]
reference_hv = hypervolume(reference)

def searched(name):  # the [search] settings its space names
    return dict(line.split(" = ", 1) for line in open(f"{work}/{name}/space.toml").read().splitlines() if " = " in line)


def breeding(name):  # front_parents:step_mutation, as its space names them
    named = searched(name)
    return f"{named['front_parents']}:{named['step_mutation']}"


record_runs = []
for name, (joins, rows, report, finished) in designs_of.items():
    algorithm, seed, shortcuts = name.rsplit("-", 2)
    run = report["runs"][0]
    step = 24
    t0, t1, last = runs[name]
    progress = []
    running, joined = set(), 0  # the front of the first `joined` designs
    for k, (n, hv_cpp, _) in enumerate(run.get("progress", [])):
        for d in joins[joined:n]:
            if rows[d][0]:
                running = join(running, point(box, rows[d][2]))
        joined = n
        prefix = list(running)
        hv = hypervolume(prefix)
        assert abs(hv - hv_cpp) <= 1e-9, f"{name} at {n} designs: hypervolume {hv} here, {hv_cpp} in the report"
        # A generation's worth of designs ends at its record's time (1 s resolution); the last point at the run's end.
        at = finished[k] - t0 if k < len(finished) and n % step == 0 else t1 - t0
        progress.append({"designs": n, "seconds": round(at, 1), "hypervolume_fraction": hv / reference_hv,
                         "igd_plus": igd_plus(prefix, reference)})
    reach = next((p for p in progress if p["hypervolume_fraction"] >= TARGET_HV), None)
    at_500 = [p for p in progress if p["designs"] <= TARGET_DESIGNS]
    in_time = [p for p in progress if p["seconds"] <= TARGET_SECONDS]
    refsim = run["refsim_seconds"]
    record_runs.append({
        "algorithm": algorithm, "seed": int(seed), "shortcuts": shortcuts == "true", "breeding": breeding(name),
        "screening": int(searched(name).get("screening", 1)),
        "seconds": round(t1 - t0, 1),
        "designs": run["designs"], "ended": last, "stopped_improving": run.get("stopped_improving", ""),
        "designs_to_target": reach["designs"] if reach else None, "seconds_to_target": reach["seconds"] if reach else None,
        "hypervolume_fraction_at_500": at_500[-1]["hypervolume_fraction"] if at_500 else None,
        "igd_plus_at_500": at_500[-1]["igd_plus"] if at_500 else None,
        "hypervolume_fraction_in_600_s": in_time[-1]["hypervolume_fraction"] if in_time else None,
        "designs_in_600_s": in_time[-1]["designs"] if in_time else 0,
        "refsim_seconds": round(refsim, 1),
        "share_censored": run["censored_seconds"] / refsim if refsim else None,
        "share_undecided": run["undecided_seconds"] / refsim if refsim else None,
        "share_off_front": run["off_front_seconds"] / refsim if refsim else None,
        "settled": run["settled"], "scenario_runs": run["scenario_runs"], "scenario_runs_not_run": run["scenario_runs_not_run"],
        "refsim_seconds_per_design": refsim / run["designs"] if run["designs"] else None,
        "progress": progress,
    })


def median(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


summary = {}
for algorithm in sorted({r["algorithm"] for r in record_runs}):
    mine = [r for r in record_runs if r["algorithm"] == algorithm and r["shortcuts"]]
    summary[algorithm] = {
        "seeds": len(mine),
        "median_hypervolume_fraction_at_500": median([r["hypervolume_fraction_at_500"] for r in mine]),
        "median_igd_plus_at_500": median([r["igd_plus_at_500"] for r in mine]),
        "median_hypervolume_fraction_in_600_s": median([r["hypervolume_fraction_in_600_s"] for r in mine]),
        "median_designs_in_600_s": median([r["designs_in_600_s"] for r in mine]),
        "seeds_reaching_target": sum(r["designs_to_target"] is not None for r in mine),
        "median_refsim_seconds_per_design": median([r["refsim_seconds_per_design"] for r in mine]),
    }
off = [r for r in record_runs if not r["shortcuts"]]
on = [r for r in record_runs if r["shortcuts"] and off and r["algorithm"] == off[0]["algorithm"] and r["seed"] == off[0]["seed"]]
print(json.dumps({
    "what": "the design search's budget (#50): each seed alone per algorithm until it stops improving, against the front of all",
    "command": "OUT=... bench/design_budget.sh", "granstack": version, "cores": int(cores), "jobs": int(jobs), "space": space,
    "max_designs": int(max_designs), "time_limit": float(time_limit), "stagnation": int(stagnation),
    "targets": {"hypervolume_fraction": TARGET_HV, "igd_plus": TARGET_IGD, "designs": TARGET_DESIGNS, "seconds": TARGET_SECONDS},
    "reference": {**about, "front": len(reference), "hypervolume": reference_hv, "box": box,
                  "designs": reference_designs},
    "summary": summary,
    "shortcuts": {"off": off[0] if off else None, "on": on[0] if on else None},
    "runs": record_runs,
}, indent=1))
