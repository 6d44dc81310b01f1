#!/usr/bin/env bash
# Issue 18's densest-blend validation: `aggpack sweep --cut-offs` on Table 2 mix 3's gradings
# (Table 1 coarse + C33 mid-band sand, drop-and-roll deposition), Fa = 25..45 %, the sand cut at
# 0.1, 0.07, 0.04 and 0.02 in, seeds 1-3: the densest blend at the finest simulated cut-off against the
# densest whole grading. Prints one Markdown row per blend and the two answers. About 10
# minutes on one core. Usage:
#   bash scripts/validate_sweep_whole_grading.sh [OUT_DIR] [extra sweep options]
set -euo pipefail
cd "$(dirname "$0")/.."
exe=$PWD/build/aggpack
out=${1:-out/validate_sweep_whole_grading}
shift || true
[ -f "$out/sweep.json" ] || OMP_NUM_THREADS=1 "$exe" sweep examples/table2_mix3.toml --fa 25:45:5 \
  --cut-offs 0.1in,0.07in,0.04in,0.02in --seeds 3 --threads 1 --quiet --out "$out" "$@"
python3 - "$out/sweep.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
print("| Fa % | simulated at 0.1 / 0.07 / 0.04 / 0.02 in | CPM whole grading | whole grading (band) |")
print("| --- | --- | --- | --- |")
for p in j["points"]:
    w = p["whole_grading"]
    sims = " / ".join(f"{c['mean']:.4f}" for c in w["cut_offs"])
    g = w["whole_grading"]
    flag = "" if g["trustworthy"] else ", not trustworthy"
    print(f"| {p['fa_percent']:g} | {sims} | {g['cpm']:.4f} | {g['density']:.4f} ({g['band'][0]:.4f}-{g['band'][1]:.4f}{flag}) |")
finest = max(j["points"], key=lambda p: p["density"]["mean"])
b = j["best"]
print(f"\ndensest at the finest cut: Fa = {finest['fa_percent']:g} % ({finest['density']['mean']:.4f}); "
      f"densest whole grading: Fa = {b['fa_percent']:g} % ({b['whole_grading']['density']:.4f}, band "
      f"{b['whole_grading']['band'][0]:.4f}-{b['whole_grading']['band'][1]:.4f}); not told apart from it: "
      f"Fa = {b['within_one_sd_fa_percent']} %; wall time {j['wall_clock_s']:.0f} s")
PY
