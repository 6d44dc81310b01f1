#!/usr/bin/env python3
"""Table 2 predicted from one calibration mix (issue 36, docs/validation.md).

Every Table 2 mix (examples/fu2003_table2.csv: Ca/Fa and the measured density) is poured by the
DEM from examples/table2_mix3_stone_sand.toml (stone and sand, each its own material with the
literature's values of docs/validation.md; the mixes share its gradings but for Ca/Fa) at a grid
of the sand's rolling friction mu_r (the stone's kept at its literature value, 0.2), over seeds; each bed is carried to its whole grading by CPM (below). Then, for every choice
of the calibration mix c, mu_r is fitted to c's measured density alone (the crossing of c's seed
mean with the measurement, by linear interpolation on the grid, as `aggpack calibrate --dem`
interpolates its last bracket; band: the measurement -+ the larger standard error of the two
grid values around it), and the other seven mixes are predicted at that mu_r. Prints the
tables and writes OUT/table2_calibrated.json.

The bed is reduced so that the study fits in about an hour on two cores (stated in every
output): sand and stone cut at 0.1 in, a 4 in container filled to 4 in, cubes of 1.4-1.6 in.
The carry to the whole grading is CPM's own: carried = simulated + (CPM of the whole grading -
CPM of the simulated distribution), i.e. the whole-grading fit of `aggpack whole-grading` with
one cut-off and the residual's slope taken as zero.

Runs are resumable: a run whose summary.json exists is not run again.

Usage: scripts/validate_table2_calibrated.py OUT [--values 0,0.1,0.2,0.35] [--seeds 2]
       [--workers 2] [--fit sand|shared] [--set KEY=VALUE ...]
"""
import argparse
import concurrent.futures
import csv
import json
import math
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENARIO = os.path.join(ROOT, "examples", "table2_mix3_stone_sand.toml")
REDUCED = [
    'particles.fine.d_min="0.1 in"',
    'container.side="4 in"',
    'container.height="10 in"',
    'particles.fill_height="4 in"',
    'analysis.box_sides=["1.4 in", "1.5 in", "1.6 in"]',
    "output.formats=[]",
]


def table2():
    with open(os.path.join(ROOT, "examples", "fu2003_table2.csv")) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return sorted(rows, key=lambda r: float(r["fa_percent"]))


def run_one(exe, out, mix, value, seed, extra_sets, core, fitted):
    folder = os.path.join(out, "runs", f"mix{mix['mix_id']}_mu{value:g}_seed{seed}")
    summary = os.path.join(folder, "summary.json")
    if not os.path.exists(summary):
        sets = REDUCED + [f"particles.ca_fa={mix['ca_fa']}"] + [f"materials.{m}.rolling_friction={value}"
                                                               for m in fitted] + extra_sets
        command = ["taskset", "-c", str(core), exe, "run", SCENARIO, "--seed", str(seed), "--threads", "1",
                   "--quiet", "--no-checkpoint", "--overwrite", "--out", folder]
        for s in sets:
            command += ["--set", s]
        start = time.time()
        subprocess.run(command, check=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
        with open(os.path.join(folder, "wall_seconds"), "w") as f:
            f.write(f"{time.time() - start:.1f}\n")
    with open(summary) as f:
        s = json.load(f)
    simulated = s["density"]["mean"]
    cpm_simulated = s["predictions"]["simulated"]["cpm"]["density"]
    cpm_whole = s["predictions"]["whole_grading"]["cpm"]["density"]
    return {"mix": mix["mix_id"], "value": value, "seed": seed, "particles": s["particle_count"],
            "simulated": simulated, "carried": simulated + cpm_whole - cpm_simulated,
            "cpm_increment": cpm_whole - cpm_simulated, "settled": s.get("settled", True)}


def mean_se(xs):
    m = sum(xs) / len(xs)
    if len(xs) < 2:
        return m, 0.0
    sd = math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1))
    return m, sd / math.sqrt(len(xs))


def crossing(values, means, target):
    """Where the piecewise-linear curve (values, means), decreasing, meets target; None beyond it."""
    for k in range(len(values) - 1):
        a, b = means[k], means[k + 1]
        if (a - target) * (b - target) <= 0 and a != b:
            return values[k] + (target - a) * (values[k + 1] - values[k]) / (b - a), k
    return None, None


def at(values, means, x):
    for k in range(len(values) - 1):
        if values[k] <= x <= values[k + 1]:
            t = (x - values[k]) / (values[k + 1] - values[k])
            return means[k] + t * (means[k + 1] - means[k])
    raise ValueError(x)


