#!/usr/bin/env bash
# Two aggpack builds that give the same bits, compared on a real bed: each resumes copies of one
# checkpoint for the same wall time, alternating, and the simulated time it reached is printed
# (BENCHMARKS.md, "Table 2 beds"). The resolution is the checkpoint cadence (an interrupted
# run stops at its next sample), so use several rounds and a long enough window.
# Usage: bench/ab_resume.sh CHECKPOINT_DIR BINARY_A BINARY_B [seconds] [rounds] [threads]
set -euo pipefail
[[ $# -ge 3 ]] || { echo "usage: $0 CHECKPOINT_DIR BINARY_A BINARY_B [seconds] [rounds] [threads]" >&2; exit 2; }
checkpoint=$1/checkpoint.bin
binaries=("$2" "$3")
seconds=${4:-120}
rounds=${5:-2}
threads=${6:-2}
[[ -f $checkpoint ]] || { echo "$0: no checkpoint.bin in $1" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(date -u +%Y-%m-%d)"
echo "round policy binary reached"
for round in $(seq "$rounds"); do
  for policy in ACTIVE PASSIVE; do
    for b in "${binaries[@]}"; do
      dir=$tmp/run; rm -rf "$dir"; mkdir "$dir"; cp "$checkpoint" "$dir/"
      OMP_WAIT_POLICY=$policy timeout -s INT "$seconds" "$b" resume "$dir" --threads "$threads" \
        > "$tmp/log" 2>&1 || true
      # the last "while settling at T s" is where the interrupted run stopped (the first, where it resumed)
      reached=$(grep -o 'while settling at [0-9][0-9.]* s' "$tmp/log" | tail -1 | grep -o '[0-9][0-9.]* s' || true)
      reached=${reached:-?}
      echo "$round $policy $b $reached"
    done
  done
done
