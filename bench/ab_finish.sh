#!/usr/bin/env bash
# Two aggpack builds that give the same bits, compared on a real bed by the time each takes to
# run a copy of one checkpoint to its end, in the order A B B A (BENCHMARKS.md, "Table 2
# beds"). Finer than bench/ab_resume.sh, whose resolution is one checkpoint sample; the last
# line of each run's log shows that both ended on the same bed.
# Usage: bench/ab_finish.sh CHECKPOINT_DIR BINARY_A BINARY_B [threads]
set -euo pipefail
[[ $# -ge 3 ]] || { echo "usage: $0 CHECKPOINT_DIR BINARY_A BINARY_B [threads]" >&2; exit 2; }
checkpoint=$1/checkpoint.bin
threads=${4:-2}
[[ -f $checkpoint ]] || { echo "$0: no checkpoint.bin in $1" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(date -u +%Y-%m-%d)"
for b in "$2" "$3" "$3" "$2"; do
  dir=$tmp/run; rm -rf "$dir"; mkdir "$dir"; cp "$checkpoint" "$dir/"
  start=$(date +%s.%N)
  "$b" resume "$dir" --threads "$threads" > "$tmp/log" 2>&1
  seconds=$(echo "$(date +%s.%N) - $start" | bc)
  echo "$b: ${seconds} s; $(grep -E 'after dynamics' "$tmp/log" | sed 's/^ *//')"
done
