#!/usr/bin/env bash
# Speed under load (issue 37, target 5), in one run on one machine (BENCHMARKS.md): one
# scenario run with --threads 1 and --threads 2
#   - alone on the machine;
#   - beside a CPU-bound process pinned to core 1 (a busy loop: a build, a browser, a sweep);
#   - two runs with --threads 2 side by side, against one alone.
# The targets: beside the busy loop, --threads 2 is never slower than --threads 1; two runs
# side by side finish within 2.2 x one alone. Each case `rounds` times, interleaved; the
# wall time of each `aggpack run` (scenario to outputs) is printed, and the median.
# Usage: bench/run_load_bench.sh [build-dir] [scenario] [rounds] [extra aggpack arguments...]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
scenario=${2:-examples/example1_pour.toml}
rounds=${3:-3}
shift $(( $# < 3 ? $# : 3 ))
extra=("$@")
tmp=$(mktemp -d)
busy_pid=
cleanup() {
  [[ -n $busy_pid ]] && { kill "$busy_pid" 2>/dev/null || true; }
  rm -rf "$tmp"
}
trap cleanup EXIT
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(date -u +%Y-%m-%d)"
echo "build: $(git describe --always --dirty), binary $build/aggpack, scenario: $scenario ${extra[*]}"
echo "OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-unset}"

run_once() {  # threads out -> wall seconds
  local start end
  start=$(date +%s.%N)
  "$build/aggpack" run "$scenario" --threads "$1" --quiet --no-checkpoint --overwrite --out "$2" "${extra[@]}" >/dev/null
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN {printf "%.2f\n", b - a}'
}
busy_start() {
  taskset -c 1 bash -c 'while :; do :; done' &
  busy_pid=$!
  sleep 0.5
}
busy_stop() {
  kill "$busy_pid"
  wait "$busy_pid" 2>/dev/null || true
  busy_pid=
}
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }

declare -A times
run_both() {  # key description: the run with --threads 1, then 2, timed into times[key1], times[key2]
  local threads t
  for threads in 1 2; do
    t=$(run_once "$threads" "$tmp/$1$threads")
    times[$1$threads]+="$t "
    echo "round $r: $2, --threads $threads: $t s"
  done
}
for ((r = 1; r <= rounds; ++r)); do
  run_both alone "alone"
  busy_start
  run_both busy "beside a busy loop on core 1"
  busy_stop
  start=$(date +%s.%N)
  run_once 2 "$tmp/pairA" >"$tmp/pairA.s" &
  pair_pid=$!
  run_once 2 "$tmp/pairB" >"$tmp/pairB.s"
  wait "$pair_pid"
  end=$(date +%s.%N)
  t=$(awk -v a="$start" -v b="$end" 'BEGIN {printf "%.2f\n", b - a}')
  times[pair]+="$t "
  echo "round $r: two runs with --threads 2 side by side: $(cat "$tmp/pairA.s") s and $(cat "$tmp/pairB.s") s, both done after $t s"
done

echo
for key in alone1 alone2 busy1 busy2 pair; do
  m=$(tr ' ' '\n' <<<"${times[$key]}" | grep . | median)
  echo "median $key: $m s (${times[$key]% })"
  declare "med_$key=$m"
done
ratio() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.2f\n", a / b}'; }
echo "speed-up alone, one thread's time / two threads': $(ratio "$med_alone1" "$med_alone2")"
echo "beside a busy loop, --threads 2 / --threads 1 (target <= 1): $(ratio "$med_busy2" "$med_busy1")"
echo "two side by side / one alone, --threads 2 (target <= 2.2): $(ratio "$med_pair" "$med_alone2")"
