#!/usr/bin/env bash
# Issue 38, speed target 2: the CI cross-check's pour of 300 grains (bench/scenarios/
# grains_pour_300.toml) on one core, aggpack against LAMMPS `fix rigid/small` pouring the same
# gas (the deck `aggpack export-lammps` writes), `rounds` rounds interleaved, both on core 0.
# Prints per round: aggpack's whole run and its DEM (the pour's wall clock in summary.json),
# LAMMPS's whole run and its loop time (the sum of its "Loop time" lines), the steps of each;
# then the ratios of the medians (target: aggpack at least 2 x faster).
# Usage: bench/run_grains_lammps_bench.sh [build-dir] [rounds]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
rounds=${2:-3}
[[ $rounds =~ ^[1-9][0-9]{0,2}$ ]] || { echo "run_grains_lammps_bench: rounds must be a whole number from 1 to 999, got '$rounds'" >&2; exit 2; }
command -v lmp >/dev/null || { echo "run_grains_lammps_bench: LAMMPS (lmp) is not installed: apt-get install lammps" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
scenario=bench/scenarios/grains_pour_300.toml
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(date -u +%Y-%m-%d)"
echo "build: $(git describe --always --dirty), binary $build/aggpack; LAMMPS $(lmp -h | sed -n 's/^Large-scale[^-]*- //p')"
"$build/aggpack" export-lammps "$scenario" --out "$tmp/deck" >/dev/null

seconds_since() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN {printf "%.2f\n", b - a}'; }
median() { printf '%s\n' "$@" | sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

ours=() our_dem=() theirs=() their_loop=()
for round in $(seq "$rounds"); do
  start=$(date +%s.%N)
  OMP_NUM_THREADS=1 taskset -c 0 "$build/aggpack" run "$scenario" --threads 1 --quiet --no-checkpoint --overwrite \
    --out "$tmp/ours" >/dev/null
  ours+=("$(seconds_since "$start")")
  read -r dem steps < <(python3 -c 'import json, sys
d = json.load(open(sys.argv[1]))["stages"]["dynamics"]
print("%.2f %d" % (d["wall_clock_s"], d["steps"]))' "$tmp/ours/summary.json")
  our_dem+=("$dem")
  start=$(date +%s.%N)
  (cd "$tmp/deck" && OMP_NUM_THREADS=1 taskset -c 0 lmp -in pour.in -log lammps.log >/dev/null)
  theirs+=("$(seconds_since "$start")")
  read -r loop their_steps < <(awk '/^Loop time/ {t += $4; n += $9} END {printf "%.2f %d\n", t, n}' "$tmp/deck/lammps.log")
  their_loop+=("$loop")
  echo "round $round: aggpack ${ours[-1]} s (DEM ${dem} s, ${steps} steps), LAMMPS ${theirs[-1]} s (loop ${loop} s, ${their_steps} steps)"
done
a=$(median "${ours[@]}") b=$(median "${theirs[@]}") c=$(median "${our_dem[@]}") d=$(median "${their_loop[@]}")
awk -v a="$a" -v b="$b" -v c="$c" -v d="$d" 'BEGIN {
  printf "medians: whole run aggpack %.2f s, LAMMPS %.2f s: LAMMPS / aggpack = %.2f (target >= 2)\n", a, b, b / a
  printf "         DEM aggpack %.2f s, LAMMPS loop %.2f s: %.2f\n", c, d, d / c }'
