#!/usr/bin/env python3
"""The documentation's result tables and the program's printouts, from a run: each lies between the markers
<!-- doc-table: NAME --> and <!-- /doc-table --> in the files below, and this script runs the
cases that make it (LIGGGHTS, as the docs say) and writes it (--write) or checks that the docs
hold exactly what the run gives (--check, the test docs.tables). With --reproduce it also runs
`granstack reproduce` on LIGGGHTS (every experiment, about a minute on 2 cores) for the
reproduction tutorial's summary, and the study on LAMMPS against it (several minutes), whose
comparison it keeps as a record (bench/results/engines-study-DATE.json). Without it, the check runs
the study on refsim instead (a fraction of LIGGGHTS's time: refsim reproduces LIGGGHTS to round-off, and
the summary prints 4 digits, so its table is LIGGGHTS's to the digit) and makes the LAMMPS page's
table from that record. The big-nest tables are made from the records their benchmarks wrote into
bench/results/ (RECORDS): the 16-core timings cannot be run again here, and the decomposition
counts take minutes (bench/decomposition.sh with OUT set makes them anew).

usage: doc_tables.py --write|--check [--reproduce] GRANSTACK WORKDIR
"""
import json
import os
import pathlib
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
# Where each table stands.
PLACES = {
    "depth": ["README.md", "docs/index.md", "docs/explanation/results.md"],
    "decay": ["docs/tutorials/decay.md"],
    "objectives": ["docs/how-to/design.md"],
    "spec_fields": ["docs/reference/spec.md"],
    "materials": ["docs/reference/spec.md"],
}
# Made from the benchmarks' records (bench/results/): the runs behind them are named there.
RECORDS = {
    "mpi_scaling": "bench/results/mpi-scaling-2026-11-26.json",         # bench/mpi_scaling.sh 3, 16 cores
    "refsim_scaling": "bench/results/mpi-scaling-refsim-2026-11-27.json",  # ONLY=refsim bench/mpi_scaling.sh 5
    "large_nest": "bench/results/mpi-large-nest-2026-11-27.json",       # bench/mpi_large_nest.sh 3, 16 cores
    "copies": "bench/results/concurrent-copies-2026-11-27.json",        # bench/concurrent_copies.sh 3 16
    # OUT=... MODES=asynchronous bench/design_cores.sh 3 16 96, then 3 2 96, on the same 16 cores
    "design_speedup_16": "bench/results/design-speedup-16-jobs-2026-11-27.json",
    "design_speedup_2": "bench/results/design-speedup-2-jobs-2026-11-27.json",
    "decomposition": "bench/results/decomposition-2026-11-26.json",     # OUT=... bench/decomposition.sh
    # OUT=... bench/design_cores.sh 3 16 360 | 3 16 96 (MODES=asynchronous, 16 cores) | 3 2 96 (GEN_DESIGNS=48, here)
    "design_cores_16": "bench/results/design-cores-16-2026-11-27.json",
    "design_cores_16_96": "bench/results/design-cores-16-96-2026-11-27.json",
    "design_cores_2": "bench/results/design-cores-2-2026-11-27.json",
    "engines": "bench/results/engines-2026-11-27.json",                 # OUT=... bench/engines.sh 3
    # doc_tables.py --write --reproduce: the study on LAMMPS against LIGGGHTS (report.json's "against")
    "engines_study": "bench/results/engines-study-2026-11-28.json",
    # GRANSTACK=build/ci/app/granstack OUT=... bash bench/reproduce.sh 3, on the 2-core machine
    "reproduce": "bench/results/reproduce-2026-12-07b.json",
    # GRANSTACK=build/ci/app/granstack CASES=<a reproduce -o folder> OUT=... bash bench/run_overhead.sh 3, 2-core machine
    "run_overhead": "bench/results/run-overhead-2026-12-07.json",
    # BASE_STUDY=<the build before's reproduction> THIS_STUDY=<this build's> OUT=... bash bench/blow_end_judge.sh 3, 2-core machine
    "blow_end_judge": "bench/results/blow-end-judge-2026-12-08.json",
    # OUT=... bench/design_front.sh, on the 2-core machine (the example's confined front, #47 item 9)
    "design_front": "bench/results/design-front-2026-11-28.json",
    # OUT=... GENERATIONS=30 CONFIRM=2 bench/design_yield_front.sh, on the 2-core machine (the yielding example, #67 item 1)
    "design_yield_front": "bench/results/design-yield-front-2026-12-07d.json",
    # bench/oversubscription.sh 3, on the 2-core machine
    "oversubscription": "bench/results/oversubscription-2026-11-28.json",
    # scripts/extension_counts.py, from the commits it names (git history)
    "extension_counts": "bench/results/extension-counts-2026-12-07.json",
    # OUT=... bench/design_budget.sh, on the 2-core machine, idle (#50)
    "design_budget": "bench/results/design-budget-2026-11-28.json",
    # GRANSTACK=build/ci/app/granstack GRANSTACK_BASE=(the build before) OUT=... bench/reduce_vs_wc.sh 15 2, 2-core machine (#46)
    "reduce_speed": "bench/results/reduce-vs-wc-2026-11-29-streamed.json",
    # the same at ca2da3e, whose script stopped each run by a window of 3 generations
    "design_budget_stagnation3": "bench/results/design-budget-stagnation3-2026-11-28.json",
    # POPULATIONS="24 64" ALGORITHMS=nsga2 OFF_RUN=0 OUT=... bench/design_budget.sh, 2-core machine, idle
    "design_population": "bench/results/design-population-2026-11-29.json",
    # the same with POPULATIONS="12 24"
    "design_population_12": "bench/results/design-population-12-2026-11-29.json",
    # ALGORITHMS=nsga2 BREEDINGS="0:0 0.5:0.5 0.5:1" SEEDS="1 2 3 4 5 6 7 8" MAX_DESIGNS=500 STAGNATION=0 OFF_RUN=0
    "design_breeding": "bench/results/design-breeding-2026-11-29.json",
    # ALGORITHMS, SEEDS, KEEP as its "what" says; MAX_DESIGNS=100000 STAGNATION=0 TIME_LIMIT=600 OFF_RUN=0
    "design_ten_minutes": "bench/results/design-ten-minutes-2026-11-29.json",
    # GRANSTACK=<c2b3096-dirty build, d063b14 code> SPACE=examples/design/yielding_protector.toml SEEDS="1 2 3 4 5" ALGORITHMS="sms-emoa nsga2"
    # POPULATIONS=24 BREEDINGS=0:0 OFF_RUN=0 TIME_LIMIT=600 STAGNATION=0 MAX_DESIGNS=100000 JOBS=2 OUT=... bash bench/design_budget.sh
    "design_ten_minutes_yield": "bench/results/design-ten-minutes-yield-2026-12-08.json",
    # BASE=<9c3cae5 build> THIS=<c2b3096-dirty build, d063b14 code> POPULATION=48 OUT=... bash bench/design_cost.sh 3, 2-core machine, idle
    "design_cost": "bench/results/design-cost-2026-12-08.json",
    # REFERENCE=bench/results/design-reference-front-2026-11-29.json ROUNDS=2 ALGORITHMS="sms-emoa nsga2"
    # MAX_DESIGNS=500 STAGNATION=0 OFF_RUN=0 BREEDINGS=0:0 OUT=... bench/design_budget.sh, 2-core machine, idle
    "design_repeat": "bench/results/design-repeat-2026-11-29.json",
    # REFERENCE=bench/results/design-reference-front-2026-11-29.json SCREENINGS="1 8" ALGORITHMS=sms-emoa
    # MAX_DESIGNS=500 STAGNATION=0 OFF_RUN=0 BREEDINGS=0:0 OUT=... bench/design_budget.sh, 2-core machine
    "design_screening": "bench/results/design-screening-regression-2026-11-29.json",
    # The same command on an earlier build, whose screening's estimate was the nearest designs' mean: read
    # for its screening 1 runs only, another invocation of the unscreened search (its code is unchanged)
    "design_screening_nearest": "bench/results/design-screening-2026-11-29.json",
    # GRANSTACK=<9647ffd build> REFERENCE=bench/results/design-reference-front-2026-11-29.json SCREENINGS=8
    # ALGORITHMS=sms-emoa MAX_DESIGNS=100000 STAGNATION=0 TIME_LIMIT=600 OFF_RUN=0 BREEDINGS=0:0 OUT=... bench/design_budget.sh
    "design_ten_minutes_screening": "bench/results/design-ten-minutes-screening-2026-11-29.json",
    # build/ci/bench/granstack_bench_restitution (the test docs.restitution_record runs it again)
    "restitution": "bench/results/restitution-2026-12-06.json",
}
RECORD_PLACES = {"nest_counts": ["docs/how-to/big-nests.md"], "nest_speed": ["docs/how-to/big-nests.md"],
                 "refsim_against_liggghts": ["docs/how-to/big-nests.md"],
                 "refsim_outside_loop": ["docs/how-to/big-nests.md"], "large_nest": ["docs/how-to/big-nests.md"],
                 "copies": ["docs/how-to/big-nests.md"], "design_speedup": ["docs/explanation/performance.md"],
                 "design_cores": ["docs/explanation/performance.md"], "design_cores_summary": ["README.md"],
                 "engines_agreement": ["docs/explanation/lammps.md"], "engines_speed": ["docs/explanation/lammps.md"],
                 "reproduce_cost": ["README.md", "docs/index.md", "docs/tutorials/reproduce.md"],
                 "reproduce_speed": ["docs/explanation/performance.md"],
                 "run_overhead": ["docs/explanation/performance.md"], "blow_end_judge": ["docs/explanation/performance.md"],
                 "design_front": ["docs/how-to/design.md"], "design_sides": ["docs/how-to/design.md"],
                 "design_yield": ["docs/how-to/design.md"], "design_example_cost": ["docs/explanation/performance.md"],
                 "design_yield_front": ["docs/how-to/design.md"], "design_yield_cost": ["docs/explanation/performance.md"],
                 "oversubscription": ["docs/reference/commands.md"],
                 "extension_counts": ["docs/developer/extending.md"],
                 "reduce_speed": ["docs/explanation/performance.md"],
                 "design_budget": ["docs/explanation/performance.md"], "design_shortcuts": ["docs/explanation/performance.md"],
                 "design_population": ["docs/explanation/performance.md"], "design_breeding": ["docs/explanation/performance.md"],
                 "design_ten_minutes": ["docs/explanation/performance.md"],
                 "design_ten_minutes_yield": ["docs/explanation/performance.md"],
                 "design_cost": ["docs/explanation/performance.md"],
                 "design_repeat": ["docs/explanation/performance.md"],
                 "design_screening": ["docs/explanation/performance.md"],
                 "design_ten_minutes_screening": ["docs/explanation/performance.md"],
                 "restitution": ["docs/physics.md"]}
