"""The record of bench/design_budget.sh: each run's progress against the reference front (the
front of every run together), in the normalised box every store fixed alike before its search.

The hypervolume here (exact, by slicing, for 2 or 3 objectives) is checked against the one
granstack's report gives for the same designs (pagmo2's) at every point of every run, to 1e-9.
"""
import json
import math
import sqlite3
import statistics
import sys

work, version, cores, max_designs, time_limit, jobs, space, stagnation = sys.argv[1:9]
REFERENCE_POINT = 1.1
TARGET_HV = 0.98        # of the reference front's hypervolume
TARGET_IGD = 0.005      # IGD+ in the normalised box
TARGET_DESIGNS = 500
TARGET_SECONDS = 600.0


def point(axes, values):
    out = []
    for a, v in zip(axes, values):
        if a["log"]:
            t = (math.log10(v) - math.log10(a["ideal"])) / (math.log10(a["nadir"]) - math.log10(a["ideal"])) if v > 0 else 0.0
        else:
            t = (v - a["ideal"]) / (a["nadir"] - a["ideal"])
        out.append(max(t, 0.0))
    return out


def dominates(a, b):
    return all(x <= y for x, y in zip(a, b)) and any(x < y for x, y in zip(a, b))


def front(points):
    # In lexicographic order a point can be dominated only by one before it, and a point one
    # dominates is dominated by one on the front: each point is read against the front so far.
    kept = []
    for p in sorted(set(map(tuple, points))):
        if not any(dominates(q, p) for q in kept):
            kept.append(p)
    return kept


def join(running, p):
    """The front of the points so far, `running`, after `p`: front(running + [p]) as a set."""
    p = tuple(p)
    if p in running or any(dominates(q, p) for q in running):
        return running
    return {q for q in running if not dominates(p, q)} | {p}


def area(points):  # 2D, minimised, against (REFERENCE_POINT, REFERENCE_POINT)
    total, best_y = 0.0, REFERENCE_POINT
    for x, y in sorted(points):
        if y < best_y:
            total += (REFERENCE_POINT - x) * (best_y - y)
            best_y = y
    return total


def hypervolume(points):
    inside = [p for p in front(points) if all(x < REFERENCE_POINT for x in p)]
    if not inside:
        return 0.0
    if len(inside[0]) == 2:
        return area(inside)
    assert len(inside[0]) == 3, "2 or 3 objectives"
    inside.sort(key=lambda p: p[2])
    volume = 0.0
    for k, p in enumerate(inside):
        top = inside[k + 1][2] if k + 1 < len(inside) else REFERENCE_POINT
        volume += area([q[:2] for q in inside[:k + 1]]) * (top - p[2])
    return volume


def igd_plus(points, reference):
    f = front(points)
    if not f:
        return math.inf
    return sum(min(math.sqrt(sum(max(a - r, 0.0) ** 2 for a, r in zip(q, p))) for q in f) for p in reference) / len(reference)


runs = {}
for line in open(f"{work}/runs.txt"):
    name, t0, t1, last = line.rstrip("\n").split(" ", 3)
    runs[name] = (float(t0), float(t1), last)

box, designs_of = None, {}
for name in runs:
    out = f"{work}/{name}/out"
    db = sqlite3.connect(f"{out}/design.sqlite")
    axes = json.loads(db.execute("select value from meta where key = 'normalisation'").fetchone()[0])
    assert box is None or axes == box, f"{name}: another box ({axes} against {box})"
    box = axes
    objectives = [a["objective"] for a in axes]
    report = json.load(open(f"{out}/report/design.json"))
    rows = {}
    cols = ", ".join(objectives)
    for digest, feasible, shortcut, *values in db.execute(f"select digest, feasible, shortcut, {cols} from evaluations"):
        rows[digest] = (bool(feasible), shortcut, values)
    joins = [d for (d,) in db.execute("select digest from joins where run = 0 order by position")]
    finished = [int(t) for (t,) in db.execute("select strftime('%s', finished) from generations where run = 0 order by generation")]
    designs_of[name] = (joins, rows, report, finished)

# The reference front: every run's feasible designs run in full, together.
everything = [point(box, v) for joins, rows, *_ in designs_of.values() for d in joins
              for feasible, shortcut, v in [rows[d]] if feasible and not shortcut]
reference = front(everything)
reference_hv = hypervolume(reference)

def breeding(name):  # front_parents:step_mutation, as its space names them
    named = dict(line.split(" = ", 1) for line in open(f"{work}/{name}/space.toml").read().splitlines() if " = " in line)
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
    "reference": {"runs": len(designs_of), "designs": len(everything), "front": len(reference), "hypervolume": reference_hv},
    "summary": summary,
    "shortcuts": {"off": off[0] if off else None, "on": on[0] if on else None},
    "runs": record_runs,
}, indent=1))