def slope_per_10(fa, phi):
    n = len(fa)
    mf, mp = sum(fa) / n, sum(phi) / n
    return 10 * sum((f - mf) * (p - mp) for f, p in zip(fa, phi)) / sum((f - mf) ** 2 for f in fa)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("out")
    p.add_argument("--values", default="0,0.1,0.2,0.35")
    p.add_argument("--seeds", type=int, default=2)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--set", action="append", default=[])
    p.add_argument("--fit", choices=["sand", "shared"], default="sand",
                   help="the sand's mu_r (the stone's kept at 0.2), or one mu_r for stone and sand")
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "aggpack"))
    a = p.parse_args()
    values = [float(v) for v in a.values.split(",")]
    mixes = table2()
    jobs = [(m, v, s) for v in values for m in mixes for s in range(1, a.seeds + 1)]
    start = time.time()
    results = []
    with concurrent.futures.ThreadPoolExecutor(a.workers) as pool:
        futures = []
        for k, (m, v, s) in enumerate(jobs):
            fitted = ["sand"] if a.fit == "sand" else ["sand", "stone"]
            futures.append(pool.submit(run_one, a.exe, a.out, m, v, s, a.set, k % a.workers, fitted))
        for f in futures:
            results.append(f.result())
            r = results[-1]
            print(f"  mix {r['mix']} mu_r {r['value']:g} seed {r['seed']}: {r['simulated']:.4f} at the cut, "
                  f"{r['carried']:.4f} carried", file=sys.stderr, flush=True)
    wall = time.time() - start

    curve = {}
    for m in mixes:
        rows = []
        for v in values:
            carried = [r["carried"] for r in results if r["mix"] == m["mix_id"] and r["value"] == v]
            simulated = [r["simulated"] for r in results if r["mix"] == m["mix_id"] and r["value"] == v]
            rows.append((v, *mean_se(carried), mean_se(simulated)[0]))
        curve[m["mix_id"]] = rows

    print(f"Reduced bed: {'; '.join(REDUCED)}; {a.seeds} seeds; {'the sand' + chr(39) + 's mu_r fitted, the stone' + chr(39) + 's 0.2' if a.fit == 'sand' else 'one mu_r for stone and sand'}; "
          f"wall {wall / 60:.1f} min for {len(jobs)} runs ({a.workers} at a time)\n")
    print("| mix | Fa % | measured | " + " | ".join(f"mu_r {v:g}: at the cut / carried" for v in values) + " |")
    print("| --- | --- | --- | " + " | ".join("---" for _ in values) + " |")
    for m in mixes:
        cells = [f"{sim:.4f} / {c:.4f} ± {se:.4f}" for (_, c, se, sim) in curve[m["mix_id"]]]
        print(f"| {m['mix_id']} | {m['fa_percent']} | {m['phi_exp']} | " + " | ".join(cells) + " |")

    lab_fa = [float(m["fa_percent"]) for m in mixes]
    lab_phi = [float(m["phi_exp"]) for m in mixes]
    print(f"\nLab slope over the eight mixes: {slope_per_10(lab_fa, lab_phi):+.4f} per 10 points of Fa\n")
    print("| calibration mix | Fa % | fitted mu_r (band) | MAE over the other seven | largest error | "
          "slope of the predictions, per 10 points (lab, same seven) |")
    print("| --- | --- | --- | --- | --- | --- |")
    choices = []
    for c in mixes:
        rows = curve[c["mix_id"]]
        vs = [r[0] for r in rows]
        means = [r[1] for r in rows]
        target = float(c["phi_exp"])
        fitted, k = crossing(vs, means, target)
        if fitted is None:
            print(f"| {c['mix_id']} | {c['fa_percent']} | out of reach: carried {means[0]:.4f} at mu_r {vs[0]:g} to "
                  f"{means[-1]:.4f} at {vs[-1]:g}, measured {target} | — | — | — |")
            choices.append({"mix": c["mix_id"], "fitted": None})
            continue
        noise = max(rows[k][2], rows[k + 1][2])
        slope = (means[k + 1] - means[k]) / (vs[k + 1] - vs[k])
        band = sorted([fitted - noise / slope, fitted + noise / slope])
        others = [m for m in mixes if m is not c]
        predicted = [at(vs, [r[1] for r in curve[m["mix_id"]]], fitted) for m in others]
        errors = [pr - float(m["phi_exp"]) for pr, m in zip(predicted, others)]
        mae = sum(abs(e) for e in errors) / len(errors)
        fa = [float(m["fa_percent"]) for m in others]
        s_pred = slope_per_10(fa, predicted)
        s_lab = slope_per_10(fa, [float(m["phi_exp"]) for m in others])
        choices.append({"mix": c["mix_id"], "fa_percent": float(c["fa_percent"]), "fitted": fitted, "band": band,
                        "mae": mae, "largest_error": max(errors, key=abs), "slope_per_10": s_pred,
                        "lab_slope_per_10": s_lab,
                        "predicted": {m["mix_id"]: pr for m, pr in zip(others, predicted)}})
        print(f"| {c['mix_id']} | {c['fa_percent']} | {fitted:.3f} ({band[0]:.3f}-{band[1]:.3f}) | {mae:.4f} | "
              f"{max(errors, key=abs):+.4f} | {s_pred:+.4f} ({s_lab:+.4f}) |")
    fitted = sorted((ch for ch in choices if ch["fitted"] is not None), key=lambda ch: ch["mae"])
    if fitted:
        median = fitted[(len(fitted) - 1) // 2]
        print(f"\nMedian choice (by MAE): mix {median['mix']}: MAE {median['mae']:.4f} (target <= 0.015), slope "
              f"{median['slope_per_10']:+.4f} per 10 points (target within 0.005 of -0.020)")
    with open(os.path.join(a.out, "table2_calibrated.json"), "w") as f:
        json.dump({"reduced_bed": REDUCED, "fit": a.fit, "extra_sets": a.set, "values": values, "seeds": a.seeds,
                   "wall_seconds": wall, "runs": results, "choices": choices,
                   "carry": "simulated + CPM(whole grading) - CPM(simulated distribution)"}, f, indent=1)


if __name__ == "__main__":
    main()
