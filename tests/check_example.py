"""Checks an example's reduced output fractions against the expected values in
tests/data/examples.json (usage: check_example.py EXAMPLE REDUCE_JSON_LINES_FILE).

The expected values were measured with LIGGGHTS 3.8.0 (granstack run) on the example with
--rows 4, as tests/CMakeLists.txt runs it; refsim gives the same values to the tolerance stated
in the data file, which is its measured largest LIGGGHTS-refsim difference on these cases times
a hundred. A change to the physics, the generator or reduce that moves any value fails here."""
import json
import os
import sys

name, lines_file = sys.argv[1], sys.argv[2]
with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "examples.json")) as f:
    golden = json.load(f)
tolerance = golden["relative_tolerance"]
expected = golden["examples"][name]
got = {}
with open(lines_file) as f:
    for line in f:
        if line.startswith("{"):
            r = json.loads(line)
            got[r["case"]] = r["output_fraction"]
if list(expected) == [""] and len(got) == 1:  # a single case, named after its directory
    got = {"": next(iter(got.values()))}
if sorted(got) != sorted(expected):
    sys.exit(f"{name}: cases {sorted(got)}, expected {sorted(expected)}")
bad = []
for case, value in sorted(expected.items()):
    difference = abs(got[case] - value) / abs(value)
    if not difference <= tolerance:
        bad.append(f"{case}: output fraction {got[case]!r}, expected {value!r} (relative difference {difference:.3g} "
                   f"> {tolerance:g})")
if bad:
    sys.exit(f"{name}:\n  " + "\n  ".join(bad))
print(f"{name}: {len(expected)} output fraction(s) as expected within {tolerance:g}")