# The study's tables: LIGGGHTS's reproduction (refsim's in the check) and the LAMMPS study's record.
REPRODUCE_PLACES = {"reproduce": ["docs/tutorials/reproduce.md"], "engines_study": ["docs/explanation/lammps.md"]}
# The notes of the report the tutorial quotes: what the consistent runs show, computed.
QUOTED_NOTES = ("One reading for Fig. 2 and Fig. 4", "Hypotheses, from the restitution scan", "Each mechanism's share")
MARK = re.compile(r"(<!-- doc-table: (\w+) -->\n)(.*?)(<!-- /doc-table -->)", re.S)
# The program's printouts the pages show, each made by running it here (printouts()).
PRINTOUT_PLACES = {"quickstart_output": ["README.md", "docs/index.md", "docs/tutorials/quick-start.md"],
                   "spec_error_output": ["docs/reference/spec.md"],
                   "blow_end_wall": ["docs/how-to/blow-end.md"], "blow_end_generate": ["docs/how-to/blow-end.md"],
                   "adopt_output": ["docs/liggghts.md"], "deck_refused_output": ["docs/reference/commands.md"]}
# What differs between two runs of the same commands: a run's wall and loop times. The check compares
# the printouts with these masked; --write writes what its run printed.
TIMINGS = re.compile(r"\([0-9.]+ s wall, loop [0-9.e+-]+ s, [0-9.e+-]+ particle-steps/s\)|loop [0-9.e+-]+ s;")


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
    return {"depth": "\n".join(rows) + "\n", "decay": decay, "objectives": objectives,
            "spec_fields": granstack(exe, "fields", "--markdown"),
            "materials": granstack(exe, "fields", "--materials", "--markdown")}


def printed(exe, cwd, *args, code=0):
    """What `granstack ARGS` prints in `cwd` (standard output, then standard error), its exit code checked."""
    r = subprocess.run([exe, *args], cwd=cwd, capture_output=True, text=True)
    if r.returncode != code:
        sys.exit(f"granstack {' '.join(args)} exited {r.returncode}, not {code}:\n{r.stdout}\n{r.stderr}")
    return r.stdout + r.stderr


def fenced(text):
    return "```\n" + text + ("" if text.endswith("\n") else "\n") + "```\n"


def printouts(exe, work):
    """The printouts the pages show: the quick start's (LIGGGHTS, as scripts/quickstart.sh runs it), a
    refused spec's, the blow-end page's (LIGGGHTS over a wall; where that blow ends, from its run to the
    blow's end on refsim, which stops at the same frame), a deck run by hand and adopted, a template
    refused for a command the spec does not list."""
    cwd = work / "printouts"
    shutil.rmtree(cwd, ignore_errors=True)
    (cwd / "runs").mkdir(parents=True)
    out = {}
    quick = printed(exe, cwd, "generate", "-o", "runs/quickstart") + printed(exe, cwd, "run", "runs/quickstart")
    out["quickstart_output"] = fenced(quick + "\n" + printed(exe, cwd, "reduce", "runs/quickstart"))
    out["spec_error_output"] = fenced("$ granstack generate -o runs/x --restitution 1,0.01\n" +
                                      printed(exe, cwd, "generate", "-o", "runs/x", "--restitution", "1,0.01", code=2))
    printed(exe, cwd, "generate", "-o", "runs/wall", "--bottom", "wall")
    printed(exe, cwd, "run", "runs/wall")
    not_ended = [l for l in printed(exe, cwd, "reduce", "runs/wall").splitlines() if l.startswith("the blow had not ended")]
    generated = printed(exe, cwd, "generate", "-o", "runs/wall_end", "--bottom", "wall", "--stop", "blow_end")
    printed(exe, cwd, "run", "--engine", "refsim", "runs/wall_end")
    summary = next(json.loads(l) for l in printed(exe, cwd, "reduce", "--json", "runs/wall_end").splitlines()
                   if l.startswith("{"))
    automatic = json.loads((cwd / "runs/wall/manifest.json").read_text())["derived"]["duration"]
    out["blow_end_wall"] = (
        f"Over a wall, the default stack's blow is still going on when that duration ends: it ends at "
        f"{summary['blow_end_time'] / automatic:.3g} automatic durations (its run to the blow's end, made by "
        f"`scripts/doc_tables.py`). `reduce` says so:\n\n" +
        fenced("$ granstack generate -o runs/wall --bottom wall\n$ granstack run runs/wall && granstack reduce "
               "runs/wall\n...\n" + "\n".join(not_ended)))
    out["blow_end_generate"] = fenced("$ granstack generate -o runs/wall_end --bottom wall --stop blow_end\n" + generated +
                                      "$ granstack run runs/wall_end && granstack reduce runs/wall_end")
    printed(exe, cwd, "generate", "-o", "runs/hand")
    with tempfile.TemporaryDirectory() as session:  # Open MPI's session files apart (granstack's os/mpi_session.hpp)
        env = {"OMPI_MCA_orte_tmpdir_base": session, "OMPI_MCA_ess_singleton_isolated": "1", **os.environ}
        subprocess.run(["liggghts", "-in", "in.stack"], cwd=cwd / "runs/hand", capture_output=True, check=True, env=env)
    out["adopt_output"] = fenced("$ cd runs/hand && liggghts -in in.stack && cd ../..\n$ granstack adopt runs/hand\n" +
                                 printed(exe, cwd, "adopt", "runs/hand"))
    template = (ROOT / "templates/in.granstack.tmpl").read_text().replace("{{run}}", "fix visc all viscous 0.001\n{{run}}")
    (cwd / "mine.tmpl").write_text(template)
    printed(exe, cwd, "generate", "-o", "runs/mine", "--template", "mine.tmpl")
    out["deck_refused_output"] = fenced("$ granstack generate -o runs/mine --template mine.tmpl\n$ granstack run runs/mine\n" +
                                        printed(exe, cwd, "run", "runs/mine", code=1))
    return out


def store_unnamed(exe, work):
    """The design store's tables, columns and meta keys that docs/how-to/design.md's store table does not name
    (read from a store a small search writes here): each is a problem of the check."""
    import sqlite3
    space = work / "store_space.toml"
    space.write_text((ROOT / "tests/data/design/small_space.toml").read_text())
    out = work / "store"
    shutil.rmtree(out, ignore_errors=True)
    printed(exe, work, "design", "run", str(space), "-o", str(out), "--max-designs", "2", "--no-report")
    db = sqlite3.connect(out / "design.sqlite")
    rows = {}
    for line in (ROOT / "docs/how-to/design.md").read_text().splitlines():
        m = re.match(r"\| `(\w+)` \|", line)
        if m:
            rows[m.group(1)] = line
    problems = []
    for (table,) in db.execute("select name from sqlite_master where type = 'table'"):
        if table not in rows:
            problems.append(f"docs/how-to/design.md: the store's table `{table}` has no row in its store table")
            continue
        names = [c[1] for c in db.execute(f"pragma table_info({table})")]
        if table == "meta":
            names += [k for (k,) in db.execute("select key from meta")]
        problems += [f"docs/how-to/design.md: the store table's row `{table}` does not name `{n}`"
                     for n in names if f"`{n}`" not in rows[table]]
    return problems


def record(name):
    return json.loads((ROOT / RECORDS[name]).read_text())


def restitution():
    """e(V) of thornton and thornton_ning against Thornton's closed form, and thornton_ning's time step."""
    r = record("restitution")
    rows = ["| material | V_y (m/s) | V (m/s) | closed form | `thornton` | `thornton_ning` | `thornton_ning` / closed form |",
            "|---|---|---|---|---|---|---|"]
    for i in r["impacts"]:
        rows.append(f"| {i['material']} | {i['yield_velocity']:.3g} | {i['speed']:g} | {i['closed_form']:.4f} | "
                    f"{i['thornton']:.4f} | {i['thornton_ning']:.4f} | {i['thornton_ning'] / i['closed_form']:.3f} |")
    steps = ", ".join(f"{s['e_minus_1']:.3g} at t_c / {s['steps_per_contact']}" for s in r["thornton_ning_elastic_steel_1ms"])
    return ("\n".join(rows) + "\n\n" + f"`thornton_ning` never yielding (steel at 1 m/s, ratio 1): e - 1 = {steps} "
            f"(`{RECORDS['restitution']}`).\n")


def nest_counts():
    """LIGGGHTS's own counts per rank, the deck before and now (bench/decomposition.sh)."""
    rows = ["| spheres | ranks | deck | grid | busiest / mean | ghosts / owned |", "|---|---|---|---|---|---|"]
    order = {"before": 0, "now": 1}
    for r in sorted(record("decomposition"), key=lambda r: (r["spheres"], r["ranks"], order[r["deck"]])):
        grid = " x ".join(str(g) for g in r["grid"])
        rows.append(f"| {r['spheres']:,} | {r['ranks']} | {r['deck']} | {grid} | {r['busiest_over_mean']:.3f} | "
                    f"{r['ghosts_per_owned']:.3f} |")
    return "\n".join(rows) + "\n"


