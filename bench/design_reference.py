"""A search's reference front, kept: the front of the runs bench/design_budget.sh left in WORK
(KEEP=WORK), each design with its description, objective values and point in the box the
stores share, for later records to be judged against (design_budget.sh's REFERENCE=FILE).
Usage: PYTHONPATH=bench python3 bench/design_reference.py WORK MADE > FILE, MADE saying how the
runs were made (the record that measured them, the build, the command).
"""
import json
import sys

from pareto import hypervolume, reference_front

work, made = sys.argv[1:3]
names = [line.split(" ", 1)[0] for line in open(f"{work}/runs.txt")]
box, designs = reference_front(f"{work}/{name}/out/design.sqlite" for name in names)
print(json.dumps({
    "what": "a design search's reference front: the front of the feasible designs run in full that these runs joined",
    "made": made, "runs": names, "box": box, "front": len(designs),
    "hypervolume": hypervolume([tuple(d["point"]) for d in designs]), "designs": designs,
}, indent=1))
