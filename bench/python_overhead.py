#!/usr/bin/env python3
"""What calling aggpack through Python costs (issue 39's speed targets), in one run.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py build/aggpack [--rounds 5] [--spheres 1000000]

1. Example 1 (deposition and DEM settling), --threads 1, run in turns by the CLI (`aggpack run
   --out`, a process) and from Python (`aggpack.run(scenario, out=...)` in this process): each
   round's wall clock, the medians and their ratio. Both write the same files.
2. The arrays of a bed of --spheres spheres (made with Bed.from_arrays, a copy, untimed): the
   time to get its positions, velocities and radii as numpy views, the best of 1000 tries.
"""
import argparse
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import aggpack

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("aggpack_exe")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--spheres", type=int, default=1_000_000)
    args = parser.parse_args()

    scenario_file = EXAMPLES / "example1.toml"
    scenario = aggpack.Scenario.from_file(scenario_file)
    cli_times, python_times = [], []
    with tempfile.TemporaryDirectory() as scratch:
        for k in range(args.rounds):
            t0 = time.perf_counter()
            subprocess.run([args.aggpack_exe, "run", scenario_file, "--quiet", "--threads", "1", "--out",
                            f"{scratch}/cli_{k}"], check=True)
            cli_times.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            aggpack.run(scenario, out=f"{scratch}/python_{k}", threads=1)
            python_times.append(time.perf_counter() - t0)
            same = pathlib.Path(f"{scratch}/cli_{k}/particles.csv").read_bytes() == pathlib.Path(
                f"{scratch}/python_{k}/particles.csv").read_bytes()
            print(f"round {k + 1}: CLI {cli_times[-1]:.3f} s, Python {python_times[-1]:.3f} s, same particles.csv: {same}")
    cli, py = statistics.median(cli_times), statistics.median(python_times)
    print(f"Example 1, medians of {args.rounds}: CLI {cli:.3f} s, Python {py:.3f} s, Python / CLI {py / cli:.4f}")

    rng = np.random.default_rng(1)
    bed = aggpack.Bed.from_arrays(rng.uniform(0, 1, (args.spheres, 3)), rng.uniform(0.001, 0.002, args.spheres))
    best = float("inf")
    for _ in range(1000):
        t0 = time.perf_counter()
        views = (bed.positions, bed.velocities, bed.radii)
        best = min(best, time.perf_counter() - t0)
    assert views[0].shape == (args.spheres, 3) and not views[0].flags.owndata
    print(f"the positions, velocities and radii of {args.spheres} spheres as views: {best * 1e6:.1f} us (best of 1000)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