def nest_speed():
    """Loop and wall seconds on 16 cores, medians (bench/mpi_scaling.sh; refsim from its own run)."""
    runs = {**{k: v for k, v in record("mpi_scaling").items() if k.startswith("l")}, **record("refsim_scaling")}
    rows = ["| run | loop | speed-up | efficiency | wall (run.json) | speed-up | last frame against 1 rank or thread |",
            "|---|---|---|---|---|---|---|"]
    for r in runs.values():
        efficiency = "" if r["units"] == 1 else f"{100 * r['efficiency']:.0f} %"
        rows.append(f"| {r['label']} | {r['loop_seconds']:.3g} s | {r['loop_speedup']:.2f} | {efficiency} | "
                    f"{r['wall_seconds']:.3g} s | {r['wall_speedup']:.2f} | {r['last_frame_vs_liggghts_1']:.1e} |")
    return "\n".join(rows) + "\n"


def refsim_against_liggghts():
    """refsim against LIGGGHTS on one core each, in one run of bench/mpi_scaling.sh."""
    r = record("mpi_scaling")
    l1, r1 = r["l1"], r["r1"]
    return (f"refsim ran the 97,921-sphere nest's first 2e-4 s (3190 steps) in {r1['loop_seconds']:.3g} s, LIGGGHTS in "
            f"{l1['loop_seconds']:.3g} s: {l1['loop_seconds'] / r1['loop_seconds']:.1f} times as fast "
            f"(`{RECORDS['mpi_scaling']}`).\n")


def refsim_outside_loop():
    """Where refsim's time beyond the loop goes, medians (run.json's outside_loop_seconds)."""
    rows = ["| threads | read | build | first output | close | wall - loop |", "|---|---|---|---|---|---|"]
    for r in record("refsim_scaling").values():
        o = r["outside_loop_seconds"]
        rows.append(f"| {r['units']} | {o['read']:.3f} s | {o['build']:.3f} s | {o['first_output']:.3f} s | "
                    f"{o['close']:.4f} s | {r['wall_seconds'] - r['loop_seconds']:.3f} s |")
    return "\n".join(rows) + "\n"


def large_nest():
    """LIGGGHTS on 1 and 16 ranks on the million-sphere nest (bench/mpi_large_nest.sh)."""
    r = record("large_nest")
    rows = ["| ranks | loop | output | loop without output | pair | comm | other | busiest / mean | ghosts / owned |",
            "|---|---|---|---|---|---|---|---|---|"]
    for ranks, x in r["ranks"].items():
        rows.append(f"| {ranks} | {x['loop_seconds']:.2f} s | {x['output_seconds']:.2f} s | {x['loop_without_output']:.2f} s | "
                    f"{x['pair_seconds']:.2f} s | {x['comm_seconds']:.2f} s | {x['other_seconds']:.2f} s | "
                    f"{x['busiest_over_mean']:.3f} | {x['ghosts_per_owned']:.3f} |")
    s, c = r["speedup_loop_seconds"], r["speedup_loop_without_output"]
    rows += ["", f"16 ranks over 1: {s:.2f} on the loop ({100 * s / 16:.0f} % efficiency), {c:.2f} without the output "
             f"({100 * c / 16:.0f} %); the last frames agree to {r['last_frame_16_vs_1']:.1e}."]
    return "\n".join(rows) + "\n"


def copies():
    """One core's run alone and as 16 copies at once (bench/concurrent_copies.sh)."""
    r = record("copies")
    rows = ["| engine | alone | a copy among 16 (median) | slowest copy | slowdown | efficiency at most |",
            "|---|---|---|---|---|---|"]
    for engine, label in (("liggghts", "LIGGGHTS, 1 rank"), ("refsim", "refsim, 1 thread")):
        x = r[engine]
        rows.append(f"| {label} | {x['alone_seconds']:.3g} s | {x['copy_seconds']:.3g} s | {x['slowest_copy_seconds']:.3g} s | "
                    f"{x['slowdown']:.2f} | {100 * x['efficiency_bound']:.0f} % |")
    return "\n".join(rows) + "\n"


def design_speedup():
    """The same asynchronous search on 16 jobs and on 2, on one 16-core machine (bench/design_cores.sh)."""
    rows = ["| -j | busy cores | wall for 96 designs | distinct designs/s | CPU per design |", "|---|---|---|---|---|"]
    rates = {}
    for name in ("design_speedup_16", "design_speedup_2"):
        r = record(name)
        m = r["modes"]["asynchronous"]
        runs, med = m["runs"], m["median"]
        rates[r["jobs"]] = med["per_second"]
        span = lambda k, f: f"{min(x[k] for x in runs):{f}}..{max(x[k] for x in runs):{f}}"
        cpu = sorted(x["cpu"] / x["distinct"] for x in runs)
        rows.append(f"| {r['jobs']} | {med['busy']:.2f} ({span('busy', '.2f')}) | {med['wall']:.1f} s ({span('wall', '.1f')}) | "
                    f"{med['per_second']:.2f} ({span('per_second', '.2f')}) | {cpu[len(cpu) // 2]:.2f} s ({cpu[0]:.2f}..{cpu[-1]:.2f}) |")
    rows += ["", f"16 jobs over 2: {rates[16] / rates[2]:.1f} times the distinct designs per second (medians)."]
    return "\n".join(rows) + "\n"


def design_cores():
    """Busy cores of design run, asynchronous against generational (bench/design_cores.sh)."""
    rows = ["| cores | search | -j | designs | busy cores | wall | distinct designs/s |", "|---|---|---|---|---|---|---|"]
    for name in ("design_cores_16", "design_cores_16_96", "design_cores_2"):
        r = record(name)
        for mode, m in r["modes"].items():
            runs, med = m["runs"], m["median"]
            span = lambda k, f: f"{min(x[k] for x in runs):{f}}..{max(x[k] for x in runs):{f}}"
            designs = r["designs"] if mode == "asynchronous" else r["generational_designs"]
            rows.append(f"| {r['cores']} | {mode} | {r['jobs']} | {designs} | {med['busy']:.2f} ({span('busy', '.2f')}) | "
                        f"{med['wall']:.1f} s ({span('wall', '.1f')}) | {med['per_second']:.2f} |")
    return "\n".join(rows) + "\n"


def design_cores_summary():
    """The README's line: the 16-core record's busy cores and designs."""
    m = record("design_cores_16")["modes"]["asynchronous"]["median"]
    return (f"The design search keeps {m['busy']:.1f} of 16 cores busy: {m['searched']} distinct designs of the example "
            f"in {m['wall']:.0f} s ([performance](docs/explanation/performance.md)).\n")


def g4(v):
    return "-" if v is None else f"{v:.4g}"


def verdict(c):
    """confirm's verdict in a few words: agree, or why not."""
    if c["verdict"] == "agree":
        return "agree"
    if "more dump frames" in c["verdict"]:
        return "DISAGREE: each engine ended the blow at another frame"
    return "DISAGREE: " + c["verdict"].split(": ", 1)[-1][:80]


def design_front():
    """The example's confined front (bench/design_front.sh): every front design's worst blow, its
    crush and yield ratio, and LIGGGHTS's verdict on the two confirm ran."""
    r = record("design_front")
    verdicts = {c["digest"]: c for c in r["confirmations"]}
    rows = ["| # | design | peak wall force (N) | wall impulse (N s) | areal mass (kg/m^2) | crush (m) | yield ratio | "
            "on LIGGGHTS |", "|---|---|---|---|---|---|---|---|"]
    for i, e in enumerate(r["front"], 1):
        o, m = e["objectives"], e["measures"]
        c = verdicts.get(e["digest"])
        lig = f"{verdict(c)}, objectives {c['objective_difference']:.1g} apart" if c else "not confirmed"
        rows.append(f"| {i} | {e['description']} | {g4(o['peak_wall_force'])} | {g4(o['wall_impulse'])} | "
                    f"{g4(o['areal_mass'])} | {g4(m.get('crush'))} | {m['yield_ratio']:.3g} | {lig} |")
    return "\n".join(rows) + "\n"


def design_sides():
    """Confined against the free strip: the front's best two (the deciding blow, confirm's run on
    LIGGGHTS) and the study's three designs (the worst of the three blows, refsim)."""
    r = record("design_front")
    rows = ["| design | peak wall force confined (N) | as a free strip (N) | change | crush confined (m) | as a free strip (m) |",
            "|---|---|---|---|---|---|"]
    def row(name, confined, strip, where, not_final=""):
        f, g = confined["peak_wall_force"], strip["peak_wall_force"]
        mark = " (censored: the strip's blow had not ended at the cap)" if not_final else ""
        rows.append(f"| {name} ({where}) | {f:.4g} | {g:.4g}{mark} | {100 * (g / f - 1):+.0f} % | {confined['crush']:.3g} | "
                    f"{strip['crush']:.3g} |")
    by_digest = {e["digest"]: e for e in r["front"]}
    for i, c in enumerate(r["confirmations"], 1):
        e = by_digest.get(c["digest"])
        if e and c["strip_measures"]:
            row(f"front {i}: {c['description']}", e["measures"], c["strip_measures"], "its deciding blow, LIGGGHTS",
                c["strip_not_final"])
    strips = {s["name"]: s for s in r["study_strip"]}
    for s in r["study_confined"]:
        row(s["name"], s["measures"], strips[s["name"]]["measures"], "worst of the three blows, refsim")
    return "\n".join(rows) + "\n"


def design_yield():
    """The share of the example's designs beyond first yield."""
    y = record("design_front")["yield"]
    return (f"{y['beyond_first_yield']} of the {y['judged']} designs the search ran press a contact beyond first yield "
            f"(yield ratios {y['smallest_ratio']:.3g} to {y['largest_ratio']:.3g}).\n")


