#!/usr/bin/env bash
# Dynamics validation runs of docs/validation.md: the paper's examples settled by DEM, with
# both friction laws, layer-by-layer settling, a 100x softer material and two restitutions.
# Prints one markdown row per run. Usage: scripts/validate_dynamics.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

row() {  # label example seed [--set key=value ...]
  local label=$1 example=$2 seed=$3
  shift 3
  local sets=()
  for s in "$@"; do sets+=(--set "$s"); done
  "$build/aggpack" run "examples/$example.toml" --quiet --seed "$seed" --out "$out/run" "${sets[@]}"
  python3 - "$out/run/summary.json" "$label" "$seed" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
dep, dyn = s["stages"]["deposition"], s["stages"]["dynamics"]
after_dep = dep["density"]["mean"] if "density" in dep else float("nan")
after_dep_text = "— (layers)" if after_dep != after_dep else f"{after_dep:.4f}"  # no bed is only deposited
print(f"| {sys.argv[2]} | {sys.argv[3]} | {after_dep_text} | {dyn['density']['mean']:.4f} ± {dyn['density']['sd']:.4f} "
      f"| {dyn['coordination']['mean']:.2f} | {dyn['ended_by']} | {dyn['simulated_time_s']:.2f} | "
      f"{dyn['final']['mean_overlap_rel']:.1e} / {dyn['final']['max_overlap_rel']:.1e} | {dyn['wall_clock_s']:.1f} |")
PY
}

echo "| run | seed | after deposition | after DEM (mean ± sd over boxes) | coordination | ended by | simulated s | overlap mean / max | DEM wall s |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for seed in 1 2 3; do row "Example 1, Mindlin" example1 $seed; done
row "Example 1, fu2003 law" example1 1 dynamics.friction_model=fu2003
row "Example 1, 4 layers" example1 1 dynamics.layers=4
row "Example 1, E = 30 MPa (E/100)" example1 1 material.youngs_modulus=3e7 material.wall_youngs_modulus=3e7
row "Example 1, e = 0.2" example1 1 material.restitution=0.2
row "Example 1, e = 0.9" example1 1 material.restitution=0.9
for seed in 1 2 3; do row "Example 2, Mindlin" example2 $seed; done
row "Example 2, fu2003 law" example2 1 dynamics.friction_model=fu2003
row "Example 2, 4 layers" example2 1 dynamics.layers=4
row "Example 2, E = 30 MPa (E/100)" example2 1 material.youngs_modulus=3e7 material.wall_youngs_modulus=3e7
