#!/usr/bin/env bash
# The container's science item: how much of the impact leaks out of the panel the striker hits,
# into the matrix and into the neighbouring panels, against the matrix's stiffness. Three steel
# panels of N_B = 3 blocks of 8 rows (the study's default stack), the centre one hit; the matrix
# a custom material of Teflon's density and Poisson ratio with Young's modulus 1e7 to 1e12 Pa;
# beside them the rigid-separator limit (walls) and panels that only touch (none). Elastic and
# frictionless, then e = 0.9, mu = 0.25. Runs LIGGGHTS (two at a time), a few minutes.
# Usage: scripts/container_study.sh OUTDIR   (prints a Markdown table; needs python3)
set -euo pipefail
out=${1:?usage: $0 OUTDIR}
here=$(cd "$(dirname "$0")/.." && pwd)
gs=${GRANSTACK:-$here/build/release/app/granstack}
common=(--geometry panels --panels 3 --blocks 3 --rows 8 --force)
moduli=(1e7 1e8 1e9 1e10 1e11 1e12)
for damping in "1 0" "0.9 0.25"; do
  read -r e mu <<<"$damping"
  set_dir="$out/e${e}_mu${mu}"
  "$gs" generate -o "$set_dir/walls" "${common[@]}" --restitution "$e" --friction "$mu" --separator walls >/dev/null
  "$gs" generate -o "$set_dir/none" "${common[@]}" --restitution "$e" --friction "$mu" --separator none >/dev/null
  for y in "${moduli[@]}"; do
    "$gs" generate -o "$set_dir/matrix_$y" "${common[@]}" --restitution "$e" --friction "$mu" \
      --custom-material "matrix:2170:$y:0.46" --matrix-material matrix >/dev/null
  done
  cases=("$set_dir/walls" "$set_dir/none")
  for y in "${moduli[@]}"; do cases+=("$set_dir/matrix_$y"); done
  "$gs" run -j 2 --force "${cases[@]}" >/dev/null
  "$gs" reduce --json "${cases[@]}" >"$set_dir/reduce.jsonl"
done
python3 - "$out" <<'PY'
import json, pathlib, sys
out = pathlib.Path(sys.argv[1])
print("| e | mu | separator | matrix Y (Pa) | output fraction | other panels | matrix | leaked (peak) |")
print("|---|---|---|---|---|---|---|---|")
for jsonl in sorted(out.glob("*/reduce.jsonl")):
    for line in jsonl.read_text().splitlines():
        r = json.loads(line)
        panels = r["panel_final_fraction"]
        hit = (len(panels) + 1) // 2 - 1  # the centre panel, the default impact_panel
        others = sum(p for i, p in enumerate(panels) if i != hit)
        name = r["case"]
        separator = name.split("_")[0]
        modulus = name.split("_")[1] if separator == "matrix" else "-"
        print(f"| {r['restitution']:g} | {r['friction']:g} | {separator} | {modulus} | {r['output_fraction']:.4g} | "
              f"{others:.3g} | {r['matrix_final_fraction']:.3g} | {r['leaked_final_fraction']:.3g} "
              f"({r['leaked_peak_fraction']:.3g}) |")
PY