def design_yield_front():
    """The yielding example's front (bench/design_yield_front.sh): each front design's objectives under
    Thornton's law (the worst of its six blows) beside its elastic twin's, then the study's designs,
    and the report's paragraphs beside the elastic model."""
    r = record("design_yield_front")
    confirmed = {c["digest"]: c for c in r.get("confirmations", [])}
    rows = ["| # | design | CFC 1000 force (N) | elastic (N) | wall impulse (N s) | elastic (N s) | areal mass (kg/m^2) | "
            "raw peak force (N) | crush (m) | on LIGGGHTS |", "|---|---|---|---|---|---|---|---|---|---|"]
    def row(name, e):
        o, t = e["objectives"], e["elastic"]["objectives"]
        mine = " (censored)" if "censored" in e["violations"] else ""
        censored = " (censored)" if "censored" in e["elastic"]["violations"] else ""
        rows.append(f"| {name} | {e['description']} | {g4(o['filtered_wall_force'])}{mine} | {g4(t['filtered_wall_force'])}{censored} | "
                    f"{g4(o['wall_impulse'])}{mine} | {g4(t['wall_impulse'])}{censored} | {g4(o['areal_mass'])} | "
                    f"{g4(e['measures'].get('peak_wall_force'))} | {g4(e['measures'].get('crush'))} | "
                    f"{law_confirmation(confirmed.get(e.get('digest')))} |")
    for i, e in enumerate(r["front"], 1):
        row(str(i), e)
    for s in r["study"]:
        row(s["name"], s)
    head = (f"{generations_of(r)} generations, {r['evaluations']} distinct designs of six blows each, "
            f"{len(r['front'])} on the front:\n\n")
    return head + "\n".join(rows) + "\n\n" + "\n\n".join(p.strip() for p in r["beside_elastic"]) + "\n"


def law_confirmation(c):
    """A confirmation of a design searched under a law LIGGGHTS lacks: its engines' verdict under
    the law LIGGGHTS ran, and that law's spread from the search's on each objective."""
    if c is None:
        return "-"
    if c.get("not_run"):
        return "not run: " + c["not_run"]
    spread = ", ".join(f"{name} {100 * v:+.1f} %" for name, v in sorted(c["law_spread"].items()))
    law = f"; {c['law']} against the search's law: {spread}" if c.get("law") else ""
    return f"{verdict(c)} (objectives {c['objective_difference']:.1g} apart){law}"


def generations_of(r):
    """The generations a design_yield_front record searched, as its command gave them."""
    return int(r["command"].split("GENERATIONS=")[1].split()[0])


def design_example_cost():
    """What the example's search and its confirmation cost on 2 cores (bench/design_front.sh)."""
    r = record("design_front")
    return (f"| what | wall time, {r['cores']} cores |\n|---|---|\n"
            f"| `design run` of the elastic example, {r['evaluations']} distinct designs, 3 blows each (generational) | "
            f"{r['search_seconds']:.0f} s |\n"
            f"| `design confirm --top 2 --sides free` (LIGGGHTS, each also as the free strip) | {r['confirm_seconds']:.0f} s |\n")


def design_yield_cost():
    """What the yielding example's search costs on 2 cores, its elastic twins included
    (bench/design_yield_front.sh)."""
    r = record("design_yield_front")
    twins = len(r["front"]) + len(r["study"])
    return (f"| what | wall time, {r['cores']} cores |\n|---|---|\n"
            f"| `design run` of the yielding example, {r['evaluations']} distinct designs, 6 blows each (3 speeds, 2 yield "
            f"pressures; generational, {generations_of(r)} generations), and {twins} "
            f"elastic twins, 3 blows each | {r['search_seconds']:.0f} s |\n"
            + (f"| `design confirm --top {len(r['confirmations'])} -j 2` (LIGGGHTS under thornton_ning, each of "
               f"the six blows, refsim beside it, then LIGGGHTS twice as long) | {r['confirm_seconds']:.0f} s |\n"
               if r.get("confirmations") else ""))


def design_budget():
    """The search's budget against its targets, per algorithm (bench/design_budget.sh, #50)."""
    r = record("design_budget")
    t = r["targets"]
    pct = lambda x: "-" if x is None else f"{x:.3f}"
    rows = [f"| algorithm | seeds | hypervolume at {t['designs']} designs (of the reference's) | IGD+ at {t['designs']} designs | "
            f"seeds reaching {t['hypervolume_fraction']} | designs to reach it | hypervolume at the run's end | "
            f"designs at its end | its wall time | refsim s per design |", "|---|---|---|---|---|---|---|---|---|---|"]
    for algorithm, m in r["summary"].items():
        mine = [x for x in r["runs"] if x["algorithm"] == algorithm and x["shortcuts"]]
        span = lambda k: (f" ({min(x[k] for x in mine if x[k] is not None):.3f}..{max(x[k] for x in mine if x[k] is not None):.3f})"
                          if any(x[k] is not None for x in mine) else "")
        reached = sorted(x["designs_to_target"] for x in mine if x["designs_to_target"] is not None)
        rows.append(f"| {algorithm} | {m['seeds']} | {pct(m['median_hypervolume_fraction_at_500'])}{span('hypervolume_fraction_at_500')} | "
                    f"{pct(m['median_igd_plus_at_500'])}{span('igd_plus_at_500')} | {m['seeds_reaching_target']} of {m['seeds']} | "
                    f"{', '.join(map(str, reached)) or '-'} | {pct(m['median_hypervolume_fraction_in_600_s'])} | "
                    f"{m['median_designs_in_600_s']:.0f} | {min(x['seconds'] for x in mine):.0f}..{max(x['seconds'] for x in mine):.0f} s | "
                    f"{m['median_refsim_seconds_per_design']:.2f} |")
    ref = r["reference"]
    met = lambda ok: "met" if ok else "not met"
    lines = [f"The reference front: {ref['front']} designs, the front of all {ref['runs']} runs' {feasible(ref)} feasible designs "
             f"run in full (hypervolume {ref['hypervolume']:.6f} in the normalised box). Each run ended as it says in the record "
             f"(`{RECORDS['design_budget']}`, `runs[].ended` and `stopped_improving`). "
             f"Measured by {r['granstack']}, breeding with front_parents:step_mutation "
             f"{', '.join(sorted({x.get('breeding', '0:0 (before the settings existed)') for x in r['runs']}))}."]
    for algorithm, m in r["summary"].items():
        hv, igd = m["median_hypervolume_fraction_at_500"], m["median_igd_plus_at_500"]
        mine = [x for x in r["runs"] if x["algorithm"] == algorithm and x["shortcuts"]]
        longest = max(x["seconds"] for x in mine)
        lines.append(f"{algorithm}: median hypervolume {pct(hv)} and IGD+ {pct(igd)} at {t['designs']} designs: "
                     f"{met(hv is not None and hv >= t['hypervolume_fraction'] and igd is not None and igd <= t['igd_plus'])}. "
                     f"On {r['cores']} cores (-j {r['jobs']}) every run ended by its rule or its {r['max_designs']} designs within "
                     f"{longest:.0f} s, at a median {pct(m['median_hypervolume_fraction_in_600_s'])} of the reference after "
                     f"{m['median_designs_in_600_s']:.0f} designs: 1,000 distinct designs in {t['seconds']:.0f} s "
                     f"{met(min(x['designs'] for x in mine) >= 1000 and longest <= t['seconds'])}, "
                     f"{t['hypervolume_fraction']} of the reference within them "
                     f"{met((m['median_hypervolume_fraction_in_600_s'] or 0) >= t['hypervolume_fraction'])} by runs that had stopped "
                     f"improving or spent their budget.")
    old = record("design_budget_stagnation3")
    stops = [x["designs"] for x in old["runs"] if x["shortcuts"]]
    share = sorted(x["progress"][-1]["hypervolume_fraction"] * old["reference"]["hypervolume"] / ref["hypervolume"]
                   for x in old["runs"] if x["shortcuts"])
    lines.append(f"With a window of 3 generations (`{RECORDS['design_budget_stagnation3']}`, the same box), the rule called "
                 f"every run stopped between {min(stops)} and {max(stops)} designs, at {share[0]:.3f} to {share[-1]:.3f} of "
                 f"this reference's hypervolume: the window is {r['stagnation']} generations since.")
    return "\n".join(rows) + "\n\n" + "\n\n".join(lines) + "\n"


def design_population():
    """The search's population: NSGA-II at each population of each record, its seeds against the front of all
    that record's runs (each invocation its own reference)."""
    rows, medians = [], {}
    for key in ("design_population", "design_population_12"):
        r = record(key)
        t = r["targets"]
        if not rows:
            rows = [f"| population | record | seeds | hypervolume at {t['designs']} designs (of the reference's) | "
                    f"IGD+ at {t['designs']} designs | hypervolume at the run's end | designs at its end |",
                    "|---|---|---|---|---|---|---|"]
        ref = r["reference"]
        for label, m in r["summary"].items():
            mine = [x for x in r["runs"] if x["algorithm"] == label and x["shortcuts"]]
            population = int(label.rsplit("-p", 1)[1])
            medians.setdefault(population, []).append(m["median_hypervolume_fraction_at_500"])
            spread = f" ({min(x['hypervolume_fraction_at_500'] for x in mine):.3f}..{max(x['hypervolume_fraction_at_500'] for x in mine):.3f})"
            rows.append(f"| {population} | `{RECORDS[key]}` (its reference: {ref['front']} designs of {feasible(ref)}) | "
                        f"{m['seeds']} | {m['median_hypervolume_fraction_at_500']:.3f}{spread} | {m['median_igd_plus_at_500']:.3f} | "
                        f"{m['median_hypervolume_fraction_in_600_s']:.3f} | {m['median_designs_in_600_s']:.0f} |")
    # Each other population against the default in the same invocation, and the default's own move
    # between invocations.
    base = 24
    lines = ["Each record's reference front is the front of all its runs."]
    gains_at_500 = []
    for key in ("design_population", "design_population_12"):
        r = record(key)
        summary = {int(label.rsplit("-p", 1)[1]): m for label, m in r["summary"].items()}
        for population, m in sorted(summary.items()):
            if population == base:
                continue
            ours, theirs = summary[base], m
            mine = [x for x in r["runs"] if x["algorithm"].endswith(f"-p{population}") and x["shortcuts"]]
            still = sum(x["stopped_improving"].startswith("still improving") for x in mine)
            gains_at_500.append(theirs["median_hypervolume_fraction_at_500"] - ours["median_hypervolume_fraction_at_500"])
            lines.append(f"Population {population} against {base} in the same invocation: "
                         f"{theirs['median_hypervolume_fraction_at_500'] - ours['median_hypervolume_fraction_at_500']:+.3f} "
                         f"at 500 designs; its runs ended after a median {theirs['median_designs_in_600_s']:.0f} designs "
                         f"({base}'s: {ours['median_designs_in_600_s']:.0f}), {still} of {len(mine)} still improving.")
    if len(medians.get(base, [])) > 1:
        v = medians[base]
        moved = max(v) - min(v)
        lines.append(f"Population {base} itself gave medians {' and '.join(f'{x:.3f}' for x in v)} at 500 designs in the two "
                     f"invocations, {moved:.3f} apart (on 2 jobs the seeds' designs finish in another order each time).")
        gains = [g for g in gains_at_500 if g > moved]
        lines.append(f"So {'a population beats' if gains else 'no population beats'} {base} at 500 designs by more than "
                     f"{base} moved between invocations.")
    return "\n".join(rows) + "\n\n" + " ".join(lines) + "\n"


