#!/usr/bin/env python3
"""What each kind of extension took, counted from the commits that made it: the files each
touched, by kind (the libraries and the program, by folder; tests; the deck templates; the rest),
as JSON on stdout. Its record (bench/results/extension-counts-DATE.json) makes the table of
docs/developer/extending.md (scripts/doc_tables.py).

usage: extension_counts.py > bench/results/extension-counts-DATE.json   (in a clone with history)
"""
import collections
import json
import subprocess
import sys

# (what was added, the commits that added it)
EXTENSIONS = [
    ("three contact models beyond Hertz/history (Hooke, no_history, epsd2)", ["f0a8783", "c4c30b8"]),
    ("LAMMPS as an engine", ["d98f9c9"]),
    ("design measures of the protected object's shock", ["b4538a3"]),
    ("the yield ratio, read by both engines at every frame", ["83919ba"]),
    ("a rolling friction model (cdt), on the sub-models' table and composition", ["dae81a7"]),
    ("a tangential model of LAMMPS's that LIGGGHTS lacks (mindlin_rescale), with the first LIGGGHTS refusals",
     ["1698a67"]),
    ("two elastic-plastic normal models with per-contact history (thornton, thornton_ning), with the generic "
     "history store and the one table of laws they were the first to use", ["d413c65", "48a949c"]),
    ("a fourth engine with an option of its own (a stand-in in the tests: refsim's integrator under another name), "
     "its row added from its own file", ["051ff28"]),
]
LIBRARIES = {"app", "cluster", "design", "formats", "generator", "model", "os", "postproc", "refsim", "runner",
             "study"}


def files_of(commits):
    names = set()
    for c in commits:
        out = subprocess.run(["git", "show", "--name-only", "--format=", c], check=True, capture_output=True,
                             text=True).stdout
        names.update(line for line in out.splitlines() if line)
    return sorted(names)


def main():
    rows = []
    for what, commits in EXTENSIONS:
        files = files_of(commits)
        by_folder = collections.Counter(f.split("/")[0] for f in files if f.split("/")[0] in LIBRARIES)
        rows.append({"extension": what, "commits": commits,
                     "library_files": sum(by_folder.values()),
                     "by_folder": dict(sorted(by_folder.items(), key=lambda kv: (-kv[1], kv[0]))),
                     "test_files": sum(f.startswith("tests/") for f in files),
                     "templates": sum(f.startswith("templates/") for f in files),
                     "other_files": sum(f.split("/")[0] not in LIBRARIES and not f.startswith(("tests/", "templates/"))
                                        for f in files)})
    json.dump({"script": "scripts/extension_counts.py", "extensions": rows}, sys.stdout, indent=2)
    print()


if __name__ == "__main__":
    main()
