#!/usr/bin/env bash
# DEM speed and memory against the peer codes, in one run on one machine (BENCHMARKS.md).
#  1. Beds at rest (1 in spheres, E = 3 GPa, e = 0.5, mu = 0.17, dt = 1e-5 s, periodic sides,
#     a floor), settled until quiet once and kept in bench/.cache: aggpack on one core and,
#     at 10^5, on two; on the very same bed file, on one core, each peer that is installed:
#     LAMMPS `pair_style granular` (the same law), LAMMPS `gran/hertz/history` (its classic
#     kernel) and LIGGGHTS. `rounds` rounds, interleaved; the ratio is aggpack's best over
#     the fastest peer's best. Beside the two-thread run, bench_core_scaling: what a second
#     thread adds to loops that share nothing, this machine's ceiling for that ratio.
#  2. Example 1 and Example 2 from scenario to settled bed (aggpack: deposition + DEM) against
#     LAMMPS pouring and settling the same spheres (bench/lammps/example{1,2}_pour.in).
# Usage: bench/run_dynamics_bench.sh [build-dir] [steps] [rounds] [counts...]
#        (EXAMPLES=no leaves out part 2)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
steps=${2:-1000}
rounds=${3:-3}
shift $(( $# < 3 ? $# : 3 ))
counts=("$@")
[[ ${#counts[@]} -gt 0 ]] || counts=(20000 100000)
warmup=500
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p bench/.cache
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(date -u +%Y-%m-%d)"

peers=()
command -v lmp >/dev/null && peers+=(lammps_granular lammps_hertz_history)
command -v liggghts >/dev/null && peers+=(liggghts)
echo "peers: ${peers[*]:-none installed}"

# peer bed -> "particle-steps-per-second peak-RSS-bytes-per-sphere" on one core (the timed
# run after the warm-up; the peak RSS of the whole process, as bench_dynamics reports its own)
peer_rate() {
  local deck exe=lmp
  case $1 in
    lammps_granular) deck=bed_at_rest.in ;;
    lammps_hertz_history) deck=bed_at_rest_hertz_history.in ;;
    liggghts) deck=bed_at_rest_liggghts.in exe=liggghts ;;
  esac
  (cd "$tmp" && OMP_NUM_THREADS=1 taskset -c 0 python3 -c '
import resource, subprocess, sys
out = subprocess.run(sys.argv[1:], capture_output=True, text=True, check=True).stdout
rate = [l.split() for l in out.splitlines() if l.startswith("Loop time of")][-1]
print(f"{float(rate[11]) * float(rate[8]) / float(rate[3]):.4g}",
      f"{1024 * resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / float(rate[11]):.0f}")
' "$exe" -in "$OLDPWD/bench/lammps/$deck" -var data "$2" -var steps "$steps" -var warmup "$warmup" \
      -var bench_dir "$OLDPWD/bench/lammps" -log none)
}
ours_rate() {  # threads bed count -> JSON line
  OMP_NUM_THREADS=$1 taskset -c "$( [[ $1 == 1 ]] && echo 0 || echo 0-$(( $1 - 1 )) )" \
    "$build/bench/bench_dynamics" "$3" "$steps" --bed "$2" --warmup "$warmup"
}
field() { python3 -c 'import json,sys; print(json.loads(sys.argv[1])[sys.argv[2]])' "$1" "$2"; }
best() { printf '%s\n' "$@" | sort -g | tail -1; }

for count in "${counts[@]}"; do
  bed="$PWD/bench/.cache/bed_$count.data"
  if [[ ! -f $bed ]]; then
    echo "settling the bed of $count spheres until quiet (once; kept in $bed) ..."
    OMP_NUM_THREADS=$(nproc) "$build/bench/bench_dynamics" "$count" 10 --bed "$bed" --warmup 0 >/dev/null
  fi
  declare -A rates=()
  one_thread=() two_threads=() ceiling=()
  for round in $(seq "$rounds"); do
    line=$(ours_rate 1 "$bed" "$count")
    echo "round $round aggpack 1 thread:  $line"
    one_thread+=("$(field "$line" particle_steps_per_second)")
    if [[ $count -ge 100000 && $(nproc) -ge 2 ]]; then
      line=$(ours_rate 2 "$bed" "$count")
      echo "round $round aggpack 2 threads: $line"
      two_threads+=("$(field "$line" particle_steps_per_second)")
      # What a second thread can add on this machine right now, with nothing shared: the
      # ceiling for the ratio above (a VM's second vCPU may not be a whole core).
      while read -r line; do
        echo "round $round machine, two threads / one: $line"
        ceiling+=("$(field "$line" two_over_one)")
      done < <(taskset -c 0-1 "$build/bench/bench_core_scaling" 1)
    fi
    for peer in "${peers[@]}"; do
      read -r rate rss <<< "$(peer_rate "$peer" "$bed")"
      echo "round $round $peer: $rate particle-steps/s, peak RSS $rss B/sphere"
      rates[$peer]="${rates[$peer]:-} $rate"
    done
  done
  ours=$(best "${one_thread[@]}")
  summary="$count spheres at rest, million particle-steps/s on one core (best of $rounds): aggpack $(python3 -c "print(f'{$ours/1e6:.2f}')")"
  fastest=0 fastest_name=""
  for peer in "${peers[@]}"; do
    # shellcheck disable=SC2086
    b=$(best ${rates[$peer]})
    summary+=", $peer $(python3 -c "print(f'{$b/1e6:.2f}')")"
    if python3 -c "import sys; sys.exit(0 if $b > $fastest else 1)"; then fastest=$b fastest_name=$peer; fi
  done
  echo "$summary"
  if [[ -n $fastest_name ]]; then
    echo "$count spheres: aggpack / fastest peer ($fastest_name) = $(python3 -c "print(f'{$ours/$fastest:.2f}')")"
  fi
  if [[ ${#two_threads[@]} -gt 0 ]]; then
    echo "$count spheres: two threads / one thread = $(python3 -c "print(f'{$(best "${two_threads[@]}")/$ours:.2f}')")"
    echo "the machine's own two / one over the rounds (throughput, latency, memory, in turn): ${ceiling[*]}"
  fi
  unset rates
done

# Scenario to settled bed on one core, against LAMMPS pouring and settling the same spheres.
[[ ${EXAMPLES:-yes} == no ]] && exit 0
for example in 1 2; do
  start=$(date +%s.%N)
  OMP_NUM_THREADS=1 taskset -c 0 "$build/aggpack" run "examples/example$example.toml" --quiet --threads 1 \
    --out "$tmp/ex$example"
  ours=$(echo "$(date +%s.%N) - $start" | bc)
  simulated=$(python3 -c 'import json,sys; d=json.load(open(sys.argv[1]))["stages"]["dynamics"]; print(sum(r["simulated_time_s"] for r in d["runs"]))' "$tmp/ex$example/summary.json")
  echo "Example $example, scenario to settled bed, aggpack one core: ${ours} s (${simulated} s simulated)"
  # LAMMPS pours from a loose gas: 1 s (Example 1) and 2 s (Example 2, a taller gas)
  # simulated let it fall and come to rest; the decks say how the times were chosen.
  lammps_time=$(( example == 1 ? 1 : 2 )).0
  if command -v lmp >/dev/null; then
    start=$(date +%s.%N)
    (cd "$tmp" && OMP_NUM_THREADS=1 taskset -c 0 lmp -in "$OLDPWD/bench/lammps/example${example}_pour.in" \
       -var time "$lammps_time" -log none >/dev/null)
    theirs=$(echo "$(date +%s.%N) - $start" | bc)
    echo "Example $example, pour and settle ${lammps_time} s, LAMMPS one core: ${theirs} s; aggpack / LAMMPS = $(echo "scale=3; $ours / $theirs" | bc)"
  fi
done