def design_breeding():
    """The asynchronous search's breeding ([search] front_parents:step_mutation), NSGA-II at population 24, each
    against the front of all the record's runs; the seeds paired (a seed's first population is the same at every
    breeding)."""
    r = record("design_breeding")
    t = r["targets"]
    label = lambda s: s.rsplit("-f", 1)[1].replace("-s", ":")
    runs = {label(a): {x["seed"]: x["hypervolume_fraction_at_500"] for x in r["runs"] if x["algorithm"] == a and x["shortcuts"]}
            for a in r["summary"]}
    rows = [f"| front_parents:step_mutation | seeds | hypervolume at {t['designs']} designs (of the reference's) | "
            f"IGD+ at {t['designs']} designs | seeds above 0:0's |", "|---|---|---|---|---|"]
    for a, m in r["summary"].items():
        b = label(a)
        mine = runs[b]
        above = "-" if b == "0:0" else f"{sum(mine[s] > runs['0:0'][s] for s in mine)} of {len(mine)}"
        rows.append(f"| {b} | {m['seeds']} | {m['median_hypervolume_fraction_at_500']:.3f} ({min(mine.values()):.3f}.."
                    f"{max(mine.values()):.3f}) | {m['median_igd_plus_at_500']:.3f} | {above} |")
    ref = r["reference"]
    medians = {label(a): m["median_hypervolume_fraction_at_500"] for a, m in r["summary"].items()}
    moved = [record(k)["summary"]["nsga2-p24"]["median_hypervolume_fraction_at_500"] for k in ("design_population", "design_population_12")]
    noise = max(moved) - min(moved)
    best = max(medians, key=medians.get)
    lines = [f"Every run searched {r['max_designs']} distinct designs; the reference front is the front of all "
             f"{ref['runs']} runs ({ref['front']} designs of {feasible(ref)}), `{RECORDS['design_breeding']}`."]
    for b, v in medians.items():
        if b != "0:0":
            lines.append(f"{b} against 0:0: {v - medians['0:0']:+.3f} at {t['designs']} designs.")
    if best == "0:0":
        lines.append("No breeding's median is above 0:0's.")
    else:
        lines.append(f"The best median is {best}'s; the same search's median moved {noise:.3f} between two invocations "
                     f"(population 24 in the population records above), so {best} beats 0:0 by "
                     f"{'more' if medians[best] - medians['0:0'] > noise else 'no more'} than that.")
    return "\n".join(rows) + "\n\n" + " ".join(lines) + "\n"


def stop_by_rule(progress, window, tolerance):
    """Where a run's own stagnation rule (the report's: the hypervolume gained no more than `tolerance`
    of itself over `window` generations' worth of designs) would have ended it: its progress point."""
    for i in range(window, len(progress)):
        now, then = progress[i]["hypervolume_fraction"], progress[i - window]["hypervolume_fraction"]
        if now - then <= tolerance * now:
            return progress[i], True
    return progress[-1], False


def meets_500(r, hv, igd):
    """Whether a median hypervolume and IGD+ at 500 designs meet the record's 500-design target."""
    return hv >= r["targets"]["hypervolume_fraction"] and igd <= r["targets"]["igd_plus"]


def searched_500(r, key):
    """What every run of a 500-design record searched, on what, and which record it is."""
    return (f"Every run searched {r['max_designs']} distinct designs on {r['jobs']} jobs ({r['granstack']}, "
            f"`{RECORDS[key]}`). ")


def design_repeat():
    """Every seed's search made twice against a kept reference front, at 500 designs (bench/design_budget.sh
    ROUNDS=2 REFERENCE=...): how far one seed's run moves between two runs on 2 jobs."""
    r = record("design_repeat")
    runs = {}
    for run in r["runs"]:
        name, _, round_ = run["algorithm"].partition("-r")
        runs.setdefault(name, {}).setdefault(run["seed"], {})[int(round_ or 1)] = run
    rows = ["| algorithm | seed | hypervolume at 500 designs (of the reference's), run 1 | run 2 | difference | IGD+, run 1 | run 2 |",
            "|---|---|---|---|---|---|---|"]
    said = []
    for name, seeds in runs.items():
        for seed, pair in sorted(seeds.items()):
            a, b = pair[1], pair[2]
            rows.append(f"| {name} | {seed} | {a['hypervolume_fraction_at_500']:.3f} | {b['hypervolume_fraction_at_500']:.3f} | "
                        f"{b['hypervolume_fraction_at_500'] - a['hypervolume_fraction_at_500']:+.3f} | "
                        f"{a['igd_plus_at_500']:.4f} | {b['igd_plus_at_500']:.4f} |")
        moved = [abs(p[2]["hypervolume_fraction_at_500"] - p[1]["hypervolume_fraction_at_500"]) for p in seeds.values()]
        medians = [statistics.median(p[k]["hypervolume_fraction_at_500"] for p in seeds.values()) for k in (1, 2)]
        igd = [statistics.median(p[k]["igd_plus_at_500"] for p in seeds.values()) for k in (1, 2)]
        met = [meets_500(r, m, i) for m, i in zip(medians, igd)]
        said.append(f"{name}: the median of the {len(seeds)} seeds {medians[0]:.3f} and {medians[1]:.3f} (IGD+ {igd[0]:.4f} and "
                    f"{igd[1]:.4f}; the 500-design target {'met' if all(met) else 'met by one run' if any(met) else 'not met'}); "
                    f"a seed moved by {statistics.median(moved):.3f} between its runs (median; at most {max(moved):.3f}), the "
                    f"median of the seeds by {abs(medians[1] - medians[0]):.3f}.")
    ref = r["reference"]
    return ("\n".join(rows) + "\n\n"
            f"The reference: `{ref['kept']}` ({ref['front']} designs, hypervolume {ref['hypervolume']:.6f}), kept from {ref['made']}. "
            + searched_500(r, "design_repeat") + " ".join(said) + "\n")


def sms_emoa_rounds(screening):
    """The median of 5 seeds' hypervolume at 500 designs of SMS-EMOA with this screening (the regression's; screening
    1 is the unscreened search, whose code did not change) against the kept front, per round that ran it, over the
    records: [(record, median)]. A ten-minute run's first 500 designs are a 500-design run's."""
    keys = ["design_repeat", "design_ten_minutes"] + (["design_screening_nearest"] if screening == 1 else []) + \
        ["design_screening", "design_ten_minutes_screening"]
    out = []
    for key in keys:
        rounds = {}
        for run in record(key)["runs"]:
            label = run["algorithm"]
            if not (label == "sms-emoa" or label.startswith("sms-emoa-r") or label.startswith("sms-emoa-sc")):
                continue
            if run.get("screening", int(label.partition("-sc")[2] or 1)) != screening or not run["shortcuts"]:
                continue
            rounds.setdefault(label, []).append(run["hypervolume_fraction_at_500"])
        out += [(RECORDS[key], statistics.median(v)) for _, v in sorted(rounds.items())]
    return out


def design_screening():
    """[search] screening against none, each seed's 500-design search with and without, against the kept front."""
    r = record("design_screening")
    by = {}
    for run in r["runs"]:
        name, _, screening = run["algorithm"].partition("-sc")
        by.setdefault((name, int(screening)), {})[run["seed"]] = run
    rows = ["| algorithm | screening | seeds | hypervolume at 500 designs (of the reference's) | IGD+ at 500 designs | "
            "seeds above screening 1's run | refsim s per design |", "|---|---|---|---|---|---|---|"]
    said = []
    for (name, screening), seeds in sorted(by.items()):
        hv = [x["hypervolume_fraction_at_500"] for x in seeds.values()]
        igd = [x["igd_plus_at_500"] for x in seeds.values()]
        base = by.get((name, 1), {})
        above = "-" if screening == 1 else f"{sum(x['hypervolume_fraction_at_500'] > base[k]['hypervolume_fraction_at_500'] for k, x in seeds.items())} of {len(seeds)}"
        rows.append(f"| {name} | {screening} | {len(seeds)} | {statistics.median(hv):.3f} ({min(hv):.3f}..{max(hv):.3f}) | "
                    f"{statistics.median(igd):.4f} | {above} | "
                    f"{statistics.median(x['refsim_seconds_per_design'] for x in seeds.values()):.2f} |")
        if screening > 1 and base:
            gain = statistics.median(hv) - statistics.median(x["hypervolume_fraction_at_500"] for x in base.values())
            said.append((name, screening, gain, statistics.median(hv), statistics.median(igd)))
    text = []
    for name, screening, gain, hv, igd in said:
        rounds = {k: sms_emoa_rounds(k) for k in (1, screening)}
        listed = {k: f"{', '.join(f'{m:.3f}' for _, m in v)} ({', '.join(dict.fromkeys(f'`{r}`' for r, _ in v))})"
                  for k, v in rounds.items()}
        low = min(m for _, m in rounds[screening])
        high = max(m for _, m in rounds[1])
        target = "met" if meets_500(r, hv, igd) else "not met"
        text.append(f"{name} with screening {screening}: the median {gain:+.3f} from screening 1's in the same invocation; "
                    f"the median of 5 seeds at 500 designs over every round that ran it, unscreened: {listed[1]}; "
                    f"screening {screening}: {listed[screening]}: its worst round is "
                    f"{'above' if low > high else 'not above'} the unscreened search's best; the 500-design target {target}.")
    ref = r["reference"]
    return ("\n".join(rows) + "\n\n"
            f"The reference: `{ref['kept']}` ({ref['front']} designs). " + searched_500(r, "design_screening") + " ".join(text) + "\n")


