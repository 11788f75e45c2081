#!/usr/bin/env bash
# Time-step convergence of the output fraction (evidence for the automatic dt rule,
# docs/timestep.md). Runs the default stack for N_B = 1..4 at e = 1 and e = 0.9 with the
# automatic dt and with dt = 8x, 4x, 2x, 1/2 of it and 1e-9 s (the study's), and prints one JSON
# line per case. Usage: scripts/timestep_study.sh OUTDIR [BLOCKS...]   (takes a few minutes)
set -euo pipefail
out=${1:?usage: $0 OUTDIR [BLOCKS...]}
shift
blocks=("${@:-1 2 3 4}")
here=$(cd "$(dirname "$0")/.." && pwd)
gs=${GRANSTACK:-$here/build/app/granstack}
mkdir -p "$out"
auto_dt=$("$gs" generate -o "$out/probe" --blocks 1 --force >/dev/null && python3 -c "import json,sys;print(json.load(open(sys.argv[1]))['derived']['dt'])" "$out/probe/manifest.json")
for e in 1 0.9; do
  for nb in ${blocks[@]}; do
    for factor in 8 4 2 1 0.5 study; do
      if [ "$factor" = study ]; then dt=1e-9; else dt=$(python3 -c "print($auto_dt*$factor)"); fi
      dir="$out/e${e}_nb${nb}_dt${factor}"
      # The duration of the automatic rule, so only dt changes.
      # The dump at the run's first and last steps only (generate refuses a longer cadence; a
      # first generation dumping every step gives the run's length, which no cadence rounds up).
      "$gs" generate -o "$dir" --blocks "$nb" --restitution "$e" --dt "$dt" --dump-every 1 --large --force >/dev/null
      steps=$(python3 -c "import json,sys;print(json.load(open(sys.argv[1]))['derived']['steps'])" "$dir/manifest.json")
      "$gs" generate -o "$dir" --blocks "$nb" --restitution "$e" --dt "$dt" --dump-every "$steps" --force >/dev/null
      "$gs" run "$dir" >/dev/null
      "$gs" reduce --json "$dir" | python3 -c "import json,sys
r=json.loads(sys.stdin.read()); m=json.load(open('$dir/manifest.json'))['derived']
print(json.dumps({'e': $e, 'blocks': $nb, 'dt': m['dt'], 'dt_factor': '$factor', 'steps': m['steps'], 'output_fraction': r['output_fraction'], 'separated': r['output_separated']}))"
    done
  done
done
