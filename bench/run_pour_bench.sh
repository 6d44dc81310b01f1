#!/usr/bin/env bash
# Examples 1 and 2 poured (issue 37, target 4: scenario to quiet bed on one core, at most a
# quarter of LAMMPS pouring the same spheres), in one run on one machine (BENCHMARKS.md):
# aggpack `run examples/example{1,2}_pour.toml` (a random gas at 0.2, falling through the DEM
# until quiet) against LAMMPS `bench/lammps/example{1,2}_pour.in` (a jittered lattice gas,
# 1 s and 2 s simulated), both on core 0, `rounds` rounds interleaved; prints each wall time,
# what aggpack simulated, and the ratio of the medians.
# Usage: bench/run_pour_bench.sh [build-dir] [rounds]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
rounds=${2:-2}
[[ $rounds =~ ^[1-9][0-9]{0,2}$ ]] || { echo "run_pour_bench: rounds must be a whole number from 1 to 999, got '$rounds'" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
command -v lmp >/dev/null || { echo "run_pour_bench: LAMMPS (lmp) is not installed: apt-get install lammps" >&2; exit 2; }
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(date -u +%Y-%m-%d)"
echo "build: $(git describe --always --dirty), binary $build/aggpack"

seconds_since() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN {printf "%.2f\n", b - a}'; }
median() { printf '%s\n' "$@" | sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

for example in 1 2; do
  lammps_time=$(( example == 1 ? 1 : 2 )).0
  ours=() theirs=()
  for round in $(seq "$rounds"); do
    start=$(date +%s.%N)
    OMP_NUM_THREADS=1 taskset -c 0 "$build/aggpack" run "examples/example${example}_pour.toml" --threads 1 --quiet \
      --no-checkpoint --overwrite --out "$tmp/ex$example" >/dev/null
    ours+=("$(seconds_since "$start")")
    simulated=$(python3 -c 'import json, sys
print("%.3f" % json.load(open(sys.argv[1]))["stages"]["dynamics"]["simulated_time_s"])' "$tmp/ex$example/summary.json")
    start=$(date +%s.%N)
    (cd "$tmp" && OMP_NUM_THREADS=1 taskset -c 0 lmp -in "$OLDPWD/bench/lammps/example${example}_pour.in" \
       -var time "$lammps_time" -log none >/dev/null)
    theirs+=("$(seconds_since "$start")")
    echo "round $round, Example $example poured: aggpack ${ours[-1]} s (${simulated} s simulated until quiet)," \
         "LAMMPS ${theirs[-1]} s (${lammps_time} s simulated)"
  done
  a=$(median "${ours[@]}") b=$(median "${theirs[@]}")
  echo "Example $example poured, medians: aggpack $a s, LAMMPS $b s, aggpack / LAMMPS = $(awk -v a="$a" -v b="$b" 'BEGIN {printf "%.2f", a / b}') (target <= 0.25)"
done