def feasible(ref):
    """How many feasible designs, run in full, a record's own reference front was made from (records before the front's
    designs were kept name the count "designs")."""
    return ref["feasible"] if "feasible" in ref else ref["designs"]


def ten_minute_row(r, algorithm, label, least_designs=1000):
    """One algorithm's runs of a ten-minute record: its table row (seeds, hypervolume and IGD+ in the time, designs,
    seeds reaching the target and when, hypervolume at 500 designs) and its verdict on the 2-core target (#50's:
    the median hypervolume and at least `least_designs` distinct designs in every run; #67 item 7's asks none)."""
    t = r["targets"]
    m = r["summary"][algorithm]
    mine = [x for x in r["runs"] if x["algorithm"] == algorithm and x["shortcuts"]]
    igd = [[p["igd_plus"] for p in x["progress"] if p["seconds"] <= t["seconds"]][-1] for x in mine]
    hv = [x["hypervolume_fraction_in_600_s"] for x in mine]
    designs = [x["designs_in_600_s"] for x in mine]
    reached = sorted((x["seconds_to_target"], x["designs_to_target"]) for x in mine if x["seconds_to_target"] is not None)
    row = (f"| {label} | {m['seeds']} | {statistics.median(hv):.3f} ({min(hv):.3f}..{max(hv):.3f}) | "
           f"{statistics.median(igd):.4f} | {statistics.median(designs):.0f} ({min(designs)}..{max(designs)}) | "
           f"{m['seeds_reaching_target']} of {m['seeds']} | {', '.join(f'{s:.0f}' for s, _ in reached) or '-'} | "
           f"{', '.join(f'{n}' for _, n in reached) or '-'} | {m['median_hypervolume_fraction_at_500']:.3f} |")
    met = statistics.median(hv) >= t["hypervolume_fraction"] and min(designs) >= least_designs
    verdict = ("met" if met else "not met") if len(mine) >= 5 else f"not judged ({len(mine)} seeds; the target is a median of 5)"
    needed = [n for _, n in reached]
    times = (f", {statistics.median(needed) / t['designs']:.1f} times the {t['designs']} of the machine-independent target"
             if least_designs else "")
    budget = (f" The runs that reached it needed a median {statistics.median(needed):.0f} distinct designs "
              f"({min(needed)}..{max(needed)}){times}." if needed else "")
    least = f", and at least {min(designs)} distinct designs in every run," if least_designs else ""
    return row, (f"{label}: a median {statistics.median(hv):.3f} of the reference's hypervolume{least} in "
                 f"{t['seconds']:.0f} s on {r['cores']} cores (-j {r['jobs']}): the 2-core target {verdict}.{budget}")


def ten_minute_header(t, first):
    """The ten-minute tables' header rows (`first`: the first column's name)."""
    return [f"| {first} | seeds | hypervolume in {t['seconds']:.0f} s (of the reference's) | IGD+ in {t['seconds']:.0f} s | "
            f"designs in {t['seconds']:.0f} s | seeds reaching {t['hypervolume_fraction']} | seconds to reach it | "
            f"designs to reach it | hypervolume at {t['designs']} designs |", "|---|---|---|---|---|---|---|---|---|"]


def design_cost():
    """What a design of the yielding example costs, this build against another on the same drawn designs
    (bench/design_cost.sh): alternating rounds, medians, and whether the measures stayed the same."""
    r = record("design_cost")
    b, t = r["median_seconds"]["base"], r["median_seconds"]["this"]
    rb, rt = r["seconds"]["base"], r["seconds"]["this"]
    return (f"| build | wall time for the batch, median of {r['repeats']} (min..max) | designs run | refsim s in all |\n"
            f"|---|---|---|---|\n"
            f"| {r['base']} | {b:.1f} s ({min(rb):.1f}..{max(rb):.1f}) | {r['designs_run']['base']} | {r['refsim_seconds']['base']:.1f} |\n"
            f"| {r['this']} | {t:.1f} s ({min(rt):.1f}..{max(rt):.1f}) | {r['designs_run']['this']} | {r['refsim_seconds']['this']:.1f} |\n"
            f"\n{r['population']} designs drawn as a generation 0 (the probes and the study's designs beside them), "
            f"-j {r['jobs']}, the builds alternating: this build takes {r['ratio']:.2f} of the other's time. The "
            f"{r['both_in_full']} designs both ran in full have {'the same' if r['measures_identical'] else 'DIFFERENT'} "
            f"measures, to the bit, and srs_peak within {r['srs_largest_relative_difference']:.1g} (relative); "
            f"`{RECORDS['design_cost']}`.\n")


def design_ten_minutes(key="design_ten_minutes", least_designs=1000):
    """The search given the whole 10 minutes on 2 cores (no design cap, no stagnation stop), each seed against
    the front of all the record's runs; then the stagnation rule judged on those runs after the fact."""
    r = record(key)
    t = r["targets"]
    rows = ten_minute_header(t, "algorithm")
    verdicts = []
    for algorithm, m in r["summary"].items():
        row, verdict = ten_minute_row(r, algorithm, algorithm, least_designs)
        rows.append(row)
        verdicts.append(verdict)
    ref = r["reference"]
    lines = [f"Every run had the whole {r['time_limit']:.0f} s (no design cap, no stagnation rule); the reference front is "
             f"the front of all {ref['runs']} runs ({ref['front']} designs of {feasible(ref)}), `{RECORDS[key]}`. "
             f"Builds: {r['granstack']}."] + verdicts
    # The stagnation rule, judged on these runs: where each would have stopped.
    tolerance = 1e-3
    rules = [f"| algorithm | window (generations), tolerance {tolerance:g} | runs it stopped before the time limit | "
             f"seconds at the stop | designs at the stop | hypervolume at the stop (of the reference's) |", "|---|---|---|---|---|---|"]
    windows = []
    for algorithm in r["summary"]:
        mine = [x for x in r["runs"] if x["algorithm"] == algorithm and x["shortcuts"]]
        enough = None
        for window in (5, 10, 20, 40):
            stops = [stop_by_rule(x["progress"], window, tolerance) for x in mine]
            hv = [p["hypervolume_fraction"] for p, _ in stops]
            if enough is None and statistics.median(hv) >= t["hypervolume_fraction"]:
                enough = window
            rules.append(f"| {algorithm} | {window} | {sum(s for _, s in stops)} of {len(stops)} | "
                         f"{statistics.median(p['seconds'] for p, _ in stops):.0f} | {statistics.median(p['designs'] for p, _ in stops):.0f} | "
                         f"{statistics.median(hv):.3f} ({min(hv):.3f}..{max(hv):.3f}) |")
        windows.append(f"{algorithm}: " + (f"the shortest window whose stops keep a median of {t['hypervolume_fraction']} is "
                                           f"{enough} generations" if enough else f"no window's stops keep a median of "
                                           f"{t['hypervolume_fraction']}") + ".")
    # The two algorithms against each other, seed by seed.
    by = {a: sorted(x["hypervolume_fraction_in_600_s"] for x in r["runs"] if x["algorithm"] == a and x["shortcuts"]) for a in r["summary"]}
    if len(by) == 2:
        (a, va), (b, vb) = sorted(by.items(), key=lambda kv: -statistics.median(kv[1]))
        lines.append(f"In {t['seconds']:.0f} s {a}'s median is {statistics.median(va) - statistics.median(vb):+.3f} from {b}'s; "
                     f"{sum(x > max(vb) for x in va)} of {len(va)} {a} seeds are above every {b} seed.")
    return ("\n".join(rows) + "\n\n" + " ".join(lines) + "\n\n" + "The rule on each run, after the fact (a run with the "
            "rule would have been the same run up to its stop):\n\n" + "\n".join(rules) + "\n\n" + " ".join(windows) + "\n")


def design_ten_minutes_screening():
    """The shipped example's algorithm given the whole 10 minutes on 2 cores with [search] screening, against the
    kept front (the ten-minute record's own), beside that record's unscreened runs."""
    plain, screened = record("design_ten_minutes"), record("design_ten_minutes_screening")
    t = screened["targets"]
    rows = ten_minute_header(t, "search")
    verdicts = []
    for r, algorithm in ((plain, "sms-emoa"), (screened, "sms-emoa")):
        screening = {x.get("screening", 1) for x in r["runs"] if x["algorithm"] == algorithm}
        assert len(screening) == 1, f"{algorithm}'s runs name screenings {screening}"
        row, verdict = ten_minute_row(r, algorithm, f"{algorithm}, screening {screening.pop()}")
        rows.append(row)
        verdicts.append(verdict)
    ref = screened["reference"]
    assert ref["kept"] == "bench/results/design-reference-front-2026-11-29.json", ref
    return ("\n".join(rows) + "\n\n"
            f"The reference: `{ref['kept']}` ({ref['front']} designs), the front of the unscreened record's 10 runs "
            f"(`{RECORDS['design_ten_minutes']}`: {plain['granstack']}). The screened runs: `{RECORDS['design_ten_minutes_screening']}` "
            f"({screened['granstack']}), another invocation. " + " ".join(verdicts) + "\n")


def design_shortcuts():
    """One seed with the shortcuts and without (bench/design_budget.sh, #50)."""
    r = record("design_budget")
    rows = ["| shortcuts | designs | wall | refsim s | refsim s per design | on censored runs | on scenarios deciding no objective | "
            "on designs off the front | settled (censored / constraint / dominated) | scenario runs not run |",
            "|---|---|---|---|---|---|---|---|---|---|"]
    for key in ("on", "off"):
        x = r["shortcuts"][key]
        n = lambda k: x["settled"].get(k, 0)
        share = lambda k: f"{100 * x[k]:.1f} %"
        rows.append(f"| {key} | {x['designs']} | {x['seconds']:.0f} s | {x['refsim_seconds']:.0f} | {x['refsim_seconds_per_design']:.2f} | "
                    f"{share('share_censored')} | {share('share_undecided')} | {share('share_off_front')} | "
                    f"{n('censored')} / {n('constraint')} / {n('dominated')} | {x['scenario_runs_not_run']} |")
    on, off = r["shortcuts"]["on"], r["shortcuts"]["off"]
    return ("\n".join(rows) + f"\n\n{on['algorithm']}, seed {on['seed']}: the shortcuts cut refsim's time per design "
            f"{off['refsim_seconds_per_design'] / on['refsim_seconds_per_design']:.2f} times.\n")


