#!/usr/bin/env bash
# Issue 17's pour and tap decks against aggpack's own pour and tapping: the paper's Example 1
# poured and Example 2 poured and tapped, seeds 1-3, each run twice, once with aggpack's DEM and
# once with dynamics.engine = "lammps" (every pour and tap step handed to LAMMPS on one rank:
# aggpack's own gas in the same batches, the container moved as aggpack moves it). Prints one
# Markdown row per bed: the poured density, the density after the taps, the wall times. Two
# beds run side by side (one core each). Usage:
#   bash scripts/validate_lammps_pour_tap.sh [OUT_DIR]    (default out/validate_lammps_pour_tap)
set -euo pipefail
cd "$(dirname "$0")/.."
exe=$PWD/build/aggpack
out=${1:-out/validate_lammps_pour_tap}
mkdir -p "$out"
export OMP_NUM_THREADS=1
one() {  # example seed engine core
  taskset -c "$4" "$exe" run "examples/$1.toml" --seed "$2" --threads 1 --quiet --no-checkpoint \
    --set "dynamics.engine=\"$3\"" --out "$out/$1_seed$2_$3"
}
for example in example1_pour example2_tapped; do
  for seed in 1 2 3; do
    one "$example" "$seed" aggpack 0 &
    one "$example" "$seed" lammps 1 &
    wait
  done
done
echo "| example | seed | poured: aggpack / LAMMPS / difference | after the taps: aggpack / LAMMPS / difference | wall s aggpack / LAMMPS |"
echo "| --- | --- | --- | --- | --- |"
for example in example1_pour example2_tapped; do
  for seed in 1 2 3; do
    python3 - "$out/${example}_seed${seed}_aggpack/summary.json" "$out/${example}_seed${seed}_lammps/summary.json" \
      "$example" "$seed" <<'PY'
import json, sys
a, l = (json.load(open(f)) for f in sys.argv[1:3])
def poured(s):
    t = s["stages"].get("tapping")
    return t["density_before"] if t else s["density"]["mean"]
def tapped(s):
    t = s["stages"].get("tapping")
    return t["density_after_each_tap"][-1] if t else None
def wall(s):
    return sum(v for k, v in s["wall_clock_s"].items() if k in ("dynamics", "tapping", "pour"))
pa, pl = poured(a), poured(l)
ta, tl = tapped(a), tapped(l)
taps = f"{ta:.4f} / {tl:.4f} / {tl - ta:+.4f}" if ta is not None else "-"
print(f"| {sys.argv[3]} | {sys.argv[4]} | {pa:.4f} / {pl:.4f} / {pl - pa:+.4f} | {taps} | {wall(a):.0f} / {wall(l):.0f} |")
PY
  done
done
