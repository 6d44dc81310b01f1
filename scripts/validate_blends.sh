#!/usr/bin/env bash
# Blends predicted against the DEM of the blend (issue 57; docs/validation.md, "Blends:
# predicted against simulated"): CPM at each material's simulated betas beside the packing of
# the blend itself, poured in a periodic bed by the same procedure, seven fine percents, three
# seeds.
#   - spheres_ratio3: glass beads 9.5-12.5 mm with glass beads 2.36-4.75 mm (size ratio 3.3);
#   - spheres_ratio2: the same beads with 4.75-6.3 mm beads (ratio 2.0): the exponents fitted
#     at ratio 3.3 checked on blends they never saw;
#   - spheres_ratio6: the same beads with 1.18-2.36 mm beads (ratio 6.5);
#   - grains_ratio3: one size of crushed stone (9.5-12.5 mm) with the natural sand cut at
#     2.36 mm (its 2.36-9.5 mm part), both as aggpack's default grains.
# Cost on one core: spheres_ratio3 about an hour, spheres_ratio2 half an hour, spheres_ratio6 and grains_ratio3 hours. Usage:
#   bash scripts/validate_blends.sh [OUT_DIR] [CASES]
#   (defaults: out/validate_blends, every case; AGGPACK_EXE: another binary, e.g. a copy to
#   rebuild while it runs; POINTS=20,40,60 SEEDS=2: a first look at a costly case;
#   CHECK_PARTICLES: coarse particles a blend bed (grains_ratio3, spheres_ratio6); BED_PARTICLES:
#   the grains' betas beds; THREADS: per run). Cases
#   already finished are kept; each writes CASE/blend.json, blend.txt and blend.svg.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
out=$(realpath -m "${1:-$repo/out/validate_blends}")
exe=$(realpath -m "${AGGPACK_EXE:-$repo/build/aggpack}")
all="spheres_ratio3 spheres_ratio2 spheres_ratio6 grains_ratio3"
cases=${2:-$all}
m="$repo/examples/materials"
[ -x "$exe" ] || { echo "validate_blends.sh: no $exe; build first (bash scripts/build.sh)" >&2; exit 2; }
mkdir -p "$out/betas"
export OMP_NUM_THREADS=${THREADS:-1}
points=${POINTS:-20,25,30,35,40,50,60}  # POINTS, SEEDS: fewer, for a first look at a costly case
seeds=${SEEDS:-3}

run_case() {  # name; a finished case is kept
  local name=$1 dir="$out/$1"
  [ -f "$dir/blend.json" ] && return 0
  case $name in
    spheres_ratio3) args=("$m/glass_beads_11mm.toml" "$m/glass_grit_3mm.toml" --check-particles 300 --sweep 10:70:1) ;;
    spheres_ratio2) args=("$m/glass_beads_11mm.toml" "$m/glass_beads_5mm.toml" --check-particles 300 --sweep 10:70:1) ;;
    spheres_ratio6) args=("$m/glass_beads_11mm.toml" "$m/glass_sand_2mm.toml" --check-particles ${CHECK_PARTICLES:-120} --sweep 10:70:1) ;;
    # The check alone (no curve): the curve would need the whole sand's betas, an hour more.
    grains_ratio3) args=("$m/crushed_stone_12mm_single.toml" "$m/natural_sand.toml" --check-cut "2.36 mm"
                         --check-particles ${CHECK_PARTICLES:-150} --bed-particles ${BED_PARTICLES:-1000}) ;;
    *) echo "validate_blends.sh: no case $name (expected: $all)" >&2; exit 2 ;;
  esac
  rm -rf "$dir.part"
  "$exe" blend "${args[@]}" --route simulation --beds c29:shovelling --check "$points" --seeds "$seeds" \
    --threads "${THREADS:-1}" --betas-cache "$out/betas" --out "$dir.part" > "$dir.part.txt" 2> "$dir.part.log" &&
    mv "$dir.part.txt" "$dir.part/blend.txt" && mv "$dir.part.log" "$dir.part/blend.log" &&
    rm -rf "$dir" && mv "$dir.part" "$dir"
}

for c in $cases; do run_case "$c"; done
