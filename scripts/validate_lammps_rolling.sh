#!/usr/bin/env bash
# The spring-dashpot rolling law against LAMMPS's `rolling sds` over many seeds (issue 36). A
# pour is chaotic: aggpack and LAMMPS, handed the same batches of the same gas, make two random
# beds of the same law, so one pour's difference is noise (sd about 0.01) and only the mean over
# seeds says whether the two laws pack alike. Each seed is poured four times: by aggpack and by
# LAMMPS (dynamics.engine = "lammps", one rank), with mu_r = 0.1 and with mu_r = 0 (the sphere
# cross-check's own control). 800 spheres of 1 cm, mu 0.5, k_roll 1000 N/m, gamma_roll 0.1 N s/m,
# two batches, a 9 cm container, one 5 cm virtual cube: the CI test's kRollingPour
# (tests/cli/test_lammps_bridge.cpp). Two runs side by side, one core each. Prints one Markdown
# row per seed, then the mean difference LAMMPS - aggpack with its standard error and 95 %
# interval, with and without rolling resistance. Usage:
#   bash scripts/validate_lammps_rolling.sh [SEEDS] [OUT_DIR]   (default 20, out/validate_lammps_rolling)
set -euo pipefail
cd "$(dirname "$0")/.."
exe=$PWD/build/aggpack
seeds=${1:-20}
out=${2:-out/validate_lammps_rolling}
if ! [[ "$seeds" =~ ^[0-9]+$ ]] || (( seeds < 2 || seeds > 1000 )); then
  echo "validate_lammps_rolling.sh: SEEDS $seeds: expected a whole number from 2 to 1000 (a mean needs two)" >&2
  exit 2
fi
mkdir -p "$out"
export OMP_NUM_THREADS=1
cat > "$out/rolling.toml" <<'TOML'
title = "LAMMPS rolling sds"
seed = 3
[container]
side = 0.09
height = 0.4
[particles]
diameter = 0.01
count = 800
[material]
youngs_modulus = 1e8
wall_youngs_modulus = 1e8
friction_particle = 0.5
friction_wall = 0.5
rolling_friction = 0.1
rolling_model = "spring_dashpot"
rolling_stiffness = 1000
rolling_damping = 0.1
[pour]
batches = 2
[dynamics]
max_time = 1.5
[analysis]
box_sides = [0.05]
TOML
grep -v '^rolling' "$out/rolling.toml" > "$out/rolling_mu0.toml"  # the control: no rolling resistance
one() {  # seed engine mu_r core
  local dir="$out/seed$1_$2_mu$3" scenario="$out/rolling.toml"
  [ "$3" = 0 ] && scenario="$out/rolling_mu0.toml"
  [ -f "$dir/summary.json" ] && return
  taskset -c "$4" "$exe" run "$scenario" --seed "$1" --threads 1 --quiet --no-checkpoint --overwrite \
    --set "dynamics.engine=\"$2\"" --out "$dir"
}
start=$(date +%s)
for seed in $(seq 1 "$seeds"); do
  for mu in 0.1 0; do
    one "$seed" aggpack "$mu" 0 &
    one "$seed" lammps "$mu" 1 &
    wait
  done
done
echo "wall: $(( $(date +%s) - start )) s for $(( 4 * seeds )) runs, two at a time"
python3 - "$out" "$seeds" <<'PY'
import json, math, sys
out, seeds = sys.argv[1], int(sys.argv[2])
def density(seed, engine, mu):
    with open(f"{out}/seed{seed}_{engine}_mu{mu}/summary.json") as f:
        return json.load(f)["density"]["mean"]
print("| seed | mu_r 0.1: aggpack / LAMMPS / difference | mu_r 0: aggpack / LAMMPS / difference |")
print("| --- | --- | --- |")
diffs = {"0.1": [], "0": []}
for seed in range(1, seeds + 1):
    cells = []
    for mu in ("0.1", "0"):
        a, l = density(seed, "aggpack", mu), density(seed, "lammps", mu)
        diffs[mu].append(l - a)
        cells.append(f"{a:.4f} / {l:.4f} / {l - a:+.4f}")
    print(f"| {seed} | {cells[0]} | {cells[1]} |")
# Student's t at 97.5 % for n - 1 degrees of freedom (n >= 2), from a short table.
T = {1: 12.71, 2: 4.30, 3: 3.18, 4: 2.78, 5: 2.57, 6: 2.45, 7: 2.36, 8: 2.31, 9: 2.26, 10: 2.23, 15: 2.13, 19: 2.09,
     20: 2.09, 29: 2.05, 30: 2.04}
def t975(dof):
    return T.get(dof) or T[max(k for k in T if k <= dof)]
print()
for mu, label in (("0.1", "mu_r 0.1"), ("0", "mu_r 0 (control)")):
    d = diffs[mu]
    n = len(d)
    mean = sum(d) / n
    sd = math.sqrt(sum((x - mean) ** 2 for x in d) / (n - 1)) if n > 1 else float("nan")
    se = sd / math.sqrt(n)
    half = t975(n - 1) * se if n > 1 else float("nan")
    print(f"{label}: LAMMPS - aggpack over {n} seeds: mean {mean:+.4f}, sd {sd:.4f}, standard error {se:.4f}, "
          f"95 % interval {mean - half:+.4f} to {mean + half:+.4f}")
PY
