#!/usr/bin/env bash
# Issue 17's contact question: does LAMMPS's `compute contact/atom` count the contacts of a bed
# as aggpack does? For each finished run folder given: `aggpack export-lammps RUN_DIR` (its
# final bed, 17 digits), LAMMPS reads it with the same pair style and writes `compute
# contact/atom` per sphere after `run 0`; a brute-force count over all pairs (Python) and aggpack's
# own analysis (`analyze --tolerance 1e-12`, the spheres in the largest box) count the same bed.
# Prints one Markdown row per run. Usage:
#   bash scripts/validate_lammps_contacts.sh OUT_DIR RUN_DIR...
set -euo pipefail
cd "$(dirname "$0")/.."
exe=$PWD/build/aggpack
out=$1
shift
mkdir -p "$out"
echo "| run | spheres | brute force: mean, rattlers | LAMMPS contact/atom: mean, rattlers | in the largest box: aggpack analyze / brute force / LAMMPS |"
echo "| --- | --- | --- | --- | --- |"
for run in "$@"; do
  name=$(basename "$run")
  dir="$out/$name"
  rm -rf "$dir"
  "$exe" export-lammps "$run" --out "$dir" > /dev/null
  {
    sed -n '/^units/,/^pair_coeff/p' "$dir/settle.in"
    grep '^neighbor' "$dir/settle.in"
    echo "compute contacts all contact/atom"
    echo "dump counts all custom 1 contacts.dump id c_contacts"
    echo "dump_modify counts sort id"
    echo "run 0"
  } > "$dir/contacts.in"
  (cd "$dir" && lmp -in contacts.in -log lammps.log > /dev/null)
  python3 - "$run" "$dir" "$exe" "$name" <<'PY'
import csv, json, math, subprocess, sys
from collections import defaultdict
run, folder, exe, name = sys.argv[1:]
rows = list(csv.DictReader(open(f"{run}/particles.csv")))
p = [(float(r["x"]), float(r["y"]), float(r["z"])) for r in rows]
r = [float(r["r"]) for r in rows]
n = len(r)
# Every pair once, through cells of the largest diameter: centre distance below the sum of the radii.
cell = 2 * max(r)
cells = defaultdict(list)
for i, c in enumerate(p):
    cells[tuple(int(math.floor(v / cell)) for v in c)].append(i)
brute = [0] * n
for (cx, cy, cz), members in cells.items():
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            for dz in (-1, 0, 1):
                for j in cells.get((cx + dx, cy + dy, cz + dz), ()):
                    for i in members:
                        if i < j and math.dist(p[i], p[j]) < r[i] + r[j]:
                            brute[i] += 1
                            brute[j] += 1
lines = open(f"{folder}/contacts.dump").read().split("ITEM: ATOMS")[1].split("\n")[1:]
lmp = [0] * n
for line in lines:
    if line.strip():
        k, c = line.split()
        lmp[int(k) - 1] = int(float(c))
summary = json.load(open(f"{run}/summary.json"))
box = summary["density"]["boxes"][-1]
lo, hi = box["lo"], box["hi"]
inside = [i for i in range(n) if all(lo[a] <= p[i][a] <= hi[a] for a in range(3))]
analysed = json.loads(subprocess.run(
    [exe, "analyze", f"{run}/particles.csv", "--box", ",".join(f"{v:.17g}" for v in [*lo, *hi]), "--tolerance",
     "1e-12", "--json"], check=True, capture_output=True, text=True).stdout)
agg = analysed["coordination"]["mean"]
mean = lambda v, idx=range(n): sum(v[i] for i in idx) / len(idx)
rattlers = lambda v: 100.0 * sum(1 for x in v if x == 0) / n
print(f"| {name} | {n} | {mean(brute):.3f}, {rattlers(brute):.1f} % | {mean(lmp):.3f}, {rattlers(lmp):.1f} % | "
      f"{agg:.3f} / {mean(brute, inside):.3f} / {mean(lmp, inside):.3f} |")
differ = [i for i in range(n) if brute[i] != lmp[i]]
if differ:
    i = differ[0]
    print(f"  {len(differ)} spheres differ, for example id {i + 1}: brute force {brute[i]}, LAMMPS {lmp[i]}")
PY
done
