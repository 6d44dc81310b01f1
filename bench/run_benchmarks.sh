#!/usr/bin/env bash
# Builds and runs the benchmarks on one core; results go to BENCHMARKS.md by hand, with this command line.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
taskset -c 0 ./build/bench/bench_sphere_box_volume --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
