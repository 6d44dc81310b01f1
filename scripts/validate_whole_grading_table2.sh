#!/usr/bin/env bash
# Issue 18's Table 2 validation: the whole grading's density of the paper's eight mixes
# (examples/table2_mix*.toml: Table 1 coarse + C33 mid-band sand, drop-and-roll deposition),
# from `aggpack whole-grading` with the sand cut at 0.1, 0.07, 0.04 and 0.02 in (seeds 1-3, one
# thread; two mixes side by side), against the experiments and the paper's computed values
# (examples/fu2003_table2.csv). Prints one Markdown row per mix, in the table's order of Fa.
# About 10 minutes on 2 cores. Usage:
#   bash scripts/validate_whole_grading_table2.sh [OUT_DIR] [extra whole-grading options]
set -euo pipefail
cd "$(dirname "$0")/.."
exe=$PWD/build/aggpack
out=${1:-out/validate_whole_grading}
shift || true
mkdir -p "$out"
export OMP_NUM_THREADS=1
one() {  # mix core
  [ -f "$out/mix$1.json" ] || taskset -c "$2" "$exe" whole-grading "examples/table2_mix$1.toml" \
    --cut-offs 0.1in,0.07in,0.04in,0.02in --seeds 3 --threads 1 --quiet --out "$out/mix$1.json" "${extra[@]}" > /dev/null
}
extra=("$@")
for pair in "1 2" "3 4" "5 6" "7 8"; do
  set -- $pair
  one "$1" 0 & one "$2" 1 & wait
done
python3 - "$out" <<'PY'
import csv, json, sys
out = sys.argv[1]
rows = [r for r in csv.DictReader(l for l in open("examples/fu2003_table2.csv") if not l.startswith("#"))]
rows.sort(key=lambda r: float(r["fa_percent"]))
print("| mix | Fa % | simulated at 0.1 / 0.07 / 0.04 / 0.02 in | CPM whole grading | whole grading (band) | simulated part | experiment | paper | estimate - experiment |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for r in rows:
    e = json.load(open(f"{out}/mix{r['mix_id']}.json"))
    w = e["whole_grading"]
    sims = " / ".join(f"{p['mean']:.4f}" for p in e["cut_offs"])
    flag = "" if w["trustworthy"] else " (not trustworthy)"
    print(f"| {r['mix_id']} | {r['fa_percent']} | {sims} | {w['cpm']:.4f} | {w['density']:.4f} ({w['band'][0]:.4f}-"
          f"{w['band'][1]:.4f}){flag} | {100 * w['simulated_volume_fraction']:.1f} % | {r['phi_exp']} | "
          f"{r['phi_com_mean']} | {w['density'] - float(r['phi_exp']):+.4f} |")
PY