def oversubscription():
    """refsim with 4 threads per CPU against one thread (bench/oversubscription.sh)."""
    r = record("oversubscription")
    return (f"Measured on {r['cpus']} CPUs (Fig. 3's three blocks, medians of {r['repeats']} alternating runs, "
            f"`{RECORDS['oversubscription']}`): refsim with `--threads {r['threads']}` took "
            f"{r['seconds_oversubscribed']:.2f} s against {r['seconds_one_thread']:.3f} s with one thread, "
            f"{r['ratio']:.0f} times as long.\n")


def reduce_speed():
    """reduce's reading speed against wc -l on the same dump (bench/reduce_vs_wc.sh)."""
    r = record("reduce_speed")
    rows = [f"| dump | wc -l | reduce, {r['cores']} threads | ratio | one thread | ratio | peak memory (a quarter of the frames) |",
            "|---|---|---|---|---|---|---|"]
    for fmt, f in r["formats"].items():
        m = {k: statistics.median(v) for k, v in f["seconds"].items()}
        rows.append(f"| {fmt}, {f['dump_mb']:.0f} MB | {f['dump_mb'] / m['wc']:.0f} MB/s | "
                    f"{f['dump_mb'] / m['reduce']:.0f} MB/s | {f['ratio']:.3f} | {f['dump_mb'] / m['reduce1']:.0f} MB/s | "
                    f"{f['ratio_one_thread']:.3f} | {f['peak_mb']:.0f} MB ({f['peak_mb_quarter']:.0f} MB) |")
    build = f", {r['granstack']}" if "granstack" in r else ""
    text = (f"Medians of {r['repeats']} alternating runs, warm page cache (`{RECORDS['reduce_speed']}`{build}):\n\n"
            + "\n".join(rows) + "\n")
    if "base" in r:
        against = "; ".join(f"{fmt} {f['base_over_this']:.3f} times as long (ratio to `wc -l` "
                            f"{statistics.median(f['seconds']['wc']) / statistics.median(f['seconds']['reduce_base']):.3f})"
                            for fmt, f in r["formats"].items())
        text += (f"\nThe build before, {r['base']}, timed in the same rounds (the median of each round's ratio): "
                 f"{against}.\n")
    return text


def extension_counts():
    """The files each extension touched, from its commits (scripts/extension_counts.py)."""
    rows = ["| extension | commits | library and program files (by folder) | test files | deck templates | other files |",
            "|---|---|---|---|---|---|"]
    for r in record("extension_counts")["extensions"]:
        folders = ", ".join(f"{n} in `{d}/`" for d, n in r["by_folder"].items())
        files = f"{r['library_files']} ({folders})" if folders else str(r["library_files"])
        rows.append(f"| {r['extension']} | {', '.join(r['commits'])} | {files} | "
                    f"{r['test_files']} | {r['templates']} | {r['other_files']} |")
    return "\n".join(rows) + "\n"


def engines_agreement():
    """validate --engines on every pair of engines and case (bench/engines.sh)."""
    names = {"two_body": "two-body, e = 1", "elastic": "stack, e = 1", "elastic_wall": "stack on a wall, e = 1",
             "damped": "stack, e = 0.9", "damped_wall": "stack on a wall, e = 0.9", "friction": "stack, e = 0.9, mu = 0.3",
             "friction_walls_gravity": "stack, e = 0.9, mu = 0.3, walls, gravity"}
    cells = {}
    for a in record("engines")["agreement"]:
        cells.setdefault(a["case"], {})[tuple(a["engines"])] = f"{a['largest']:.2g} ({a['where']})"
    pairs = [("liggghts", "lammps"), ("lammps", "refsim"), ("liggghts", "refsim")]
    rows = ["| case | LIGGGHTS - LAMMPS | LAMMPS - refsim (LAMMPS's rules) | LIGGGHTS - refsim |", "|---|---|---|---|"]
    for case, label in names.items():
        rows.append(f"| {label} | " + " | ".join(cells[case][p] for p in pairs) + " |")
    return "\n".join(rows) + "\n"


def engines_speed():
    """Loop seconds of the three engines on two cases (bench/engines.sh)."""
    r = record("engines")
    speed, names = r["speed"], r["cases"]
    rows = ["| case | outputs | LIGGGHTS | LAMMPS | refsim | LAMMPS / LIGGGHTS |", "|---|---|---|---|---|---|"]
    for case in ("quick", "damped"):
        for o, label in (("", "default"), ("_off", "off")):
            t = {e: speed[f"{case}{o}.{e}"] for e in ("liggghts", "lammps", "refsim")}
            span = lambda e: f"{t[e]['median']:.3f} s ({min(t[e]['runs']):.3f}..{max(t[e]['runs']):.3f})"
            rows.append(f"| {names[case]} | {label} | {span('liggghts')} | {span('lammps')} | {span('refsim')} | "
                        f"{t['lammps']['median'] / t['liggghts']['median']:.2f} |")
    return "\n".join(rows) + "\n"


def run_engines_study(exe, work):
    """The study on LAMMPS against the LIGGGHTS reproduction reproduce_table made (reproduce --against),
    kept as the record RECORDS["engines_study"] names."""
    out = work / "reproduce_lammps"
    granstack(exe, "reproduce", "-j", "2", "--force", "--engine", "lammps", "--against", str(work / "reproduce"), "-o", str(out))
    record = {"made_by": "python3 scripts/doc_tables.py --write --reproduce GRANSTACK WORKDIR",
              "granstack": json.loads((out / "report.json").read_text())["git_commit"],
              "against": json.loads((out / "report.json").read_text())["against"]}
    (ROOT / RECORDS["engines_study"]).write_text(json.dumps(record, indent=2) + "\n")


def engines_study():
    """The LAMMPS page's table from the study's record."""
    a = json.loads((ROOT / RECORDS["engines_study"]).read_text())["against"]
    beyond = [c for c in a["claims"] if c["relative"] is None or c["relative"] > 1e-12]
    largest = max(a["claims"], key=lambda c: c["relative"] or 0.0)
    rows = [f"{a['changed']} of {len(a['claims'])} statements change their verdict between LIGGGHTS and LAMMPS; "
            f"{len(a['claims']) - len(beyond)} agree to round-off (at most 1e-12), and {len(beyond)} differ by more, "
            f"the largest by {largest['relative']:.2g} ({largest['claim']}):", "",
            "| claim | LAMMPS | LIGGGHTS | relative difference | verdicts | why |", "|---|---|---|---|---|---|"]
    for c in beyond:
        verdicts = c["verdict_here"] if c["verdict_here"] == c["verdict_there"] else f"{c['verdict_there']} -> {c['verdict_here']}"
        rows.append(f"| {c['claim']} | {number(c['here'])} | {number(c['there'])} | {c['relative']:.2g} | {verdicts} | "
                    f"{c['cause'].split(':')[0]} |")
    return "\n".join(rows) + "\n"


def reproduce_record():
    return json.loads((ROOT / RECORDS["reproduce"]).read_text())


def reproduce_cost():
    """The study's size and time, said once and made from bench/reproduce.sh's record."""
    r, m = reproduce_record(), statistics.median
    wall, cpu = r["seconds"], r["cpu_seconds"]
    return (f"The study's {r['cases']} cases reproduce in about {m(wall['reproduce']):.0f} s on 2 cores "
            f"(`granstack reproduce -j 2`, every experiment from scratch; bare LIGGGHTS on the same cases, two at a "
            f"time, takes {m(wall['bare_liggghts']):.0f} s: reproduce is {m(wall['reproduce']) / m(wall['bare_liggghts']):.2f} "
            f"times it in wall time, {m(cpu['reproduce']) / m(cpu['bare_liggghts']):.2f} in CPU time; medians of "
            f"{r['repeats']} runs by `bench/reproduce.sh`, `{RECORDS['reproduce']}`).\n")


def reproduce_speed():
    """Every reproduce the benchmark times and its two baselines, wall and CPU time, medians (min..max) of its
    alternating runs, and the ratios the targets are stated in."""
    r, m = reproduce_record(), statistics.median
    wall, cpu = r["seconds"], r["cpu_seconds"]
    runs = [("`reproduce`, every experiment", "reproduce"), ("`reproduce --validate`", "validate"),
            ("`reproduce --quick`", "quick"), ("`granstack run -j 2 --force` on the same cases", "baseline_run"),
            ("bare LIGGGHTS on the same cases, two at a time", "bare_liggghts")]
    if "reproduce_base" in wall:
        runs.append((f"`reproduce` of the build before, {r['base']}", "reproduce_base"))
    rows = [f"| run ({r['cases']} cases, -j 2, from scratch) | wall, median | min..max | CPU, median | min..max |",
            "|---|---|---|---|---|"]
    for label, key in runs:
        w, c = wall[key], cpu[key]
        rows.append(f"| {label} | {m(w):.1f} s | {min(w):.1f}..{max(w):.1f} s | {m(c):.1f} s | {min(c):.1f}..{max(c):.1f} s |")
    ratio = lambda a, b, t: m(t[a]) / m(t[b])
    text = (f"\n\n`reproduce` over bare LIGGGHTS: {ratio('reproduce', 'bare_liggghts', wall):.3f} in wall time, "
            f"{ratio('reproduce', 'bare_liggghts', cpu):.3f} in CPU time (target 1.10 in CPU time); over `granstack run`: "
            f"{ratio('reproduce', 'baseline_run', wall):.3f} and {ratio('reproduce', 'baseline_run', cpu):.3f}. "
            f"`granstack run` over bare LIGGGHTS: {ratio('baseline_run', 'bare_liggghts', wall):.3f} in wall time, "
            f"{ratio('baseline_run', 'bare_liggghts', cpu):.3f} in CPU time (target 1.03).")
    if "reproduce_base" in wall:
        text += (f" The build before over bare LIGGGHTS: {ratio('reproduce_base', 'bare_liggghts', wall):.3f} in wall time, "
                 f"{ratio('reproduce_base', 'bare_liggghts', cpu):.3f} in CPU time.")
    own = r.get("own_cpu_seconds", {})
    if own:
        # granstack's own process against the programs it started, in the same minutes: free of the drift between
        # rounds that the ratios to bare LIGGGHTS carry.
        share = lambda k: f"{m(own[k]):.1f} s of {m(cpu[k]):.1f} s ({100 * m([o / c for o, c in zip(own[k], cpu[k])]):.1f} %)"
        text += (f"\n\ngranstack's own process (every thread, not the programs it starts), medians: `reproduce` "
                 f"{share('reproduce')}, `granstack run` {share('baseline_run')}"
                 + (f", the build before's `reproduce` {share('reproduce_base')}" if "reproduce_base" in own else "")
                 + f". `granstack run`'s own process alone is {100 * m(own['baseline_run']) / m(cpu['bare_liggghts']):.1f} % of "
                 f"bare LIGGGHTS's CPU time (the target for `run` in all: 3 %).")
    return "\n".join(rows) + text + "\n"


