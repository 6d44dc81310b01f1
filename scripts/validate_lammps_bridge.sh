#!/usr/bin/env bash
# Issue 17's validation: aggpack's DEM and LAMMPS settling the same deposited beds of the
# paper's Examples 1 and 2, seeds 1-3. For each: `aggpack export-lammps` (the deposited bed and
# the deck), LAMMPS on one rank and on two, `aggpack import-lammps`, and `aggpack run` (aggpack's
# own DEM from the same bed), each on one core. Prints one Markdown row per bed:
# seed, densities, their difference, coordination, wall times. Usage:
#   bash scripts/validate_lammps_bridge.sh [OUT_DIR]    (default out/validate_lammps)
set -euo pipefail
cd "$(dirname "$0")/.."
exe=build/aggpack
out=${1:-out/validate_lammps}
mkdir -p "$out"
export OMP_NUM_THREADS=1
field() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }
echo "| example | seed | aggpack DEM | LAMMPS 1 rank | LAMMPS 2 ranks | LAMMPS - aggpack | coordination aggpack / LAMMPS | wall s aggpack / LAMMPS 1 / LAMMPS 2 |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
for example in example1 example2; do
  for seed in 1 2 3; do
    dir="$out/${example}_seed$seed"
    rm -rf "$dir"
    "$exe" export-lammps "examples/$example.toml" --set "seed=$seed" --out "$dir/lammps" > /dev/null
    cp -r "$dir/lammps" "$dir/lammps_2"
    t0=$(date +%s.%N)
    (cd "$dir/lammps" && taskset -c 0 lmp -in settle.in -log lammps.log > /dev/null)
    t1=$(date +%s.%N)
    (cd "$dir/lammps_2" && mpirun --allow-run-as-root -np 2 lmp -in settle.in -log lammps.log > /dev/null)
    t2=$(date +%s.%N)
    "$exe" import-lammps "$dir/lammps/settled.dump" --scenario "examples/$example.toml" --set "seed=$seed" \
      --quiet --out "$dir/imported_1"
    "$exe" import-lammps "$dir/lammps_2/settled.dump" --scenario "examples/$example.toml" --set "seed=$seed" \
      --quiet --out "$dir/imported_2"
    taskset -c 0 "$exe" run "examples/$example.toml" --seed "$seed" --threads 1 --quiet --no-checkpoint \
      --out "$dir/aggpack"
    a=$(field "$dir/aggpack/summary.json" "d['density']['mean']")
    l1=$(field "$dir/imported_1/summary.json" "d['density']['mean']")
    l2=$(field "$dir/imported_2/summary.json" "d['density']['mean']")
    ca=$(field "$dir/aggpack/summary.json" "d['coordination']['mean']")
    cl=$(field "$dir/imported_1/summary.json" "d['coordination']['mean']")
    wa=$(field "$dir/aggpack/summary.json" "d['stages']['dynamics']['wall_clock_s']")
    python3 -c "
import sys
a,l1,l2,ca,cl,wa,t0,t1,t2=map(float,sys.argv[3:])
print(f'| {sys.argv[1]} | {sys.argv[2]} | {a:.4f} | {l1:.4f} | {l2:.4f} | {l1-a:+.4f} | {ca:.2f} / {cl:.2f} | {wa:.1f} / {t1-t0:.1f} / {t2-t1:.1f} |')
" "$example" "$seed" "$a" "$l1" "$l2" "$ca" "$cl" "$wa" "$t0" "$t1" "$t2"
  done
done
