#!/usr/bin/env bash
# Does the settled density depend on the contact stiffness? (docs/validation.md, issue 14.)
# One Table 2 blend (mix 3) on a smaller bed than the report's: sand cut at 0.1 in instead of
# 0.04 in, a 4 in container filled to 4 in (about 1.2e4 spheres; cubes of 1.6-1.8 in, which
# fit the settled bed), settled by DEM with Young's modulus E/10, E/100 and E/1000 of natural
# aggregate (E = 50 GPa). Prints one markdown row per run. Usage: scripts/validate_stiffness.sh [build-dir] [threads]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
threads=${2:-1}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

echo "| E | after deposition | after DEM (mean ± sd over boxes) | coordination | ended by | simulated s | time step s | overlap mean / max | DEM wall s |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for modulus in 5e9 5e8 5e7; do
  "$build/aggpack" run examples/table2_mix3.toml --quiet --threads "$threads" --out "$out/run" \
    --set 'particles.fine.d_min="0.1 in"' --set 'container.side="4 in"' --set 'particles.fill_height="4 in"' \
    --set 'analysis.box_sides=["1.6 in", "1.7 in", "1.8 in"]' \
    --set "material.youngs_modulus=$modulus" --set "material.wall_youngs_modulus=$modulus" \
    --set 'dynamics.friction_model="mindlin"'
  python3 - "$out/run/summary.json" "$modulus" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
dep, dyn = s["stages"]["deposition"], s["stages"]["dynamics"]
step = dyn["runs"][0]["time_step_s"]
print(f"| {float(sys.argv[2]) / 1e9:g} GPa | {dep['density']['mean']:.4f} | {dyn['density']['mean']:.4f} ± {dyn['density']['sd']:.4f} "
      f"| {dyn['coordination']['mean']:.2f} | {dyn['ended_by']} | {dyn['simulated_time_s']:.2f} | {step:.2e} | "
      f"{dyn['final']['mean_overlap_rel']:.1e} / {dyn['final']['max_overlap_rel']:.1e} | {dyn['wall_clock_s']:.1f} |")
PY
done
