#!/usr/bin/env bash
# LIGGGHTS against refsim on the study's stacks: N_B = 1..4, e = 1 and 0.9, mu = 0 and 0.25
# (every dumped column, series column and the output fraction within round-off, validate's
# default tolerance). CI runs N_B = 1, 2 (tests/CMakeLists.txt); this runs all 16 cases, a few
# minutes. Usage: scripts/validate_study.sh OUTDIR [TOLERANCE]
set -euo pipefail
out=${1:?usage: $0 OUTDIR [TOLERANCE]}
tolerance=${2:-1e-8}
here=$(cd "$(dirname "$0")/.." && pwd)
gs=${GRANSTACK:-$here/build/release/app/granstack}
"$gs" generate -o "$out" --blocks 1,2,3,4 --restitution 1,0.9 --friction 0,0.25 --force
"$gs" validate -j 2 --tolerance "$tolerance" "$out"
