"""Fronts in the normalised box of a design store (granstack's convergence.hpp): the point of an
objective vector, non-domination, the exact hypervolume (by slicing, 2 or 3 objectives) against
the reference point 1.1 on every axis, IGD+ (Ishibuchi et al. 2015), and a search's reference
front from the stores of several runs. Shared by bench/design_budget.py and
bench/design_reference.py.
"""
import json
import math
import sqlite3

REFERENCE_POINT = 1.1


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


def store_designs(path):
    """A store's box (its axes), the designs it joined in order (run 0) and every evaluation's
    (feasible, shortcut, objective values, description) by digest."""
    db = sqlite3.connect(path)
    axes = json.loads(db.execute("select value from meta where key = 'normalisation'").fetchone()[0])
    cols = ", ".join(a["objective"] for a in axes)
    rows = {digest: (bool(feasible), shortcut, values, description)
            for digest, feasible, shortcut, description, *values
            in db.execute(f"select digest, feasible, shortcut, description, {cols} from evaluations")}
    joins = [d for (d,) in db.execute("select digest from joins where run = 0 order by position")]
    return axes, joins, rows


def reference_front(stores):
    """The front of the feasible designs run in full that the stores' runs joined, together: the
    box they share, and each front design's description, objective values and point."""
    box, designs = None, {}
    for path in stores:
        axes, joins, rows = store_designs(path)
        assert box is None or axes == box, f"{path}: another box ({axes} against {box})"
        box = axes
        for d in joins:
            feasible, shortcut, values, description = rows[d]
            if feasible and not shortcut:
                designs[tuple(point(box, values))] = (d, description, values)
    kept = front(designs)
    return box, [{"digest": designs[p][0], "description": designs[p][1], "values": designs[p][2], "point": list(p)}
                 for p in kept]
