#!/usr/bin/env python3
"""Example 2 of Fu and Dekelbab (2003), run from Python: its density profile and its sizes.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/example2_profile.py --out out/py_example2

Runs examples/example2.toml (2000 spheres of 0.5 in and 1000 of 1 in, deposited and settled by
DEM), then plots with matplotlib the solid fraction against height (the final analysis's
vertical profile, the virtual boxes' span shaded) and the spheres' diameters, and writes the
figure and the run's files into --out. --quick stops after the deposition (seconds).
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")  # files, no window
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import aggpack  # noqa: E402

EXAMPLES = pathlib.Path(__file__).resolve().parents[1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("out/py_example2"))
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--quick", action="store_true", help="stop after the deposition")
    args = parser.parse_args()

    scenario = aggpack.Scenario.from_file(EXAMPLES / "example2.toml", seed=args.seed)
    report = aggpack.run(scenario, threads=args.threads, stop_after="deposition" if args.quick else None)
    aggpack.write_outputs(report, args.out, overwrite=True)

    profile = report.analysis["profiles"]["vertical"]
    z_mm = 1000 * np.asarray(profile["z_m"])
    boxes = report.analysis["density"]["boxes"]
    diameters_in = 2 * report.bed.radii / 0.0254

    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4.5))
    left.plot(profile["solid_fraction"], z_mm, lw=1)
    lo = 1000 * min(b["lo"][2] for b in boxes)
    hi = 1000 * max(b["hi"][2] for b in boxes)
    left.axhspan(lo, hi, color="0.9", label=f"virtual boxes: mean {report.density:.4f}")
    left.set_xlabel("solid fraction")
    left.set_ylabel("height, mm")
    left.set_title("vertical profile")
    left.legend(loc="upper right")
    right.hist(diameters_in, bins=40)
    right.set_xlabel("diameter, in")
    right.set_ylabel("spheres")
    right.set_title(f"{len(report.bed)} spheres")
    fig.suptitle(scenario.title)
    fig.tight_layout()
    figure = args.out / "example2_profile.png"
    fig.savefig(figure, dpi=120)
    print(f"density {report.density:.4f}; {figure} and the run's files in {args.out}")


if __name__ == "__main__":
    main()
