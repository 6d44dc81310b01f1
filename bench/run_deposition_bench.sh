#!/usr/bin/env bash
# Drop-and-roll speed and memory targets (issue 3), one bed per process, pinned to one core.
# Prints one JSON line per bed; copy the numbers into BENCHMARKS.md with this command line.
#   bash bench/run_deposition_bench.sh          # 10^4 and 10^6 monosized, 10^6 with a 1:20 range
#   bash bench/run_deposition_bench.sh --huge   # also a 10^7 monosized bed (about a minute, 1.3 GB)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh >/dev/null
bench=./build/bench/bench_deposition
for seed in 1 2 3; do
  taskset -c 0 "$bench" 1e4 mono "$seed"
done
taskset -c 0 "$bench" 1e6 mono 1
taskset -c 0 "$bench" 1e6 range20 1
if [[ "${1:-}" == "--huge" ]]; then
  taskset -c 0 "$bench" 1e7 mono 1
fi
