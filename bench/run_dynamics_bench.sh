#!/usr/bin/env bash
# DEM speed and memory against LAMMPS, in one run on one machine (BENCHMARKS.md).
#  1. Beds at rest (1 in spheres, E = 3 GPa, e = 0.5, mu = 0.17, dt = 1e-5 s, periodic sides,
#     a floor): aggpack on one core and, at 10^5, on two; LAMMPS (Debian `lammps`, pair_style
#     granular, the same law) on one core on the very same bed, when `lmp` is installed.
#  2. Example 1 from scenario to settled bed (aggpack: deposition + DEM) against LAMMPS
#     pouring and settling the same spheres (bench/lammps/example1_pour.in, 1 s simulated).
# Usage: bench/run_dynamics_bench.sh [build-dir] [steps]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
steps=${2:-1000}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
have_lammps=false
command -v lmp >/dev/null && have_lammps=true
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(date -u +%Y-%m-%d)"

lammps_rate() {  # data steps -> particle-steps per second on one core
  local out
  out=$(OMP_NUM_THREADS=1 taskset -c 0 lmp -in bench/lammps/bed_at_rest.in -var data "$1" -var steps "$2" -log none)
  echo "$out" | awk '/^Loop time of/ {printf "%.4g", $9 * $12 / $4}'
}

for count in 20000 100000; do
  one=$(OMP_NUM_THREADS=1 taskset -c 0 "$build/bench/bench_dynamics" "$count" "$steps" --lammps-data "$tmp/bed.data")
  echo "aggpack 1 thread:  $one"
  ours=$(echo "$one" | python3 -c 'import json,sys; print(json.load(sys.stdin)["particle_steps_per_second"])')
  if [[ $count == 100000 ]]; then
    two=$(OMP_NUM_THREADS=2 "$build/bench/bench_dynamics" "$count" "$steps")
    echo "aggpack 2 threads: $two"
    python3 -c 'import json,sys; k="particle_steps_per_second"; a,b=(json.loads(x)[k] for x in sys.argv[1:3]); print(f"two threads / one thread: {b/a:.2f}")' "$one" "$two"
  fi
  if $have_lammps; then
    theirs=$(lammps_rate "$tmp/bed.data" "$steps")
    python3 -c "import sys; o,t=float(sys.argv[1]),float(sys.argv[2]); print(f'{sys.argv[3]} spheres at rest: aggpack {o/1e6:.2f}, LAMMPS granular {t/1e6:.2f} million particle-steps/s; ratio {o/t:.2f}')" "$ours" "$theirs" "$count"
  fi
done

start=$(date +%s.%N)
OMP_NUM_THREADS=1 taskset -c 0 "$build/aggpack" run examples/example1.toml --quiet --threads 1 --out "$tmp/ex1"
ours=$(echo "$(date +%s.%N) - $start" | bc)
echo "Example 1, scenario to settled bed, aggpack one core: ${ours} s"
if $have_lammps; then
  start=$(date +%s.%N)
  (cd "$tmp" && OMP_NUM_THREADS=1 taskset -c 0 lmp -in "$OLDPWD/bench/lammps/example1_pour.in" -var time 1.0 -log none >/dev/null)
  theirs=$(echo "$(date +%s.%N) - $start" | bc)
  echo "Example 1, pour and settle 1 s, LAMMPS one core: ${theirs} s; aggpack / LAMMPS = $(echo "scale=3; $ours / $theirs" | bc)"
fi
