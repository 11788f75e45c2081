#!/usr/bin/env python3
"""The documentation's result tables, from a run: each lies between the markers
<!-- doc-table: NAME --> and <!-- /doc-table --> in the files below, and this script runs the
cases that make it (LIGGGHTS, as the docs say) and writes it (--write) or checks that the docs
hold exactly what the run gives (--check, the test docs.tables).

usage: doc_tables.py --write|--check GRANSTACK WORKDIR
"""
import json
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
# Where each table stands.
PLACES = {
    "depth": ["README.md", "docs/index.md", "docs/explanation/results.md"],
    "decay": ["docs/tutorials/decay.md"],
    "objectives": ["docs/how-to/design.md"],
}
MARK = re.compile(r"(<!-- doc-table: (\w+) -->\n)(.*?)(<!-- /doc-table -->)", re.S)


def granstack(exe, *args):
    r = subprocess.run([exe, *args], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"granstack {' '.join(args)} failed ({r.returncode}):\n{r.stdout}\n{r.stderr}")
    return r.stdout


def tables(exe, work):
    """The tables' text, from one sweep: N_B 1 to 4, e = 1, 0.95 and 0.9, the study's default stack."""
    sweep = work / "decay"
    granstack(exe, "generate", "-o", str(sweep), "--blocks", "1,2,3,4", "--restitution", "1,0.95,0.9", "--force")
    granstack(exe, "run", "-j", "2", "--force", str(sweep))
    # table prints the output fractions and the fits as markdown: the tutorial shows them as printed.
    printed = granstack(exe, "table", str(sweep))
    decay = "\n".join(line for line in printed.splitlines() if line.startswith("|"))
    decay = decay.replace("|\n| group", "|\n\n| group", 1) + "\n"
    fraction, spheres = {}, {}
    for line in granstack(exe, "reduce", "--json", str(sweep)).splitlines():
        if line.startswith("{"):
            r = json.loads(line)
            manifest = json.loads((sweep / r["case"] / "manifest.json").read_text())
            key = (manifest["spec"]["blocks"], manifest["spec"]["restitution"])
            fraction[key] = r["output_fraction"]
            spheres[key[0]] = manifest["derived"]["sphere_count"]
    rows = ["| N_B | spheres | e = 1 | e = 0.9 |", "|---|---|---|---|"]
    for nb in range(1, 5):
        rows.append(f"| {nb} | {spheres[nb]} | {fraction[(nb, 1)]:.5g} | {fraction[(nb, 0.9)]:.5g} |")
    # The design objectives: the program's own table (design/objectives.hpp), as it prints it.
    objectives = granstack(exe, "design", "objectives")
    return {"depth": "\n".join(rows) + "\n", "decay": decay, "objectives": objectives}


def main():
    if len(sys.argv) != 4 or sys.argv[1] not in ("--write", "--check"):
        sys.exit(__doc__)
    mode, exe, work = sys.argv[1], sys.argv[2], pathlib.Path(sys.argv[3])
    work.mkdir(parents=True, exist_ok=True)
    made = tables(exe, work)
    stale = []
    for name, files in PLACES.items():
        for f in files:
            path = ROOT / f
            text = path.read_text()
            found = [m for m in MARK.finditer(text) if m.group(2) == name]
            if len(found) != 1:
                sys.exit(f"{f}: expected one doc-table '{name}', found {len(found)}")
            if found[0].group(3) == made[name]:
                continue
            stale.append(f"{f}: the table '{name}' is not what the run gives:\n{found[0].group(3)}\nthe run:\n{made[name]}")
            if mode == "--write":
                m = found[0]
                path.write_text(text[: m.start(3)] + made[name] + text[m.end(3):])
    if mode == "--check" and stale:
        sys.exit("\n".join(stale) + "\nrun: python3 scripts/doc_tables.py --write GRANSTACK WORKDIR")
    print(f"doc tables: {sum(len(v) for v in PLACES.values())} places, "
          f"{'rewritten where stale' if mode == '--write' else 'all as the run gives'}")


main()
