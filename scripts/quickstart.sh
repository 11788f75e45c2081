#!/usr/bin/env bash
# The main job: install, build, then the study's default stack (4 steel blocks, 8 rows, 2 top
# columns, r = 1 mm, v = 1 m/s, e = 1, mu = 0, free bottom, no gravity) generated, run with
# LIGGGHTS and reduced. The case lives in runs/quickstart; an existing one is reused, never
# overwritten (delete the directory for a fresh run).
set -euo pipefail
cd "$(dirname "$0")/.."
# Only the program: the tests and benchmarks are the test command's to build.
bash scripts/build.sh release granstack
gs=build/release/app/granstack
case_dir=runs/quickstart
# A case made by an older granstack (its manifest's schema is not formats::kManifestSchema, 2) is
# made anew: this granstack would refuse to run it.
if [ -d "$case_dir" ] && ! grep -q '"schema": 2,' "$case_dir/manifest.json" 2>/dev/null; then
  echo "quickstart: $case_dir was made by an older granstack: generating it anew"
  "$gs" generate -o "$case_dir" --force
elif [ -d "$case_dir" ]; then
  echo "quickstart: reusing $case_dir (delete it for a fresh run)"
else
  "$gs" generate -o "$case_dir"
fi
# A reused case whose run is not whole or not as recorded (status says changed, failed or
# interrupted; a record from an older granstack cannot vouch for its outputs) runs again.
if [ -f "$case_dir/run.json" ] && ! "$gs" status "$case_dir" >/dev/null 2>&1; then
  echo "quickstart: $case_dir's run is not as its record says ('granstack status $case_dir' says why): running it again"
  "$gs" run --force "$case_dir"
else
  "$gs" run "$case_dir"
fi
echo
"$gs" reduce "$case_dir"
