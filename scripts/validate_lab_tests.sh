#!/usr/bin/env bash
# The lab's tests against published packings (issue 56; docs/validation.md, "The lab's tests of
# one aggregate"): aggpack's named default shapes and spheres, uncalibrated.
#   - glass beads 9.5-12.5 mm in C29's 2.8 L measure: shovelled, rodded, and shovelled then
#     tapped (spheres first: loose and tapped monosized beads against the literature);
#   - one size (9.5-12.5 mm) of crushed stone and of gravel, the same in all but the shape,
#     shovelled and rodded: the sign and size of the shape effect and of compaction;
#   - C1252 of glass beads 1.18-2.36 mm in the whole 100 mL cylinder and in representative
#     cylinders (--max-particles 2000 and 8000): the check of the representative cylinder.
# Cost on one core: beads minutes; each stone run tens of minutes shovelled, hours rodded; the
# whole C1252 cylinder about an hour. Usage:
#   bash scripts/validate_lab_tests.sh [OUT_DIR] [CASES]
#   (defaults: out/validate_lab_tests, every case; AGGPACK_EXE: another binary)
# CASES: a space-separated list of the names below. Writes OUT_DIR/results.md: each case's
# packing per seed, mean and sd. Cases already finished are kept.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
out=$(realpath -m "${1:-$repo/out/validate_lab_tests}")
exe=$(realpath -m "${AGGPACK_EXE:-$repo/build/aggpack}")  # AGGPACK_EXE: a copy, to rebuild while it runs
all="beads_shovelling beads_rodding beads_tapped sand_whole sand_representative sand_representative_large crushed_shovelling gravel_shovelling crushed_rodding gravel_rodding"
cases=${2:-$all}
m="$repo/examples/materials"
[ -x "$exe" ] || { echo "validate_lab_tests.sh: no $exe; build first (bash scripts/build.sh)" >&2; exit 2; }
mkdir -p "$out"
export OMP_NUM_THREADS=1

# The tapped beads: the shovelled test's own scenario, then 200 taps of the measure at 2 g
# (the protocol's tap step, the measure and its collar shaken together), struck off as before.
tapped() {
  local seed=$1 dir="$out/beads_tapped/seed$1"
  [ -f "$dir/summary.json" ] && return 0
  mkdir -p "$out/beads_tapped"
  "$exe" test c29 "$m/glass_beads_11mm.toml" --method shovelling --seeds 1 --threads 1 --quiet \
    --out "$out/beads_tapped/scenario" >/dev/null 2>&1 || true
  { cat "$out/beads_tapped/scenario/scenario_1.toml"
    printf '\n[tapping]\ntaps = 200\nintensity = 2.0\nfrequency = 30\n\n[[protocol]]\nstep = "tap"\n'; } \
    > "$out/beads_tapped/tapped.toml"
  "$exe" run "$out/beads_tapped/tapped.toml" --seed "$seed" --threads 1 --quiet --overwrite --out "$dir"
}

run_case() {  # name; a finished case is kept
  local name=$1 dir="$out/$1"
  if [ "$name" = beads_tapped ]; then tapped 1; tapped 2; return; fi
  [ -f "$dir/summary.json" ] && return 0
  case $name in
    beads_shovelling) args=(c29 "$m/glass_beads_11mm.toml" --method shovelling --seeds 3) ;;
    beads_rodding) args=(c29 "$m/glass_beads_11mm.toml" --method rodding --seeds 3) ;;
    sand_whole) args=(c1252 "$m/glass_sand_2mm.toml" --method C --seeds 2) ;;
    sand_representative) args=(c1252 "$m/glass_sand_2mm.toml" --method C --seeds 4 --max-particles 2000) ;;
    sand_representative_large) args=(c1252 "$m/glass_sand_2mm.toml" --method C --seeds 3 --max-particles 8000) ;;
    crushed_shovelling) args=(c29 "$m/crushed_stone_12mm_single.toml" --method shovelling --seeds 2) ;;
    gravel_shovelling) args=(c29 "$m/gravel_12mm_single.toml" --method shovelling --seeds 2) ;;
    crushed_rodding) args=(c29 "$m/crushed_stone_12mm_single.toml" --method rodding --seeds 1) ;;
    gravel_rodding) args=(c29 "$m/gravel_12mm_single.toml" --method rodding --seeds 1) ;;
    *) echo "validate_lab_tests.sh: no case $name (expected: $all)" >&2; exit 2 ;;
  esac
  "$exe" test "${args[@]}" --threads 1 --quiet --out "$dir.part" && rm -rf "$dir" && mv "$dir.part" "$dir"
}

for c in $cases; do run_case "$c"; done

python3 - "$out" $cases <<'EOF'
import json, statistics, sys, pathlib
out = pathlib.Path(sys.argv[1])
rows = ["| case | seeds | packing per seed (the standard measure's) | mean | sd | simulated measure's own | core |",
        "| --- | --- | --- | --- | --- | --- | --- |"]
for name in sys.argv[2:]:
    if name == "beads_tapped":
        runs = [json.loads(p.read_text()) for p in sorted((out / name).glob("seed*/summary.json"))]
        phi = [r["measure"]["packing_density"] for r in runs]
        own = core = "-"
    else:
        p = out / name / "summary.json"
        if not p.exists():
            continue
        part = json.loads(p.read_text())["parts"][0]
        phi = part["packing_density"]
        own = " ".join(f"{x:.4f}" for x in part["packing_density_simulated_measure"])
        core = " ".join(f"{x:.4f}" for x in part["packing_density_core"])
    if not phi:
        continue
    sd = statistics.stdev(phi) if len(phi) > 1 else float("nan")
    rows.append(f"| {name} | {len(phi)} | {' '.join(f'{x:.4f}' for x in phi)} | {statistics.mean(phi):.4f} | {sd:.4f} | {own} | {core} |")
(out / "results.md").write_text("\n".join(rows) + "\n")
print("\n".join(rows))
EOF
