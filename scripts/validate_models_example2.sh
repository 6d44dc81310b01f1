#!/usr/bin/env bash
# Issue 18's Example 2 validation: CPM against aggpack's simulations of the paper's Example 2
# (1 in and 0.5 in spheres, 20 % small by volume; experiment 0.660), one protocol at a time.
# For each protocol, `aggpack calibrate` simulates the monosized 1 in bed and the mix (seeds
# 1-3, one thread); then CPM is evaluated two ways: (a) beta from the simulated monosized bed
# through CPM's own relation, beta = phi_mono (1 + 1/K), with de Larrard's K for the nearest lab
# process (4.1 poured; 4.75 vibrated for the tapped protocol); (b) K and beta both calibrated
# (which gives back the mix's density by construction: shown for the fitted K). Prints one
# Markdown row per protocol. About 15 minutes on 2 cores. Usage:
#   bash scripts/validate_models_example2.sh [OUT_DIR]    (default out/validate_models)
set -euo pipefail
cd "$(dirname "$0")/.."
exe=$PWD/build/aggpack
out=${1:-out/validate_models}
mkdir -p "$out"
export OMP_NUM_THREADS=1
# Example 2 as deposited only: example2.toml without its [dynamics] table.
python3 - "$out/example2_deposited.toml" <<'PY'
import sys
s = open("examples/example2.toml").read()
open(sys.argv[1], "w").write(s[:s.index("[dynamics]")] + s[s.index("[analysis]"):])
PY
one() {  # name scenario core; a calibration already in OUT_DIR is kept (delete OUT_DIR to redo it)
  [ -f "$out/$1.json" ] || taskset -c "$3" "$exe" calibrate "$2" --threads 1 --quiet --out "$out/$1.json"
}
one deposited "$out/example2_deposited.toml" 0 & one settled examples/example2.toml 1 & wait
one poured examples/example2_pour.toml 0 & one tapped examples/example2_tapped.toml 1 & wait
echo "| protocol | simulated: monosized / mix | (a) K (table), beta from monosized | (a) CPM | (a) CPM - simulated | (a) CPM - 0.660 | (b) calibrated K, beta |"
echo "| --- | --- | --- | --- | --- | --- | --- |"
for p in deposited settled poured tapped; do
  k=4.1
  [ "$p" = tapped ] && k=4.75
  scenario=examples/example2.toml
  [ "$p" = tapped ] && scenario=examples/example2_tapped.toml
  python3 - "$out/$p.json" "$p" "$k" "$exe" "$scenario" <<'PY'
import json, subprocess, sys
c = json.load(open(sys.argv[1]))
p, k, exe, scenario = sys.argv[2], float(sys.argv[3]), sys.argv[4], sys.argv[5]
mono, mix = c["monosized"]["mean"], c["mix"]["mean"]
beta = mono * (1 + 1 / k)
out = subprocess.run([exe, "predict", scenario, "--k", str(k), "--beta", repr(beta), "--json"], check=True,
                     capture_output=True, text=True).stdout
cpm = json.loads(out)["simulated"]["cpm"]["density"]
fit = c["cpm"]
kr, br = fit["compaction_index_range"], fit["residual_packing_density_range"]
fmt = lambda v: "?" if v is None else f"{v:.3g}"
print(f"| {p} | {mono:.4f} / {mix:.4f} | {k:g}, {beta:.4f} | {cpm:.4f} | {cpm - mix:+.4f} | {cpm - 0.660:+.4f} | "
      f"{fit['compaction_index']:.2f} ({fmt(kr[0])}-{fmt(kr[1])}), {fit['residual_packing_density']:.3f} "
      f"({fmt(br[0])}-{fmt(br[1])}) |")
PY
done
