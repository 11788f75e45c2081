# Sourced by the bench scripts: the repository's top folder ($here), the granstack to time ($gs:
# $GRANSTACK, else the release build) and a scratch folder ($work) removed on exit; with KEEP=DIR
# the scratch folder is DIR, kept (a script that appends its runs to a list there, as
# design_budget.sh does, then adds them to those an earlier invocation left).
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
export PYTHONPATH="$here/bench${PYTHONPATH:+:$PYTHONPATH}"  # bench/frames.py for the scripts' Python
gs=${GRANSTACK:-$here/build/release/app/granstack}
if [ -n "${KEEP:-}" ]; then
  work=$(mkdir -p "$KEEP" && cd "$KEEP" && pwd)
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
# A median of fewer than three alternating runs says nothing about a machine that drifts by 30 %:
# every script takes REPEATS >= 3 (its first argument), and refuses fewer.
if [ -n "${repeats:-}" ] && ! [ "$repeats" -ge 3 ] 2>/dev/null; then
  echo "$(basename "$0"): REPEATS is $repeats; give at least 3 (medians of fewer runs are not reported)" >&2
  exit 2
fi
# LIGGGHTS itself on a case directory (for a deck or data file granstack would refuse to run as
# edited): liggghts_directly DIR RANKS X Y Z runs it on an X x Y x Z grid into DIR/log.direct and
# prints "LOOP_SECONDS WALL_SECONDS BUSIEST_OVER_MEAN GHOSTS_PER_OWNED" from its log.
liggghts_directly() {
  local dir=$1 ranks=$2 t0 t1 mpi=(mpirun -np "$2")
  [ "$(id -u)" = 0 ] && mpi+=(--allow-run-as-root)
  [ "$ranks" -gt "$(nproc)" ] && mpi+=(--oversubscribe)
  t0=$(date +%s.%N)
  (cd "$dir" && "${mpi[@]}" liggghts -in in.stack -log log.direct -var gs_ranks_x "$3" -var gs_ranks_y "$4" \
    -var gs_ranks_z "$5" >/dev/null)
  t1=$(date +%s.%N)
  awk -v wall="$(awk "BEGIN{print $t1 - $t0}")" '
    /^Loop time of/ {loop += $4}
    /^Nlocal:/ {own = $2; own_max = $4}
    /^Nghost:/ {ghost = $2}
    END {printf "%s %s %s %s\n", loop, wall, own_max / own, ghost / own}' "$dir/log.direct"
}
# The data file's box as granstack wrote it before 2026-11-26: one top radius (the striker's, the
# first atom's) beyond the lattice's faces in x and y, computed as it was (half_width + r1, whose
# last bit decides on which side of a split plane the centres lying on it fall).
# widen_box_as_before DATA_FILE
widen_box_as_before() {
  python3 - "$1" <<'PY'
import sys
path = sys.argv[1]
lines = open(path).read().split("\n")
x = next(i for i, l in enumerate(lines) if l.endswith(" xlo xhi"))
y = x + 1
half = float(lines[x].split()[1])
first = next(l for l in lines[lines.index("Atoms") + 1:] if l.strip())
wide = half + float(first.split()[2]) / 2
lines[x] = f"{-wide!r} {wide!r} xlo xhi"
lines[y] = f"{-wide!r} {wide!r} ylo yhi"
open(path, "w").write("\n".join(lines))
PY
}
# generate_ends_only DIR ARGS...: `granstack generate -o DIR ARGS...` whose dump holds the run's
# first and last frames only (generate refuses a dump cadence longer than the run, so the run's
# own length, read from a first generation dumping every step, which no cadence rounds up).
# Prints the second generation's lines.
generate_ends_only() {
  local dir=$1 steps
  shift
  "$gs" generate -o "$dir" --force "$@" --dump-every 1 --large >/dev/null
  steps=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['derived']['steps'])" "$dir/manifest.json")
  "$gs" generate -o "$dir" --force "$@" --dump-every "$steps"
}
