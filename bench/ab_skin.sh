#!/usr/bin/env bash
# The Verlet skin on a Table 2 bed (issue 37, target 1), side by side in one run: mix 3 on
# Table 2's DEM protocol bed (periodic sides 4 in apart, E/1000, seed 1), deposited, then
# settled for the first `max_time` seconds with the default skin (0.1 of the smallest
# diameter) and with the protocol's 0.008 in (0.2 of it). The two runs go at once, each on one
# thread and one core, the cores swapped between rounds; prints each run's DEM wall time, its
# steps and its neighbour-list builds, and the ratio of the DEM wall times.
# Usage: bench/ab_skin.sh [build-dir] [mix] [max_time s] [rounds]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
mix=${2:-3}
max_time=${3:-0.03}
rounds=${4:-2}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(date -u +%Y-%m-%d)"
echo "build: $(git describe --always --dirty), binary $build/aggpack, mix $mix, DEM to $max_time s simulated"
protocol=(--set 'output.formats=[]' --set 'container.sides="periodic"' --set 'container.side="4 in"'
  --set material.youngs_modulus=5e7 --set material.wall_youngs_modulus=5e7
  --set 'dynamics.friction_model="mindlin"' --set "dynamics.max_time=$max_time")
run_on() {  # core skin-label out [more --set]
  local core=$1 label=$2 out=$3
  shift 3
  taskset -c "$core" "$build/aggpack" run "examples/table2_mix$mix.toml" --seed 1 --threads 1 --quiet \
    --no-checkpoint --overwrite --out "$out" "${protocol[@]}" "$@" >/dev/null
  python3 -c "
import json
d = json.load(open('$out/summary.json'))['stages']['dynamics']
print(f\"$label core $core: DEM {d['wall_clock_s']:.1f} s, {d['steps']} steps, {d['neighbour_list_builds']} list builds, \"
      f\"skin {d['skin_m'] * 1e3:.4f} mm, {d['particle_steps_per_second'] / 1e6:.2f} M particle-steps/s\")"
}
for round in $(seq 1 "$rounds"); do
  a=$(( (round + 1) % 2 )) b=$(( round % 2 ))
  run_on "$a" "skin 0.1 d_min" "$tmp/default_$round" &
  run_on "$b" "skin 0.2 d_min" "$tmp/wide_$round" --set 'dynamics.skin="0.008 in"' &
  wait
  python3 -c "
import json
t = [json.load(open(f'$tmp/{k}_$round/summary.json'))['stages']['dynamics']['wall_clock_s'] for k in ('default', 'wide')]
print(f'round $round: skin 0.1 / skin 0.2 DEM wall time = {t[0] / t[1]:.2f}')"
done