def run_overhead():
    """What `granstack run` adds to LIGGGHTS in CPU time, case by case: each case run bare and by
    `granstack run` one right after the other (bench/run_overhead.sh's record)."""
    r, m = json.loads((ROOT / RECORDS["run_overhead"]).read_text()), statistics.median
    rounds = r["rounds"]
    rows = ["| round | bare LIGGGHTS, CPU | `granstack run`, CPU | its own process | run / bare |", "|---|---|---|---|---|"]
    for i, x in enumerate(rounds, 1):
        rows.append(f"| {i} | {x['bare']:.1f} s | {x['run']:.1f} s | {x['own']:.2f} s | {x['run'] / x['bare']:.4f} |")
    ratio = [x["run"] / x["bare"] for x in rounds]
    own = [100 * x["own"] / x["bare"] for x in rounds]
    starts = [100 * r["cases"] * x["start"] / x["bare"] for x in rounds]
    programs = [(x["run"] - x["own"]) / x["bare"] for x in rounds]
    return ("\n".join(rows) + f"\n\nThe {r['cases']} cases, each run bare and by `granstack run --force` one right after the "
            f"other, two such pairs at a time, {r['repeats']} rounds: `granstack run` over bare LIGGGHTS "
            f"{m(ratio):.3f} in CPU time ({min(ratio):.3f}..{max(ratio):.3f}; the target 1.03). granstack's own process is "
            f"{m(own):.1f} % of bare LIGGGHTS's time, {m(starts):.1f} % of it the {r['cases']} starts of granstack this "
            f"measure makes (`granstack run -j 2 CASES...` starts once); the programs it starts take "
            f"{m(programs):.3f} times bare LIGGGHTS's time.\n")


def blow_end_judge():
    """What the blow-end judge costs LIGGGHTS: the study's decks of two builds, each case's run bare
    one right after the other (bench/blow_end_judge.sh's record)."""
    r = json.loads((ROOT / RECORDS["blow_end_judge"]).read_text())
    rows = ["| round | the build before's decks, CPU | this build's decks, CPU | this / before |", "|---|---|---|---|"]
    for i, x in enumerate(r["rounds"], 1):
        rows.append(f"| {i} | {x['base']:.1f} s | {x['this']:.1f} s | {x['this'] / x['base']:.4f} |")
    ratio = [x["this"] / x["base"] for x in r["rounds"]]
    return ("\n".join(rows) + f"\n\nThe {r['cases']} cases, {r['repeats']} rounds, two pairs at a time: this build's decks "
            f"cost bare LIGGGHTS {statistics.median(ratio):.3f} times the CPU time of the build before's "
            f"({min(ratio):.3f}..{max(ratio):.3f}), every case's dumps and series byte for byte the same.\n")


def number(v):
    return "-" if v is None else f"{v:.4g}"


def from_paper(c):
    """(granstack - paper) / paper as the report prints it, with standard errors where a fit has them."""
    if c["from_paper"] is None:
        return "-"
    p = 100.0 * c["from_paper"]
    a = abs(p)
    text = "0.000 %" if a < 0.0005 else f"{p:+.3f} %" if a < 1 else f"{p:+.2f} %" if a < 10 else f"{p:+.1f} %" if a < 100 else f"{p:+.0f} %"
    if c["sigmas"] is not None:
        text += f" ({c['sigmas']:+.2g} s.e.)"
    return text


def reproduce_table(exe, work, engine):
    """The report's summary (every claim, whose it is, its primary reading and verdict) and the
    notes it quotes, from `granstack reproduce` run again from scratch on `engine`."""
    out = work / ("reproduce" if engine == "liggghts" else "reproduce_" + engine)
    granstack(exe, "reproduce", "-j", "2", "--force", "--engine", engine, "-o", str(out))
    report = json.loads((out / "report.json").read_text())
    cases = sum(len(e["cases"]) for e in report["experiments"])
    if cases != reproduce_record()["cases"]:
        sys.exit(f"the study has {cases} cases, {RECORDS['reproduce']} timed {reproduce_record()['cases']}: "
                 "run bench/reproduce.sh again (OUT=...) and point RECORDS at its record")
    whose = {"paper": "the paper", "granstack": "granstack's"}
    rows = ["| claim | whose | the statement | paper | granstack | from the paper | verdict |", "|---|---|---|---|---|---|---|"]
    notes = []
    for e in report["experiments"]:
        for c in e["claims"]:
            verdict = f"outside, by {100 * c['off']:.0f} %" if c["verdict"] == "outside" else c["verdict"]
            rows.append(f"| {c['id']} | {whose.get(c['scope'], c['scope'])} | {c['summary']} | {number(c['paper'])} | "
                        f"{number(c['value'])} | {from_paper(c)} | {verdict} |")
        notes += [n for n in e["notes"] if n.startswith(QUOTED_NOTES)]
    return "\n".join(rows) + "\n\n" + "\n\n".join(notes) + "\n"


def main():
    args = [a for a in sys.argv[1:] if a != "--reproduce"]
    if len(args) != 3 or args[0] not in ("--write", "--check"):
        sys.exit(__doc__)
    mode, exe, work = args[0], str(pathlib.Path(args[1]).resolve()), pathlib.Path(args[2]).resolve()
    work.mkdir(parents=True, exist_ok=True)
    if mode == "--check":
        # The check's runs in a directory of their own, removed when every table holds (the
        # study's dumps and reductions are most of a gigabyte); a failed check keeps them.
        work = pathlib.Path(tempfile.mkdtemp(prefix="check-", dir=work))
    made = tables(exe, work)
    made.update(nest_counts=nest_counts(), nest_speed=nest_speed(), refsim_against_liggghts=refsim_against_liggghts(),
                refsim_outside_loop=refsim_outside_loop(),
                large_nest=large_nest(), copies=copies(), design_speedup=design_speedup(), design_cores=design_cores(),
                design_cores_summary=design_cores_summary(), engines_agreement=engines_agreement(),
                engines_speed=engines_speed(), reproduce_cost=reproduce_cost(), reproduce_speed=reproduce_speed(), run_overhead=run_overhead(),
                blow_end_judge=blow_end_judge(),
                design_front=design_front(), design_sides=design_sides(), design_yield=design_yield(),
                design_yield_front=design_yield_front(), design_yield_cost=design_yield_cost(),
                design_example_cost=design_example_cost(), oversubscription=oversubscription(),
                extension_counts=extension_counts(), reduce_speed=reduce_speed(), design_budget=design_budget(), design_shortcuts=design_shortcuts(),
                design_population=design_population(), design_breeding=design_breeding(),
                design_ten_minutes=design_ten_minutes(), design_repeat=design_repeat(),
                design_ten_minutes_yield=design_ten_minutes("design_ten_minutes_yield", least_designs=0), design_cost=design_cost(),
                design_screening=design_screening(),
                design_ten_minutes_screening=design_ten_minutes_screening(), restitution=restitution())
    places = {**PLACES, **RECORD_PLACES, **REPRODUCE_PLACES}
    if "--reproduce" in sys.argv[1:]:
        made["reproduce"] = reproduce_table(exe, work, "liggghts")
        run_engines_study(exe, work)
    else:
        made["reproduce"] = reproduce_table(exe, work, "refsim")
    made["engines_study"] = engines_study()
    made.update(printouts(exe, work))
    places.update(PRINTOUT_PLACES)
    stale = []
    for name, files in places.items():
        for f in files:
            path = ROOT / f
            text = path.read_text()
            found = [m for m in MARK.finditer(text) if m.group(2) == name]
            if len(found) != 1:
                sys.exit(f"{f}: expected one doc-table '{name}', found {len(found)}")
            if TIMINGS.sub("(timings)", found[0].group(3)) == TIMINGS.sub("(timings)", made[name]):
                continue
            stale.append(f"{f}: the table '{name}' is not what the run gives:\n{found[0].group(3)}\nthe run:\n{made[name]}")
            if mode == "--write":
                m = found[0]
                path.write_text(text[: m.start(3)] + made[name] + text[m.end(3):])
    stale += store_unnamed(exe, work)
    if mode == "--check" and stale:
        sys.exit("\n".join(stale) + "\nrun: python3 scripts/doc_tables.py --write GRANSTACK WORKDIR")
    if mode == "--check":
        shutil.rmtree(work)
    print(f"doc tables: {sum(len(v) for v in places.values())} places, "
          f"{'rewritten where stale' if mode == '--write' else 'all as the run gives'}"
          f"{' (the study on LIGGGHTS and LAMMPS)' if '--reproduce' in sys.argv[1:] else ' (the study on refsim; LAMMPS from its record)'}")


main()
