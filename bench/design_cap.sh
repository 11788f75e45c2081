#!/usr/bin/env bash
# The design example's physics (issue #32): examples/design/least_wall_force.toml searched (the
# generational schedule, which repeats bit for bit) for
# GENERATIONS generations (-j 2) at the default cap (20 automatic durations) and at twice it.
# Prints the front and the study's designs against it (peak force and impulse on the protected
# object, worst of the three striker speeds), how many designs were censored (their blow not
# ended at the cap), what the designs cost on refsim (ended ones against censored ones), and
# whether doubling the cap changed the front or any of its objectives. Then confirms the front's
# first two designs on LIGGGHTS, also as 3D nests (confirm --geometry nested3d): its output, its
# time, and each design's measures as the strip and as the nest.
# Usage: bench/design_cap.sh [GENERATIONS]   (about 10 minutes with 6)
set -euo pipefail
generations=${1:-6}
source "$(dirname "$0")/common.sh"
# The generational search: the same designs on any number of cores, so the docs' figures repeat.
sed -e 's/^\[search\]$/[search]\nevaluation = "generational"/' -e '/^algorithm = /d' "$here/examples/design/least_wall_force.toml" > "$work/example.toml"
example=$work/example.toml
sed 's/^impulse_window = \(.*\)/impulse_window = \1\ncap_durations = 40/' "$example" > "$work/cap40.toml"
for run in cap20 cap40; do
  space=$example
  [ "$run" = cap40 ] && space=$work/cap40.toml
  t0=$(date +%s.%N)
  "$gs" design run "$space" -o "$work/$run" -j 2 --generations "$generations" >/dev/null 2>&1
  python3 -c "import sys,time; print(f'{sys.argv[1]}: {time.time() - float(sys.argv[2]):.0f} s wall')" "$run" "$t0"
done
python3 - "$work/cap20" "$work/cap40" <<'PY'
import json, sqlite3, sys
def load(d):
    c = sqlite3.connect(f"{d}/design.sqlite")
    return {r[0]: r[1:] for r in c.execute(
        "select digest, feasible, description, peak_wall_force, wall_impulse, crush, areal_mass, violations, seconds "
        "from evaluations where searched = 1")}
a, b = load(sys.argv[1]), load(sys.argv[2])
for name, runs in (("cap 20", a), ("cap 40", b)):
    censored = [r for r in runs.values() if "censored" in r[6]]
    ended = [r for r in runs.values() if "censored" not in r[6] and r[7] > 0]
    print(f"{name}: {len(runs)} designs, {len(censored)} censored; refsim per design (three speeds): "
          f"{sum(r[7] for r in ended) / max(1, len(ended)):.2f} s ended, {sum(r[7] for r in censored) / max(1, len(censored)):.2f} s censored")
front = lambda d: {e["digest"]: e for e in json.load(open(f"{d}/report/design.json"))["front"]}
fa, fb = front(sys.argv[1]), front(sys.argv[2])
worst = 0.0
for k in set(fa) & set(fb):
    for o, v in fa[k]["objectives"].items():
        w = fb[k]["objectives"][o]
        worst = max(worst, abs(v - w) / max(abs(v), abs(w)))
print(f"doubling the cap: front of {len(fa)} and {len(fb)} designs, {len(set(fa) ^ set(fb))} differ; "
      f"largest relative change of an objective of a front design: {worst:.3g}")
report = json.load(open(f"{sys.argv[1]}/report/design.json"))
print("the front (worst of 0.5, 1 and 2 m/s): peak wall force (N), wall impulse in 0.1 ms (N s), areal mass (kg/m^2)")
for e in report["front"]:
    o = e["objectives"]
    print(f"  {e['description']:<55} {o['peak_wall_force']:9.4g} {o['wall_impulse']:9.4g} {o['areal_mass']:8.4g}")
print("the study's designs at the same footprint, and the front's best at equal or lower areal mass")
for s in report["study_designs"]:
    o = s["objectives"]
    lighter = [e for e in report["front"] if e["objectives"]["areal_mass"] <= o["areal_mass"]]
    best_f = min(lighter, key=lambda e: e["objectives"]["peak_wall_force"])
    best_i = min(lighter, key=lambda e: e["objectives"]["wall_impulse"])
    print(f"  {s['name']:<38} {o['peak_wall_force']:9.4g} N {o['wall_impulse']:9.4g} N s {o['areal_mass']:8.4g} kg/m^2; "
          f"force {o['peak_wall_force'] / best_f['objectives']['peak_wall_force']:.3g}x ({best_f['description']}), "
          f"impulse {o['wall_impulse'] / best_i['objectives']['wall_impulse']:.3g}x ({best_i['description']})")
PY
t0=$(date +%s.%N)
"$gs" design confirm "$work/cap20" --top 2 --geometry nested3d | sed "s#$work/##g"
python3 -c "import sys,time; print(f'confirm --top 2 --geometry nested3d: {time.time() - float(sys.argv[1]):.0f} s wall')" "$t0"
python3 - "$work/cap20" <<'PY'
import json, sqlite3, sys
c = sqlite3.connect(f"{sys.argv[1]}/design.sqlite")
print("as the strip and as a 3D nest (its worst scenario): peak wall force (N), crush (m), wall impulse (N s)")
for digest, variant in c.execute("select digest, variant from confirmations"):
    desc, force, crush, impulse = c.execute(
        "select description, peak_wall_force, crush, wall_impulse from evaluations where digest = ?", (digest,)).fetchone()
    v = json.loads(variant)["measures"]
    print(f"  {desc:<45} strip {force:9.4g} {crush:9.4g} {impulse:9.4g}   nest {v['peak_wall_force']:9.4g} "
          f"{v['crush']:9.4g} {v['wall_impulse']:9.4g}")
PY
