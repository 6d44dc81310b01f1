#!/usr/bin/env bash
# Gravel against crushed stone of the same grading (issue 38, docs/validation.md "Gravel against
# crushed stone"): examples/grains_crushed_stone.toml (700 grains of 1/2 in, flakiness 18 % by
# EN 933-3, mu 0.5, a 4 in box with walls) as angular grains (crushed stone) and as rounded
# ones (gravel), each filled with 6 and with 16 spheres a grain, over several seeds, 64
# templates each (one size: fewer miss 18 % by more than a point for some seeds). Measures:
# the mean of the run's virtual boxes, and the interior density (the vertical profile's
# slices between one d_max above the floor and one below the surface).
# Cost on one core: about 3 minutes a run at 6 spheres, 15-21 at 16. Usage:
#   bash scripts/validate_gravel_crushed.sh [OUT_DIR] [SEEDS] [JOBS]
#   (defaults: out/validate_gravel_crushed, "1 2 3", 1 run at a time; AGGPACK_EXE: another binary)
# Writes OUT_DIR/results.md: one row per run, then per filling the mean over seeds and the
# gap gravel - crushed stone seed by seed. Runs already finished are kept; stopped ones run again.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
out=$(realpath -m "${1:-$repo/out/validate_gravel_crushed}")
exe=$(realpath -m "${AGGPACK_EXE:-$repo/build/aggpack}")  # AGGPACK_EXE: a copy, to rebuild while it runs
seeds=${2:-1 2 3}
jobs=${3:-1}
cd "$repo"
[ -x "$exe" ] || { echo "validate_gravel_crushed.sh: no $exe; build first (bash scripts/build.sh)" >&2; exit 2; }
mkdir -p "$out"
export OMP_NUM_THREADS=1
names=()
# Seed by seed, both families at a time: a study stopped early still has pairs to compare.
for spheres in 6 16; do
  for seed in $seeds; do
    for family in angular rounded; do
      names+=("${family}_${spheres}_seed$seed")
      echo "${family}_${spheres}_seed$seed $seed $family $spheres 64"
    done
  done
done > "$out/runs.txt"
run_one() {  # name seed family spheres templates; a finished run is kept, a stopped one run again
  [ -f "$out/$1/summary.json" ] && ! grep -q '"interrupted": true' "$out/$1/summary.json" && return 0
  "$exe" run examples/grains_crushed_stone.toml --quiet --threads 1 --overwrite --seed "$2" --set 'output.formats=[]' \
    --set "particles.classes=[{ diameter = \"0.5 in\", count = 700, shape = { family = \"$3\", spheres = $4, templates = $5, flakiness_index = 18 } }]" \
    --out "$out/$1"
}
export -f run_one
export exe out
status=0
xargs -P "$jobs" -L 1 bash -c 'run_one "$@"' _ < "$out/runs.txt" || status=$?  # tabulate what finished anyway

python3 - "$out" "${names[@]}" <<'PY'
import json, os, statistics, sys
def finished(out, n):
    path = f"{out}/{n}/summary.json"
    return os.path.exists(path) and not json.load(open(path)).get("interrupted", False)
out, names = sys.argv[1], [n for n in sys.argv[2:] if finished(sys.argv[1], n)]
def measure(name):
    s = json.load(open(f"{out}/{name}/summary.json"))
    bed, v = s["bed"], s["profiles"]["vertical"]
    lo, hi = bed["floor_m"] + bed["d_max_m"], bed["surface_m"] - bed["d_max_m"]
    slices = [f for z, f in zip(v["z_m"], v["solid_fraction"]) if lo <= z <= hi]
    flaky = s["grains"]["components"][0]["bed"]["flakiness_index_percent"] or float("nan")
    interior = sum(slices) / len(slices) if slices else float("nan")
    return s["density"]["mean"], interior, flaky, s["stages"]["dynamics"]["ended_by"], s["wall_clock_s"]["total"]
m = {n: measure(n) for n in names}
lines = ["| run | boxes | interior | flakiness of the bed | ended | wall clock, one core |", "| --- | --- | --- | --- | --- | --- |"]
lines += [f"| {n} | {b:.4f} | {i:.4f} | {f:.1f} % | {e} | {w:.0f} s |" for n, (b, i, f, e, w) in m.items()]
lines += ["", "| spheres a grain | crushed: boxes / interior (mean ± sd) | gravel: boxes / interior | gravel − crushed, boxes, by seed | interior, by seed |",
          "| --- | --- | --- | --- | --- |"]
fmt = lambda xs: f"{statistics.mean(xs):.4f} ± {statistics.stdev(xs):.4f}" if len(xs) > 1 else f"{xs[0]:.4f}"
for spheres in ("6", "16"):
    seeds = [n.split("seed")[1] for n in names if n.startswith(f"angular_{spheres}_") and f"rounded_{spheres}_seed{n.split('seed')[1]}" in m]
    if not seeds:
        continue
    a = [m[f"angular_{spheres}_seed{s}"] for s in seeds]
    r = [m[f"rounded_{spheres}_seed{s}"] for s in seeds]
    gb = [y[0] - x[0] for x, y in zip(a, r)]
    gi = [y[1] - x[1] for x, y in zip(a, r)]
    lines.append(f"| {spheres} | {fmt([x[0] for x in a])} / {fmt([x[1] for x in a])} | {fmt([x[0] for x in r])} / "
                 f"{fmt([x[1] for x in r])} | {', '.join(f'{g:+.3f}' for g in gb)} (mean {statistics.mean(gb):+.3f}) | "
                 f"{', '.join(f'{g:+.3f}' for g in gi)} (mean {statistics.mean(gi):+.3f}) |")
open(f"{out}/results.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
exit $status
