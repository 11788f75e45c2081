#!/usr/bin/env bash
# The design search judged by what it finds per minute (issue #50): each of SEEDS run alone with
# each of ALGORITHMS on SPACE (asynchronous, -j JOBS), until it stops improving ([search]
# stagnation = STAGNATION generations, the report's rule: 10), MAX_DESIGNS distinct designs or
# TIME_LIMIT seconds; the reference front is the front of all those runs together. Per run: its hypervolume
# and IGD+ against the reference after each generation's worth of designs, the designs and the
# seconds it needed to reach 0.98 of the reference's hypervolume, and where its refsim time went
# (censored runs, scenarios that decided no objective, designs off its front, the shortcuts). One
# more run, the first seed of the first algorithm with [search] shortcuts = false, measures what
# the shortcuts save. Writes the record (OUT, JSON) the performance page's table is made from.
# With several POPULATIONS each algorithm runs at each, labelled ALGORITHM-pPOPULATION; with several
# BREEDINGS (FRONT_PARENTS:STEP_MUTATION, [search] front_parents and step_mutation) at each,
# labelled ALGORITHM-fFRONT_PARENTS-sSTEP_MUTATION; OFF_RUN=0 leaves out the run without shortcuts.
# With ROUNDS=N every run is made N times, labelled ALGORITHM-rROUND (on more than one job the order
# in which designs end shapes a search, so a seed's run is not the same run twice). With
# REFERENCE=FILE the runs are judged against a front kept by bench/design_reference.py instead of
# their own together (the record then names it); every record keeps its reference front's designs.
# With several SCREENINGS ([search] screening) each runs at each, labelled ALGORITHM-scSCREENING.
# Usage: OUT=bench/results/design-budget-DATE.json bench/design_budget.sh
#   (SPACE, SEEDS="1 2 3 4 5", ALGORITHMS="nsga2 sms-emoa", POPULATIONS=24, BREEDINGS=0.5:0.5, MAX_DESIGNS=1500,
#   TIME_LIMIT=600, STAGNATION=10, JOBS=2, OFF_RUN=1, ROUNDS=1, REFERENCE unset; up to (rounds x seeds x algorithms x populations + 1) x
#   TIME_LIMIT seconds, about 45 minutes on 2 cores with the shortcuts)
set -euo pipefail
source "$(dirname "$0")/common.sh"
: "${OUT:?set OUT to the record to write (bench/results/design-budget-DATE.json)}"
space=${SPACE:-$here/examples/design/least_wall_force.toml}
seeds=${SEEDS:-1 2 3 4 5}
algorithms=${ALGORITHMS:-nsga2 sms-emoa}
populations=${POPULATIONS:-24}
breedings=${BREEDINGS:-0.5:0.5}
off_run=${OFF_RUN:-1}
max_designs=${MAX_DESIGNS:-1500}
stagnation=${STAGNATION:-10}
time_limit=${TIME_LIMIT:-600}
jobs=${JOBS:-2}
rounds=${ROUNDS:-1}
screenings=${SCREENINGS:-1}
runs=()
one() {  # one ALGORITHM SEED SHORTCUTS POPULATION BREEDING [ROUND] [SCREENING]: a search alone in its own store
  local label=$1 front=${5%%:*} step=${5##*:} screening=${7:-1}
  [ "${6:-1}" -gt 1 ] && label="$label-r$6"
  [ "$(wc -w <<< "$screenings")" -gt 1 ] && label="$label-sc$screening"
  [ "$(wc -w <<< "$populations")" -gt 1 ] && label="$label-p$4"
  [ "$(wc -w <<< "$breedings")" -gt 1 ] && label="$label-f$front-s$step"
  local name="$label-$2-$3" dir="$work/$label-$2-$3"
  mkdir -p "$dir"
  sed -e '/^\[search\]$/,$d' "$space" > "$dir/space.toml"
  printf '[search]\npopulation = %s\ngenerations = 1000\nseed = %s\nalgorithm = "%s"\nmax_designs = %s\nstagnation = %s\nshortcuts = %s\n' \
    "$4" "$2" "$1" "$max_designs" "$stagnation" "$3" >> "$dir/space.toml"
  printf 'front_parents = %s\nstep_mutation = %s\n' "$front" "$step" >> "$dir/space.toml"
  [ "$screening" -gt 1 ] && printf 'screening = %s\n' "$screening" >> "$dir/space.toml"
  local t0 t1
  t0=$(date +%s.%N)
  "$gs" design run "$dir/space.toml" -o "$dir/out" -j "$jobs" --time-limit "$time_limit" > "$dir/log" 2>&1
  t1=$(date +%s.%N)
  # Why it ended: the line before the report's, its folder left out.
  echo "$name $t0 $t1 $(grep -v '^report:' "$dir/log" | tail -1 | sed "s|$dir/out|the store|g" | tr -d '\n' | head -c 300)" >> "$work/runs.txt"
  runs+=("$name")
}
first_algorithm=${algorithms%% *}
first_seed=${seeds%% *}
# The seeds alternate between the settings compared (the machine drifts over a long benchmark).
for r in $(seq "$rounds"); do
  for a in $algorithms; do
    for s in $seeds; do
      for p in $populations; do
        for b in $breedings; do
          for c in $screenings; do one "$a" "$s" true "$p" "$b" "$r" "$c"; done
        done
      done
    done
  done
done
[ "$off_run" = 0 ] || one "$first_algorithm" "$first_seed" false "${populations%% *}" "${breedings%% *}"
python3 "$here/bench/design_budget.py" "$work" "$("$gs" --version)" "$(nproc)" "$max_designs" "$time_limit" "$jobs" \
  "$(realpath --relative-to="$here" "$space")" "$stagnation" > "$OUT"
echo "wrote $OUT"
