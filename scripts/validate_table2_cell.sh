#!/usr/bin/env bash
# What does Table 2's DEM protocol lose by its smaller bed? (docs/validation.md, issue 37.)
# Deposits Table 2 mixes (3, 1, 4 and 8 unless given) over seeds 1-4 in the shipped 5 in
# container with walls, with periodic sides 5 in apart, and with periodic sides 4 in apart (the
# protocol's bed: drop-and-roll needs more than four of the largest diameters, 1 in), and prints
# each mix's mean and sd over the seeds, then the differences averaged over the mixes.
# Deposition only (seconds a bed): the settled beds are compared in docs/validation.md.
# Usage: scripts/validate_table2_cell.sh [build-dir] [mix ...]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
shift || true
if [ $# -gt 0 ]; then mixes=("$@"); else mixes=(3 1 4 8); fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

echo "mix,bed,seed,particles,density" >"$out/beds.csv"
for mix in "${mixes[@]}"; do
  for bed in walls_5in periodic_5in periodic_4in; do
    case $bed in
      walls_5in) sets=() ;;
      periodic_5in) sets=(--set 'container.sides="periodic"') ;;
      periodic_4in) sets=(--set 'container.sides="periodic"' --set 'container.side="4 in"') ;;
    esac
    for seed in 1 2 3 4; do
      "$build/aggpack" run "examples/table2_mix$mix.toml" --quiet --threads 1 --seed "$seed" --out "$out/run" \
        --set 'output.formats=[]' "${sets[@]}"
      python3 -c "
import json, sys
s = json.load(open('$out/run/summary.json'))
print(f\"$mix,$bed,$seed,{s['particle_count']},{s['density']['mean']:.5f}\")" >>"$out/beds.csv"
    done
  done
done
python3 - "$out/beds.csv" <<'PY'
import csv, statistics, sys
from collections import defaultdict
density, count = defaultdict(list), defaultdict(list)
for row in csv.DictReader(open(sys.argv[1])):
    density[row["mix"], row["bed"]].append(float(row["density"]))
    count[row["mix"], row["bed"]].append(int(row["particles"]))
beds = ["walls_5in", "periodic_5in", "periodic_4in"]
mixes = list(dict.fromkeys(m for m, _ in density))
print("| mix | " + " | ".join(f"{b}: mean ± sd over seeds (particles)" for b in beds) + " | periodic 4 in − walls 5 in |")
print("| --- " * (len(beds) + 2) + "|")
for m in mixes:
    cells = [f"{statistics.mean(density[m, b]):.4f} ± {statistics.stdev(density[m, b]):.4f} "
             f"({statistics.mean(count[m, b]):.0f})" for b in beds]
    gap = statistics.mean(density[m, "periodic_4in"]) - statistics.mean(density[m, "walls_5in"])
    print(f"| {m} | " + " | ".join(cells) + f" | {gap:+.4f} |")
for a, b in [("periodic_5in", "walls_5in"), ("periodic_4in", "periodic_5in"), ("periodic_4in", "walls_5in")]:
    gaps = [statistics.mean(density[m, a]) - statistics.mean(density[m, b]) for m in mixes]
    print(f"{a} − {b}, mean over the mixes: {statistics.mean(gaps):+.4f}")
for b in beds:
    pooled = (sum(statistics.variance(density[m, b]) for m in mixes) / len(mixes)) ** 0.5
    print(f"{b}: sd between seeds, pooled over the mixes: {pooled:.4f}")
PY
